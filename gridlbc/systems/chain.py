"""A planar chain of n links in canonical momenta: the gymnast on a bar, or a diver in flight.

Coordinates. s = (θ1, θ2, …, θn): θ1 is link 1's absolute angle from the upward vertical, θk
(k ≥ 2) the joint angle of link k relative to link k − 1, so link k's absolute angle is
ψk = θ1 + … + θk, i.e. ψ = L s with L the lower-triangular matrix of ones. A link at absolute
angle ψ points along e(ψ) = (−sin ψ, cos ψ) (x to the right, y up; angles counterclockwise, as
drawn for the gymnast). The state is x = (s, p) with the canonical momenta p = M(s) ṡ.

Kinetic and potential energy. Both mass models below give, with constants G (n×n, symmetric),
J (n) and h (n),

    T = ½ ψ̇ᵀ A(ψ) ψ̇,   A_ij = G_ij cos(ψi − ψj) + J_i δ_ij,   V = g Σ_j h_j cos ψj,

so M(s) = Lᵀ A(Ls) L. The Hamiltonian H(s, p) = ½ pᵀ M(s)⁻¹ p + V(s) gives

    ṡ = ∂H/∂p = M⁻¹ p,
    ṗ = −∂H/∂s + Q = Lᵀ f + Q,   f_i = −ψ̇_i Σ_j G_ij sin(ψi − ψj) ψ̇_j + g h_i sin ψi,

with ψ̇ = L ṡ (f_i is ∂(T − V)/∂ψi at fixed ψ̇, and ∂/∂s = Lᵀ ∂/∂ψ). The torque u_k at joint
k + 1 (between links k and k + 1, k = 1 … n − 1) does work on θ_{k+1} alone, so Q = (0, u) and
B = [0; 0; I]: every torque drives one momentum, and B R⁻¹ Bᵀ is diagonal in these coordinates
whenever R is (it is not in joint velocities, where one torque accelerates every joint).

Pinned (``pinned=True``, the gymnast of paper §6.3): the end of link 1 holds the bar, point masses
m_k sit at the far end of massless links l_k, so with μ_k = m_k + … + m_n (the mass beyond
joint k)

    G_ij = l_i l_j μ_max(i,j),   J = 0,   h_j = l_j μ_j.

With two links this is :class:`gridlbc.systems.Acrobot`.

Free (``pinned=False``, a diver in flight): the centre of mass follows its parabola whatever the
body does, and uniform gravity exerts no torque about it, so the centre of mass is dropped from
the state and gravity does not enter (h = 0). Each link is a uniform rod of mass m_k and length
l_k (moment of inertia m_k l_k²/12 about its middle; point masses at the far link ends would leave
link 1 without inertia, M singular). With c_k = Σ_j D_kj e(ψj) the middle of rod k relative to
the centre of mass, D_kj = l_j ([j < k] + ½[j = k]) − Σ_i (m_i/m) l_j ([j < i] + ½[j = i]),

    G_ij = Σ_k m_k D_ki D_kj,   J_k = m_k l_k²/12,   h = 0.

T does not depend on θ1 (turning the whole body changes no energy), so ṗ1 = Σ_i f_i = 0: the
momentum conjugate to θ1, the total angular momentum about the centre of mass (counterclockwise
positive), is conserved. The equations set ṗ1 = 0 exactly (the sum cancels pairwise, to rounding),
and B has no row for p1, so rollouts conserve it to the bit.
"""

from __future__ import annotations

import numpy as np

from .base import ControlAffineSystem, physical_parameter


def _per_link(name: str, value, n: int) -> tuple[float, ...]:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise ValueError(f"{name} must be one number or one per link ({n}), got shape {arr.shape}")
    return tuple(physical_parameter(f"{name}[{k}]", v) for k, v in enumerate(arr))


class PlanarChain(ControlAffineSystem):
    """A planar chain of ``n_links`` links in canonical momenta, torques at the joints between
    links (see the module docstring for the equations).

    Parameters
    ----------
    n_links : int
        n ≥ 2; the state is (θ1, …, θn, p1, …, pn), 2n coordinates, with n − 1 controls.
    masses, lengths : float or sequence of n floats
        Link masses (kg) and lengths (m). Pinned: point masses at the far link ends. Free: uniform
        rods.
    pinned : bool
        True: link 1's base holds a fixed bar (the gymnast). False: free flight (a diver), the
        centre of mass dropped from the state; p1 is then the conserved angular momentum.
    gravity : float
        g (m/s²). It has no effect on a free chain (no torque about the centre of mass).
    """

    def __init__(
        self, n_links: int, masses=1.0, lengths=1.0, pinned: bool = True, gravity: float = 9.81
    ):
        if isinstance(n_links, bool) or not isinstance(n_links, (int, np.integer)) or n_links < 2:
            raise ValueError(
                f"n_links must be an integer ≥ 2 (a chain with a joint to drive), got {n_links!r}"
            )
        n = int(n_links)
        self.n_links = n
        self.masses = _per_link("masses", masses, n)
        self.lengths = _per_link("lengths", lengths, n)
        if not isinstance(pinned, (bool, np.bool_)):
            raise TypeError(f"pinned must be True or False, got {pinned!r}")
        self.pinned = bool(pinned)
        self.gravity = physical_parameter("gravity", gravity, zero_allowed=True)
        self.state_dim, self.control_dim = 2 * n, n - 1
        self.state_names = tuple(f"theta{k}" for k in range(1, n + 1)) + tuple(
            f"p{k}" for k in range(1, n + 1)
        )
        self.angle_axes = tuple(range(n))
        self._G, self._J, self._h = self._inertia_constants()
        self._L = np.tril(np.ones((n, n)))

    def _inertia_constants(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """G, J, h of T = ½ ψ̇ᵀ (G ∘ cos(ψi − ψj) + diag J) ψ̇ and V = g Σ h_j cos ψj."""
        m, length = np.array(self.masses), np.array(self.lengths)
        n = m.size
        if self.pinned:
            beyond = np.cumsum(m[::-1])[::-1]  # μ_k
            G = np.outer(length, length) * beyond[np.maximum.outer(np.arange(n), np.arange(n))]
            return G, np.zeros(n), length * beyond
        lower = np.tril(np.ones((n, n)), -1) + 0.5 * np.eye(n)  # [j < k] + ½[j = k]
        D0 = lower * length  # rod middles from the base point
        D = D0 - (m / m.sum()) @ D0
        return D.T @ (m[:, None] * D), m * length**2 / 12.0, np.zeros(n)

    # -- kinematics -------------------------------------------------------------------------

    def absolute_angles(self, x) -> np.ndarray:
        """ψ = L s, each link's angle from the upward vertical, shape ``(N, n)``."""
        x = self._states(x)
        return np.cumsum(x[:, : self.n_links], axis=1)

    def mass_matrix(self, angles) -> np.ndarray:
        """M(s) = Lᵀ A(Ls) L for joint angles s ``(N, n)`` (or one ``(n,)``), shape ``(N, n, n)``."""
        s = np.asarray(angles, dtype=float)
        s = s[None] if s.ndim == 1 else s
        if s.ndim != 2 or s.shape[1] != self.n_links:
            raise ValueError(f"angles must have shape (N, {self.n_links}), got {np.shape(angles)}")
        psi = np.cumsum(s, axis=1)
        A = self._G * np.cos(psi[:, :, None] - psi[:, None, :]) + np.diag(self._J)
        return self._L.T @ A @ self._L

    def _joint_velocities(self, x: np.ndarray) -> np.ndarray:
        n = self.n_links
        return np.linalg.solve(self.mass_matrix(x[:, :n]), x[:, n:, None])[..., 0]

    def positions(self, x) -> np.ndarray:
        """The n + 1 joint and end points, shape ``(N, n + 1, 2)`` as (x to the right, y up).

        Pinned: relative to the bar (point 0 is the bar). Free: relative to the centre of mass.
        """
        psi = self.absolute_angles(x)
        steps = np.array(self.lengths)[:, None] * np.stack([-np.sin(psi), np.cos(psi)], axis=-1)
        points = np.concatenate([np.zeros((psi.shape[0], 1, 2)), np.cumsum(steps, axis=1)], axis=1)
        if not self.pinned:
            m = np.array(self.masses)
            middles = 0.5 * (points[:, 1:] + points[:, :-1])
            points -= np.einsum("nkc,k->nc", middles, m / m.sum())[:, None, :]
        return points

    # -- dynamics ---------------------------------------------------------------------------

    def drift(self, x):
        x = self._states(x)
        n = self.n_links
        s_dot = self._joint_velocities(x)
        psi = np.cumsum(x[:, :n], axis=1)
        psi_dot = np.cumsum(s_dot, axis=1)
        sin_rel = np.sin(psi[:, :, None] - psi[:, None, :])
        f = -psi_dot * np.einsum("nij,nj->ni", self._G * sin_rel, psi_dot)
        f += self.gravity * self._h * np.sin(psi)
        p_dot = np.cumsum(f[:, ::-1], axis=1)[:, ::-1]  # Lᵀ f
        if not self.pinned:
            p_dot[:, 0] = 0.0  # Σ_i f_i = 0 identically (see the module docstring)
        return np.concatenate([s_dot, p_dot], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        n = self.n_links
        B = np.zeros((x.shape[0], 2 * n, n - 1))
        B[:, n + 1 :, :] = np.eye(n - 1)
        return B

    def potential(self, x) -> np.ndarray:
        """V = g Σ_j h_j cos ψj (zero for a free chain), shape ``(N,)``."""
        return self.gravity * np.cos(self.absolute_angles(x)) @ self._h

    def energy(self, x) -> np.ndarray:
        """H = ½ pᵀ M⁻¹ p + V (conserved without control), shape ``(N,)``."""
        x = self._states(x)
        kinetic = 0.5 * np.einsum("ni,ni->n", x[:, self.n_links :], self._joint_velocities(x))
        return kinetic + self.potential(x)

    def angular_momentum(self, x) -> np.ndarray:
        """p1: the angular momentum about the bar (pinned) or the centre of mass (free),
        counterclockwise positive; conserved in free flight. Shape ``(N,)``."""
        return self._states(x)[:, self.n_links]

    def from_velocities(self, x) -> np.ndarray:
        """(s, ṡ) → (s, p) with p = M(s) ṡ."""
        x = self._states(x)
        n = self.n_links
        p = np.einsum("nij,nj->ni", self.mass_matrix(x[:, :n]), x[:, n:])
        return np.concatenate([x[:, :n], p], axis=1)

    def to_velocities(self, x) -> np.ndarray:
        """(s, p) → (s, ṡ) with ṡ = M(s)⁻¹ p."""
        x = self._states(x)
        return np.concatenate([x[:, : self.n_links], self._joint_velocities(x)], axis=1)

    def parameters(self):
        return {
            "n_links": self.n_links,
            "masses": self.masses,
            "lengths": self.lengths,
            "pinned": self.pinned,
            "gravity": self.gravity,
        }
