"""A linearly solvable finite-horizon control problem on a grid (paper §3.2).

    dx = (a(x) + B(x) u) dt + dξ,      Cov[dξ] = λ B R⁻¹ Bᵀ dt
    J  = E[ g(x_T) + ∫₀ᵀ ( q(x) + ½ uᵀ R u ) dt ]

The desirability z = exp(−v/λ) then solves the linear backward PDE

    −∂ₜz = −(q/λ) z + aᵀ∇z + (λ/2) tr(B R⁻¹ Bᵀ ∇²z),      z(x, T) = exp(−g(x)/λ),

and the optimal policy is u* = λ R⁻¹ Bᵀ∇z / z = −R⁻¹ Bᵀ∇v.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .costs import Quadratic, evaluate_cost
from .grid import Grid
from .systems.base import ControlAffineSystem


def _control_cost_matrix(control_cost, m: int) -> np.ndarray:
    R = np.asarray(control_cost, dtype=float)
    if R.ndim == 0:
        R = np.full(m, float(R))
    if R.ndim == 1:
        if R.shape != (m,):
            raise ValueError(f"control_cost must be a scalar, ({m},) or ({m}, {m}), got shape {R.shape}")
        R = np.diag(R)
    if R.shape != (m, m):
        raise ValueError(f"control_cost must be a scalar, ({m},) or ({m}, {m}), got shape {R.shape}")
    if not np.all(np.isfinite(R)) or not np.allclose(R, R.T, rtol=1e-12, atol=0):
        raise ValueError("control_cost R must be a finite symmetric matrix")
    if np.linalg.eigvalsh(R).min() <= 0:
        raise ValueError("control_cost R must be positive definite (every control must cost effort)")
    return R


def _positive_float(name: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number, got {value!r}") from None
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be positive and finite, got {value}")
    return value


@dataclass(frozen=True, eq=False)
class Problem:
    """A system, a grid, a horizon and the costs; the input to :func:`gridlbc.solve`.

    Parameters
    ----------
    system : ControlAffineSystem
        The dynamics a(x), B(x).
    grid : Grid
        The state-space box; one axis per state coordinate.
    horizon : float
        T > 0, in the system's time unit.
    terminal_cost : callable
        g(x) on ``(N, d)`` states, e.g. :class:`gridlbc.costs.Quadratic`. Quadratic costs are made
        wrap-aware on the grid's periodic axes.
    state_cost : callable, optional
        q(x) ≥ 0 on ``(N, d)`` states; zero when omitted.
    control_cost : float, (m,) or (m, m)
        R, symmetric positive definite (a scalar means R = r I).
    temperature : float
        λ > 0: the noise level and the unit of the exponential transform z = exp(−v/λ).
    """

    system: ControlAffineSystem
    grid: Grid
    horizon: float
    terminal_cost: object
    state_cost: object = None
    control_cost: object = 1.0
    temperature: float = 1.0

    def __post_init__(self):
        sys, grid = self.system, self.grid
        if not isinstance(grid, Grid):
            raise TypeError(f"grid must be a gridlbc.Grid, got {type(grid).__name__}")
        for attr in ("drift", "input_matrix", "state_dim", "control_dim"):
            if not hasattr(sys, attr):
                raise TypeError(
                    f"system must be a control-affine system with .{attr} "
                    "(subclass gridlbc.systems.ControlAffineSystem)"
                )
        if grid.ndim != sys.state_dim:
            raise ValueError(
                f"grid has {grid.ndim} axes but the {type(sys).__name__} state has "
                f"{sys.state_dim} coordinates: give one Axis per state coordinate"
            )
        set_ = lambda k, v: object.__setattr__(self, k, v)
        set_("horizon", _positive_float("horizon", self.horizon))
        set_("temperature", _positive_float("temperature", self.temperature))
        set_("control_cost", _control_cost_matrix(self.control_cost, sys.control_dim))
        set_("terminal_cost", self._bind_cost(self.terminal_cost, "terminal_cost"))
        if self.state_cost is not None:
            set_("state_cost", self._bind_cost(self.state_cost, "state_cost"))

    def _bind_cost(self, cost, name):
        if not callable(cost):
            raise TypeError(f"{name} must be callable on (N, d) states, e.g. gridlbc.costs.Quadratic")
        if isinstance(cost, Quadratic):
            if cost.dim != self.grid.ndim:
                raise ValueError(
                    f"{name} center has {cost.dim} coordinates but the state has {self.grid.ndim}"
                )
            if cost.periods is None:
                cost = cost.with_periods(self.grid.periods)
        return cost

    def replace(self, **changes) -> Problem:
        """A copy with some fields changed (e.g. ``terminal_cost``)."""
        return dataclasses.replace(self, **changes)

    @property
    def R(self) -> np.ndarray:
        """The control cost matrix, (m, m)."""
        return self.control_cost

    @property
    def R_inv(self) -> np.ndarray:
        return np.linalg.inv(self.control_cost)

    def terminal_values(self, x=None) -> np.ndarray:
        """g at states (default: the grid nodes), checked finite."""
        x = self.grid.nodes() if x is None else self.grid.check_states(x)
        return evaluate_cost(self.terminal_cost, x, "terminal_cost")

    def state_cost_values(self, x=None) -> np.ndarray:
        """q at states (default: the grid nodes), checked finite and non-negative."""
        x = self.grid.nodes() if x is None else self.grid.check_states(x)
        if self.state_cost is None:
            return np.zeros(x.shape[0])
        q = evaluate_cost(self.state_cost, x, "state_cost")
        if np.any(q < 0):
            raise ValueError(
                f"state_cost must be non-negative (min {q.min():.3g}): add a constant to it; "
                "a constant shifts v by constant·T and leaves the policy unchanged"
            )
        return q

    def noise_covariance(self, x) -> np.ndarray:
        """Σ(x) = λ B R⁻¹ Bᵀ, shape ``(N, d, d)``."""
        x = self.grid.check_states(x)
        d, m = self.system.state_dim, self.system.control_dim
        B = np.asarray(self.system.input_matrix(x), dtype=float)
        if B.shape != (x.shape[0], d, m):
            raise ValueError(
                f"{type(self.system).__name__}.input_matrix returned shape {B.shape}, "
                f"expected (N, d, m) = ({x.shape[0]}, {d}, {m})"
            )
        return self.temperature * np.einsum("nim,mk,njk->nij", B, self.R_inv, B)

    def noise_diagonal(self, x) -> np.ndarray:
        """The diagonal of Σ(x) = λ B R⁻¹ Bᵀ, shape ``(N, d)``; raises if Σ is not diagonal.

        The grid solvers need noise that is diagonal in the grid's coordinates (no cross
        derivatives ∂²z/∂x_i∂x_j).
        """
        sigma = self.noise_covariance(x)
        d = sigma.shape[1]
        diag = np.einsum("nii->ni", sigma)
        off = sigma - diag[:, :, None] * np.eye(d)
        scale = max(np.abs(diag).max(), np.finfo(float).tiny)
        if np.abs(off).max() > 1e-12 * scale:
            i, j = np.unravel_index(np.abs(off).max(axis=0).argmax(), (d, d))
            raise ValueError(
                f"the noise covariance λ B R⁻¹ Bᵀ is not diagonal in the grid coordinates "
                f"(entry ({i}, {j}) is nonzero): the grid solvers need each control to drive its "
                "own state axis. Change coordinates so that it does, as the Acrobot does by using "
                "canonical momenta p = M(θ)θ̇ instead of joint velocities, or use a diagonal R with "
                "B having one nonzero per column in distinct rows."
            )
        return diag

    def describe(self) -> str:
        return (
            f"{type(self.system).__name__} on {self.grid.describe()}, T={self.horizon:g}, "
            f"λ={self.temperature:g}"
        )
