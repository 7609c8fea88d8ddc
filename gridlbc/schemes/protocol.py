"""What the solver asks of a scheme, written out: :class:`Scheme` and the records it exchanges.

:func:`gridlbc.solve_many` owns the time grid, the memory check, the terminal data and the
packaging of :class:`~gridlbc.Solution` objects; everything that depends on the discretisation is
behind a :class:`Scheme`, looked up by name in :data:`gridlbc.schemes.METHODS`. In the order the
solver calls them:

1. ``scheme.estimate_bytes(grid)``: the operator's memory, for the check before any work
   (:func:`gridlbc.settings.memory_estimate`);
2. ``scheme.step_bound(problem)``: a :class:`StepBound`, the largest step the scheme can take on
   this problem (the default step is held below it; a given one above it is warned about by
   ``bound.check(dt)``);
3. ``scheme.step_rule(settings)``: the default step's :class:`StepRule` (a Courant number against
   the drift's largest or root-mean-square rate, and the fewest steps), then
   ``scheme.estimate_bytes(grid)`` again with the number of slices known;
4. ``scheme.march(plan, terminal)``: the time loop, from the :class:`Terminal` data over the
   :class:`MarchPlan`'s steps into storage it allocates through the plan; returns a
   :class:`Marched`;
5. ``scheme.check(solutions, marched)``: the scheme's own warnings about the solutions it made
   (:class:`~gridlbc.solution.ResolutionWarning`).

``scheme.supports_fitting`` says whether ``fitting=`` applies (:class:`gridlbc.SolverSettings`
resolves ``"auto"`` with it); ``scheme.supports_linear_solver`` whether ``linear_solver=``
does; ``scheme.supports_exit`` whether it solves problems with an exit set
(SPEC §9: z held at exp(−g_E/λ) on E). Inside, a scheme builds a :class:`StepOperator` and steps it; the
solver never sees the operator except through :attr:`Marched.operator` (its memory and iteration
counts go to the diagnostics).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, NamedTuple, Protocol, runtime_checkable

import numpy as np

from ..grid import Grid
from ..problem import Problem
from ..progress import ProgressBar
from ..representation import Representation
from ..storage import slice_storage


@runtime_checkable
class StepOperator(Protocol):
    """One backward step of the linear Bellman PDE on a fixed grid and time step.

    Built once per solve; then for K right-hand sides at once,

        peak = step(z, out, scale)      out[r] = S (scale[r] · z[r]),  r < K

    with ``z`` and ``out`` float64 arrays of shape (K, N) (``z`` may be overwritten) and
    ``peak[r] = max out[r]`` (the march renormalises with it).
    """

    iterations: list[int]
    """Per-step iteration counts of an iterative linear solver (empty for direct schemes)."""

    @property
    def nbytes(self) -> int:
        """Memory held by the operator."""

    @staticmethod
    def estimate_bytes(grid: Grid) -> int:
        """Memory the operator will hold on ``grid``, without building it."""

    def __call__(self, z: np.ndarray, out: np.ndarray, scale: np.ndarray) -> np.ndarray: ...


class StepRule(NamedTuple):
    """A scheme's default time step: the fewest steps n with ``courant`` ≥ T·r/n, r the drift's
    Courant rate (:func:`gridlbc.solver.courant_rates`) taken as its largest value over the nodes
    (``rate="peak"``) or its root mean square (``rate="rms"``), and at least ``min_steps``."""

    courant: float
    rate: str
    min_steps: int


@dataclass(frozen=True)
class StepBound:
    """The largest step a scheme can take on a problem (``limit``, ∞ for none) and what sets it
    (``reason``). The default step is held at or below ``limit``; :meth:`check` hears of a given
    step (``dt=``) above it, and a scheme whose bound matters warns there."""

    limit: float = math.inf
    reason: str = ""

    def check(self, dt: float) -> None:
        """Called with every step the solver takes; this bound has nothing to say."""


@dataclass(frozen=True)
class Terminal:
    """The terminal data of a solve, prepared by the solver.

    ``values`` ``(rows, N)``: the scaled desirabilities Z = z_T e^{−ℓ} (max 1 per row) with their
    log-scales ``log_scale`` ``(rows,)``; when ``log`` (a single terminal cost fitted to itself),
    log Z instead, so that a scheme can march it in the log domain (``np.exp`` gives Z). The first
    ``count`` rows are the solutions'; ``reference`` is the row of the fitting reference φ (None:
    the plain operator; it may be one of the solutions' rows or one row more), and
    ``fingerprint`` the digest of φ that fixes the operator (``"none"`` without one)."""

    values: np.ndarray
    log_scale: np.ndarray
    count: int
    reference: int | None
    log: bool
    fingerprint: str


@dataclass
class MarchPlan:
    """What the solver hands to :meth:`Scheme.march`: the problem, the time grid (``dt``,
    ``steps`` = n, the ``kept`` step indices whose slices are stored, 0 and n among them), how
    to store (``dtype``, ``mmap_dir``), whether to show progress and when the solve ``started``
    (:func:`time.perf_counter`), plus the options the scheme reads (``options``: the settings'
    fields, e.g. ``linear_solver``)."""

    problem: Problem
    dt: float
    steps: int
    kept: list[int]
    dtype: str = "float64"
    mmap_dir: str | None = None
    progress: bool | None = False
    started: float = field(default_factory=time.perf_counter)
    options: dict[str, Any] = field(default_factory=dict)

    def storage(self, *shape: int) -> np.ndarray:
        """Uninitialised slice storage of this shape (:func:`gridlbc.storage.slice_storage`)."""
        return slice_storage(shape, np.dtype(self.dtype), self.mmap_dir)

    def progress_bar(self, label: str) -> ProgressBar:
        """A progress bar over the steps, ``label`` and the grid in front."""
        grid = self.problem.require_grid("a march")
        return ProgressBar.chosen(
            self.steps, self.progress, f"{label} {grid.describe()}", work_per_item=grid.size
        )

    def elapsed(self) -> float:
        """Seconds since the solve started."""
        return time.perf_counter() - self.started


@dataclass
class Marched:
    """What :meth:`Scheme.march` returns: per solution r the stored ``slices[r]``
    ``(len(kept), N)`` and their log-scales ``scales[:, r]``, in the ``representation`` the
    solutions share (:mod:`gridlbc.representation`: :class:`~gridlbc.representation.LinearZ`,
    :class:`~gridlbc.representation.RelativeZ` with the log φ of the fitting reference at the
    stored times, or :class:`~gridlbc.representation.LogZ`); the nodes whose z underflowed at t = 0 (``underflow_nodes``, one per solution), values the
    float32 storage ``flushed`` to zero, the ``operator`` that was stepped and the
    ``setup_time`` it took to build (from the solve's start)."""

    slices: np.ndarray
    scales: np.ndarray
    representation: Representation
    operator: Any  # the StepOperator, with whatever else its scheme's check reads
    setup_time: float
    underflow_nodes: tuple[int, ...]
    flushed: int = 0


@runtime_checkable
class Scheme(Protocol):
    """A discretisation of the linear Bellman PDE as the solver uses it (the module docstring
    lists the calls in order)."""

    name: str
    supports_fitting: bool
    supports_exit: bool
    supports_linear_solver: bool

    def estimate_bytes(self, grid: Grid) -> int:
        """Memory of the operator on ``grid``, without building it."""

    def step_rule(self, settings) -> StepRule:
        """The default step's rule for these :class:`gridlbc.SolverSettings`."""

    def step_bound(self, problem: Problem) -> StepBound:
        """The largest step this scheme can take on ``problem``."""

    def march(self, plan: MarchPlan, terminal: Terminal) -> Marched:
        """Step backward from the terminal data to t = 0, storing the kept slices."""

    def check(self, solutions: list, marched: Marched) -> None:
        """Warn about what the grid and step do not resolve in ``solutions``."""


class SchemeBase:
    """Defaults for a :class:`Scheme`: the operator's memory from its class ``step`` (a
    :class:`StepOperator`), and no bound on the step."""

    name: str
    supports_fitting: bool = False
    supports_exit: bool = False
    supports_linear_solver: bool = False
    step: type[StepOperator]

    def estimate_bytes(self, grid: Grid) -> int:
        """Memory of the operator on ``grid`` (``step.estimate_bytes``)."""
        return self.step.estimate_bytes(grid)

    def step_bound(self, problem: Problem) -> StepBound:
        """No bound: the scheme is stable and accurate enough at any step its rule picks."""
        return StepBound()
