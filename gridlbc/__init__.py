"""gridlbc: linearly solvable stochastic optimal control on grids, and linear Bellman combination.

The desirability z = exp(−v/λ) of a control-affine problem with noise in the control channels
solves a linear PDE (paper §3.2); solved on a grid, it gives the optimal value and policy anywhere,
and solutions for different terminal costs superpose into new optimal controllers.
"""

from . import costs, reference, regions, systems, trajectory
from .certificate import Certificate
from .certify import certify
from .combine import Combination, CombinedSolution, NaiveBlend, combine, naive_blend
from .costs import Quadratic
from .errors import (
    CertificateWarning,
    ConvergenceError,
    GridlbcWarning,
    ProjectionWarning,
    ResolutionWarning,
    UnderflowWarning,
)
from .grid import Axis, Grid
from .io import load, save
from .problem import Problem
from .project import Projection, project, projection
from .schemes import METHODS
from .settings import PRESETS, SolverSettings
from .simulate import Rollouts, simulate
from .solution import Solution, SolveDiagnostics, StationarySolution
from .solver import solve, solve_many
from .sweep import SweepMember, sweep  # imports Dask only when a sweep runs
from .version import __version__ as __version__

__all__ = [
    "METHODS",
    "PRESETS",
    "Axis",
    "Certificate",
    "CertificateWarning",
    "Combination",
    "CombinedSolution",
    "ConvergenceError",
    "Grid",
    "GridlbcWarning",
    "NaiveBlend",
    "Problem",
    "Projection",
    "ProjectionWarning",
    "Quadratic",
    "ResolutionWarning",
    "Rollouts",
    "Solution",
    "SolveDiagnostics",
    "SolverSettings",
    "StationarySolution",
    "SweepMember",
    "UnderflowWarning",
    "certify",
    "combine",
    "costs",
    "load",
    "naive_blend",
    "project",
    "projection",
    "reference",
    "regions",
    "save",
    "simulate",
    "solve",
    "solve_many",
    "sweep",
    "systems",
    "trajectory",
]
