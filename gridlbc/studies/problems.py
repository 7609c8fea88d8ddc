"""Named problems shared by the studies, the benchmarks and the tests.

The diver (paper §6.1–6.2, Figs. 6 and 8), beyond the grid: a free-flying 4-link
:class:`gridlbc.systems.PlanarChain` of uniform rods, 8-D state (θ1 … θ4, p1 … p4). Link 1 is the
arms (from the hands to the shoulders), then the trunk with the head, the thighs and the shanks;
the torques act at the shoulder, hip and knee. Masses are fractions of the body mass (total 1)
and lengths in metres, roughly human proportions. No joint limits are modelled.

The dive lasts T = 1 s (about a 3 m springboard). It takes off standing straight with the arms
overhead, θ = (π, 0, 0, 0) (the hands at the top: every link points down), turning rigidly at
ω0 = κ · 2 rad/s counterclockwise; κ scales the take-off angular momentum p1 = I ω0, which
nothing in the air can change. A vertical head-first entry is θ = (0, 0, 0, 0) (the hands at the
bottom, the body straight): half a somersault, π rad, more than the straight body's ω0 T = 2 rad,
so the diver must pike to turn faster and open again to enter. The entry cost is

    g(x) = W1 (θ1 − c)² + W_shape (θ2² + θ3² + θ4²),      wrap-aware in the angles,

c = 0 for a vertical entry, c < 0 short of vertical (under-rotated), c > 0 past it.
"""

from __future__ import annotations

import numpy as np

from ..costs import Quadratic
from ..problem import Problem
from ..systems import PlanarChain

DIVER_MASSES = (0.1, 0.58, 0.2, 0.12)
"""Arms, trunk and head, thighs, shanks (fractions of the body mass)."""

DIVER_LENGTHS = (0.6, 0.8, 0.45, 0.5)
"""Hands–shoulders, shoulders–hips, hips–knees, knees–feet (m)."""

DIVER_HORIZON = 1.0
"""Flight time T (s)."""

DIVER_SPIN = 2.0
"""Nominal take-off angular velocity ω0 of the straight body (rad/s, counterclockwise)."""

DIVER_ENTRY_WEIGHTS = (10.0, 2.0)
"""W1 on the arms' angle from vertical, W_shape on each joint angle (per rad²)."""

DIVER_CONTROL_COST = 50.0
"""R per joint torque: a dive's torques of a few tenths of N·m (body mass 1) cost about as much as
its entry error."""

DIVER_TEMPERATURE = 1.0
"""λ: the paper's exp(−v) (λ = 1), which makes exp(−g/λ) wide enough (±0.3 rad) to interpolate
entries 0.6 rad apart."""


def diver() -> PlanarChain:
    """The 4-link free-flying diver."""
    return PlanarChain(4, masses=DIVER_MASSES, lengths=DIVER_LENGTHS, pinned=False)


def diver_start(momentum_scale: float = 1.0) -> np.ndarray:
    """Take-off state ``(8,)``: straight, arms overhead, turning rigidly at κ ω0 (κ =
    ``momentum_scale``, so p1 is κ times nominal)."""
    return diver().from_velocities([np.pi, 0.0, 0.0, 0.0, momentum_scale * DIVER_SPIN, 0, 0, 0])[0]


def diver_entry_cost(entry_angle: float = 0.0) -> Quadratic:
    """g of the entry: the arms at ``entry_angle`` rad from vertical (negative: short of it), the
    body straight; no cost on the momenta."""
    w1, shape = DIVER_ENTRY_WEIGHTS
    return Quadratic([entry_angle, 0, 0, 0, 0, 0, 0, 0], [w1, shape, shape, shape, 0, 0, 0, 0])


def diver_problem(entry_angle: float = 0.0, temperature: float = DIVER_TEMPERATURE,
                  control_cost: float = DIVER_CONTROL_COST) -> Problem:
    """The grid-free diving problem: T = 1 s, the entry cost :func:`diver_entry_cost`, q = 0."""
    return Problem(diver(), None, DIVER_HORIZON, diver_entry_cost(entry_angle),
                   control_cost=control_cost, temperature=temperature)
