"""Stationary problems: first exit without a horizon, and average cost (SPEC §9; docs page
:doc:`first_exit`; Todorov 2009).

**First exit.** The task ends at τ, the first time the state enters the exit set E, paying
g_E(x_τ). Off E, z = exp(−v/λ) solves the *linear* stationary equation

    (q/λ) z = aᵀ∇z + (λ/2) tr(B R⁻¹ Bᵀ ∇²z),        z = exp(−g_E/λ) on E.

On the grid, aᵀ∇ + (λ/2) tr(B R⁻¹ Bᵀ ∇²) becomes the generator L of a monotone Markov chain on the
nodes (:mod:`gridlbc.schemes.generator`; exponentially fitted rates by default), whose nodes next
to E jump to the points b where their arms enter E (the set's boundary fitted between the
nodes), and the equation the sparse linear system

    (diag(q/λ) − L)_II z_I = L_IE z_E + L_Ib z_b,        z_E, z_b = exp(−g_E/λ) there,

over the nodes I off E, with the nodes of E and the boundary points as known values. Its matrix is a non-singular
M-matrix exactly when every node can reach E or a node with q > 0 along the chain's jumps
(:func:`~gridlbc.stationary.first_exit.check_well_posed` refuses a problem where some cannot: their
z would be undetermined). It is solved directly (sparse LU) or by a Krylov method; no time marching.
The solution is linear in z_E: exit costs g_i on one E, solved with one operator, superpose exactly,
z = Σ_i w_i z_i (:func:`gridlbc.combine`).

**Average cost.** A task that never ends has an optimal cost per unit time c and a relative value
h(x) (v(x, T) ≈ c T + h(x) for long horizons): e = exp(−h/λ) is the principal eigenfunction of
the same operator,

    (L − diag(q/λ)) e = −(c/λ) e,

the eigenvalue of largest real part, whose eigenvector is positive (Perron–Frobenius: the
matrix's off-diagonal entries are non-negative). It is found by Noda's inverse iteration,
whose shifts σ_k ↓ μ from σ₀ = −min q/λ + ε keep σ_k I − M a non-singular M-matrix, solved
by LU where the first-exit system would be (one and two dimensions) and otherwise by the same
Krylov methods (:func:`principal_eigenpair`). h is
normalised to min h = 0 at the nodes, and the embedded solves on the grids 2h and 4h, normalised
the same way, give the estimates of h (:meth:`StationarySolution.error_estimate
<gridlbc.Solution.error_estimate>`) and of c
(``average_cost_error``, :func:`gridlbc.accuracy.estimate.scalar_estimate`).

The package: :mod:`~gridlbc.stationary.first_exit` (the linear system),
:mod:`~gridlbc.stationary.average` (the eigenpair), :mod:`~gridlbc.stationary.linear` (their
settings and sparse solvers), :mod:`~gridlbc.stationary.solve` (the solves as
:func:`gridlbc.solve` runs them, with their estimates, and to a tolerance).
"""

from .average import (
    eigen_residual,
    principal_eigenpair,
    solve_average_cost,
    stationary_distribution,
)
from .first_exit import check_well_posed, exit_nodes, solve_first_exit, solve_first_exit_many
from .linear import (
    BYTES_PER_NODE,
    DIRECT_LIMIT,
    LINEAR_SOLVERS,
    MAX_ITERATIONS,
    MAX_SHIFTS,
    TAIL,
    StationarySettings,
    accurate_tail,
    stationary_settings,
    stationary_work_exponent,
)
from .solve import solve_stationary, solve_stationary_many, solve_stationary_to_tolerance

__all__ = [
    "BYTES_PER_NODE",
    "DIRECT_LIMIT",
    "LINEAR_SOLVERS",
    "MAX_ITERATIONS",
    "MAX_SHIFTS",
    "TAIL",
    "StationarySettings",
    "accurate_tail",
    "check_well_posed",
    "eigen_residual",
    "exit_nodes",
    "principal_eigenpair",
    "solve_average_cost",
    "solve_first_exit",
    "solve_first_exit_many",
    "solve_stationary",
    "solve_stationary_many",
    "solve_stationary_to_tolerance",
    "stationary_distribution",
    "stationary_settings",
    "stationary_work_exponent",
]
