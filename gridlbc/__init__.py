"""gridlbc: linearly solvable stochastic optimal control on grids, and linear Bellman combination.

The desirability z = exp(−v/λ) of a control-affine problem with noise in the control channels
solves a linear PDE (SPEC §1); solved on a grid, it gives the optimal value and policy anywhere,
and solutions for different terminal costs superpose into new optimal controllers.
"""

from . import costs, systems
from .combine import CombinedSolution, NaiveBlend, combine, naive_blend
from .costs import Quadratic
from .grid import Axis, Grid
from .io import load, save
from .problem import Problem
from .project import Projection, ProjectionWarning, project, projection
from .solution import Solution, SolveDiagnostics, UnderflowWarning
from .simulate import Rollouts, simulate
from .solver import METHODS, PRESETS, SolverSettings, solve, solve_many

__version__ = "0.1.0"

__all__ = [
    "Axis", "Grid", "save", "load", "Problem", "Quadratic", "Solution", "SolveDiagnostics", "SolverSettings",
    "UnderflowWarning", "METHODS", "PRESETS", "costs", "solve", "solve_many", "systems",
    "CombinedSolution", "NaiveBlend", "combine", "naive_blend",
    "Projection", "ProjectionWarning", "project", "projection", "Rollouts", "simulate",
]
