"""Trajectory-based components for linear Bellman combination (paper §5, "High-Dimensional
Systems").

Where no grid fits the state space, each component is a locally optimal trajectory of the
deterministic problem with its quadratic value expansion and LQR tracker:

    trajectory = optimize(problem, x0)          # multi-start shooting, polished by iLQR
    component = expand(problem, trajectory)     # v̂ = v̄ + pᵀΔx + ½ΔxᵀPΔx, u = ū + KΔx (saturated)

Components combine with :func:`gridlbc.combine` (α_i ∝ w_i exp(−v̂_i/λ)), alone or with grid
solutions of the same problem.
"""

from ..errors import TrajectoryWarning
from .expansion import TrajectoryExpansion, expand
from .optimize import Trajectory, optimize, tape_cost

__all__ = [
    "Trajectory",
    "TrajectoryExpansion",
    "TrajectoryWarning",
    "expand",
    "optimize",
    "tape_cost",
]
