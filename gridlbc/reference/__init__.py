"""Independent references for checking the grid solver: the Riccati solution of linear-quadratic
problems and of their Euler–Maruyama chains (:mod:`gridlbc.reference.lq`) and a value-space HJB solver for any problem
(:mod:`gridlbc.reference.hjb`). Neither shares code with the linear desirability scheme."""

from .hjb import HJBDiagnostics, HJBSolution, solve_hjb
from .lq import LQSolution, euler_chain_value, lq_solution

__all__ = [
    "HJBDiagnostics",
    "HJBSolution",
    "LQSolution",
    "euler_chain_value",
    "lq_solution",
    "solve_hjb",
]
