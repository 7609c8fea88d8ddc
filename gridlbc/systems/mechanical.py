"""The built-in systems (paper §6). Angles are measured from the upright; hanging down is ±π."""

from __future__ import annotations

import math

import numpy as np

from .base import ControlAffineSystem, LinearSystem, physical_parameter


class SingleIntegrator(LinearSystem):
    """dx = u dt + noise: state (x), a = 0, B = 1."""

    def __init__(self):
        super().__init__([[0.0]], [[1.0]], state_names=("x",))

    default_box = ((-4.0, 4.0),)

    def parameters(self):
        return {}


class PointMass(LinearSystem):
    """A mass on a line: state (position, velocity), a = (v, 0), B = (0, 1/m).

    Parameters
    ----------
    mass : float
        m (positive).
    """

    def __init__(self, mass: float = 1.0):
        self.mass = physical_parameter("mass", mass)
        super().__init__(
            [[0.0, 1.0], [0.0, 0.0]],
            [[0.0], [1.0 / self.mass]],
            state_names=("position", "velocity"),
        )

    default_box = ((-4.0, 4.0), (-6.0, 6.0))

    def parameters(self):
        return {"mass": self.mass}


class Pendulum(ControlAffineSystem):
    """A torque-driven pendulum, state (θ, ω) with θ from the upright.

        θ̇ = ω,   ω̇ = (g/l) sin θ − b ω / (m l²) + u / (m l²)

    so a = (ω, (g/l) sin θ − b ω/(m l²)) and B = (0, 1/(m l²)). θ = 0 is the unstable upright
    equilibrium, θ = ±π hanging down.

    Parameters
    ----------
    mass, length : float
        m and l (positive).
    gravity : float
        g (non-negative).
    damping : float
        The viscous friction b (non-negative).
    """

    state_dim = 2
    control_dim = 1
    state_names = ("theta", "omega")
    angle_axes = (0,)
    default_box = (None, (-10.0, 10.0))

    def __init__(
        self, mass: float = 1.0, length: float = 1.0, gravity: float = 9.81, damping: float = 0.0
    ):
        self.mass = physical_parameter("mass", mass)
        self.length = physical_parameter("length", length)
        self.gravity = physical_parameter("gravity", gravity, zero_allowed=True)
        self.damping = physical_parameter("damping", damping, zero_allowed=True)

    @property
    def inertia(self) -> float:
        """m l²."""
        return self.mass * self.length**2

    def drift(self, x):
        x = self._states(x)
        theta, omega = x[:, 0], x[:, 1]
        accel = (self.gravity / self.length) * np.sin(theta) - self.damping * omega / self.inertia
        return np.stack([omega, accel], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 2, 1))
        B[:, 1, 0] = 1.0 / self.inertia
        return B

    def energy(self, x) -> np.ndarray:
        """½ m l² ω² + m g l cos θ (conserved without control and damping)."""
        x = self._states(x)
        return 0.5 * self.inertia * x[:, 1] ** 2 + self.mass * self.gravity * self.length * np.cos(
            x[:, 0]
        )

    def parameters(self):
        return {
            "mass": self.mass,
            "length": self.length,
            "gravity": self.gravity,
            "damping": self.damping,
        }


class Acrobot(ControlAffineSystem):
    """The two-link gymnast on a high bar (paper §6.2–6.3), in canonical momenta.

    Point masses ``m1``, ``m2`` at the ends of massless links ``l1``, ``l2``; the hands on the bar
    (joint 1) are passive, the hip (joint 2) is driven by the torque u. θ1 is link 1's angle from
    the upward vertical, θ2 the hip angle relative to link 1; the handstand is (0, 0, 0, 0).
    With s = (θ1, θ2) and p = M(θ2) ṡ the state is x = (θ1, θ2, p1, p2) and

        M11 = m1 l1² + m2 (l1² + l2² + 2 l1 l2 cos θ2),  M12 = m2 (l2² + l1 l2 cos θ2),  M22 = m2 l2²
        V   = g [m1 l1 cos θ1 + m2 (l1 cos θ1 + l2 cos(θ1 + θ2))]
        ṡ   = M⁻¹ p,   ṗ1 = −∂V/∂θ1,   ṗ2 = −m2 l1 l2 sin θ2 (ṡ1² + ṡ1 ṡ2) − ∂V/∂θ2 + u.

    The torque, and the noise entering with it, drives p2 alone: B = (0, 0, 0, 1), so B R⁻¹ Bᵀ is
    diagonal in these coordinates (it would not be in joint velocities, where the torque moves
    both θ̈1 and θ̈2). Use :meth:`from_velocities` / :meth:`to_velocities` to convert.

    Parameters
    ----------
    m1, m2 : float
        The point masses at the ends of link 1 and link 2 (positive).
    l1, l2 : float
        The link lengths (positive).
    gravity : float
        g (non-negative).
    """

    state_dim = 4
    control_dim = 1
    state_names = ("theta1", "theta2", "p1", "p2")
    angle_axes = (0, 1)
    default_box = (None, (-math.pi, math.pi), (-16.0, 16.0), (-9.0, 9.0))
    """The gymnast study's box: hip stops at ±π, momenta ±16 × ±9 (see
    :func:`gridlbc.studies.problems.gymnast_problem`)."""

    def __init__(
        self,
        m1: float = 1.0,
        m2: float = 1.0,
        l1: float = 1.0,
        l2: float = 1.0,
        gravity: float = 9.81,
    ):
        self.m1 = physical_parameter("m1", m1)
        self.m2 = physical_parameter("m2", m2)
        self.l1 = physical_parameter("l1", l1)
        self.l2 = physical_parameter("l2", l2)
        self.gravity = physical_parameter("gravity", gravity, zero_allowed=True)

    def mass_matrix(self, theta2) -> np.ndarray:
        """M(θ2), shape ``(N, 2, 2)``."""
        c = np.cos(np.atleast_1d(np.asarray(theta2, dtype=float)))
        m1, m2, l1, l2 = self.m1, self.m2, self.l1, self.l2
        M = np.empty((*c.shape, 2, 2))
        M[..., 0, 0] = m1 * l1**2 + m2 * (l1**2 + l2**2 + 2 * l1 * l2 * c)
        M[..., 0, 1] = M[..., 1, 0] = m2 * (l2**2 + l1 * l2 * c)
        M[..., 1, 1] = m2 * l2**2
        return M

    def _joint_velocities(self, x):
        """ṡ = M⁻¹(θ2) p, by the explicit 2×2 inverse; returns (ṡ1, ṡ2)."""
        M = self.mass_matrix(x[:, 1])
        det = M[:, 0, 0] * M[:, 1, 1] - M[:, 0, 1] ** 2
        p1, p2 = x[:, 2], x[:, 3]
        s1 = (M[:, 1, 1] * p1 - M[:, 0, 1] * p2) / det
        s2 = (M[:, 0, 0] * p2 - M[:, 0, 1] * p1) / det
        return s1, s2

    def drift(self, x):
        x = self._states(x)
        t1, t2 = x[:, 0], x[:, 1]
        m1, m2, l1, l2, g = self.m1, self.m2, self.l1, self.l2, self.gravity
        s1, s2 = self._joint_velocities(x)
        dV1 = -g * ((m1 + m2) * l1 * np.sin(t1) + m2 * l2 * np.sin(t1 + t2))
        dV2 = -g * m2 * l2 * np.sin(t1 + t2)
        p1dot = -dV1
        p2dot = -m2 * l1 * l2 * np.sin(t2) * (s1**2 + s1 * s2) - dV2
        return np.stack([s1, s2, p1dot, p2dot], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 4, 1))
        B[:, 3, 0] = 1.0
        return B

    def energy(self, x) -> np.ndarray:
        """H = ½ pᵀ M⁻¹ p + V (conserved without control)."""
        x = self._states(x)
        s1, s2 = self._joint_velocities(x)
        kinetic = 0.5 * (x[:, 2] * s1 + x[:, 3] * s2)
        t1, t2 = x[:, 0], x[:, 1]
        potential = self.gravity * (
            self.m1 * self.l1 * np.cos(t1)
            + self.m2 * (self.l1 * np.cos(t1) + self.l2 * np.cos(t1 + t2))
        )
        return kinetic + potential

    def from_velocities(self, x) -> np.ndarray:
        """(θ1, θ2, θ̇1, θ̇2) → (θ1, θ2, p1, p2) with p = M(θ2) θ̇."""
        x = self._states(x)
        p = np.einsum("nij,nj->ni", self.mass_matrix(x[:, 1]), x[:, 2:])
        return np.concatenate([x[:, :2], p], axis=1)

    def to_velocities(self, x) -> np.ndarray:
        """(θ1, θ2, p1, p2) → (θ1, θ2, θ̇1, θ̇2) with θ̇ = M(θ2)⁻¹ p."""
        x = self._states(x)
        s1, s2 = self._joint_velocities(x)
        return np.concatenate([x[:, :2], np.stack([s1, s2], axis=1)], axis=1)

    def velocity_dynamics(self, x, u) -> np.ndarray:
        """Equations of motion in joint velocities, M θ̈ + C θ̇ + ∂V/∂θ = (0, u) (Lagrange form).

        Returns (θ̇1, θ̇2, θ̈1, θ̈2) for states (θ1, θ2, θ̇1, θ̇2); an independent derivation used to
        check the momentum form.
        """
        x = self._states(x)
        u = np.asarray(u, dtype=float).reshape(x.shape[0])
        t1, t2, w1, w2 = x.T
        m1, m2, l1, l2, g = self.m1, self.m2, self.l1, self.l2, self.gravity
        M = self.mass_matrix(t2)
        h = m2 * l1 * l2 * np.sin(t2)
        # Coriolis/centrifugal terms of the Lagrangian with V as above.
        c1 = -h * (2 * w1 * w2 + w2**2)
        c2 = h * w1**2
        grav1 = -g * ((m1 + m2) * l1 * np.sin(t1) + m2 * l2 * np.sin(t1 + t2))
        grav2 = -g * m2 * l2 * np.sin(t1 + t2)
        rhs = np.stack([-c1 - grav1, u - c2 - grav2], axis=1)
        acc = np.linalg.solve(M, rhs[..., None])[..., 0]
        return np.concatenate([np.stack([w1, w2], axis=1), acc], axis=1)

    def parameters(self):
        return {"m1": self.m1, "m2": self.m2, "l1": self.l1, "l2": self.l2, "gravity": self.gravity}
