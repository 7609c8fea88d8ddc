"""Control-affine systems: the built-ins (paper §6) and the base class for your own."""

from .base import ControlAffineSystem, LinearSystem
from .chain import PlanarChain
from .mechanical import Acrobot, Pendulum, PointMass, SingleIntegrator

__all__ = [
    "Acrobot",
    "ControlAffineSystem",
    "LinearSystem",
    "Pendulum",
    "PlanarChain",
    "PointMass",
    "SingleIntegrator",
]
