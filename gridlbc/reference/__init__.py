"""Independent references for checking the grid solver: the Riccati solution of linear-quadratic
problems (:mod:`gridlbc.reference.lq`) and a value-space HJB solver for any problem
(:mod:`gridlbc.reference.hjb`). Neither shares code with the linear desirability scheme."""

from .hjb import HJBDiagnostics, HJBSolution, solve_hjb
from .lq import LQSolution, lq_solution

__all__ = ["HJBDiagnostics", "HJBSolution", "LQSolution", "lq_solution", "solve_hjb"]
