"""Schemes for the backward time stepping of the desirability z (docs/maths.rst, docs/schemes.rst).

Every scheme is a *step operator* S with z(·, t − Δt) = S z(·, t), linear in z and monotone
(z ≥ 0 and a discrete maximum principle), so the discrete problem is itself a linearly solvable
Markov chain and superposition holds to rounding. :data:`~gridlbc.METHODS` names the schemes; each
is a
:class:`~gridlbc.schemes.protocol.Scheme`, the written contract of everything
:func:`gridlbc.solve` asks of a scheme (its default step, its bound on the step, its time loop,
its checks; :mod:`gridlbc.schemes.protocol` lists them in the order they are called).

Where things go:

- A scheme: a module or package here with a :class:`~gridlbc.schemes.protocol.Scheme` object,
  registered in :data:`~gridlbc.METHODS` (the implicit scheme, one module, is the small example; the
  splitting, :mod:`gridlbc.schemes.splitting`, the large one). Its compiled kernels go to
  :mod:`gridlbc.backends.numba`; loops over a linear step operator can reuse
  :func:`gridlbc.schemes.march.march_linear`.
- A stationary (first-exit) driver: beside ``march`` in the protocol, a
  ``solve_stationary(plan, terminal)`` that iterates the same step operator to its fixed point
  z = S z instead of a fixed number of steps. A :class:`~gridlbc.schemes.protocol.MarchPlan` then
  carries no horizon but a stopping rule, and it returns the same
  :class:`~gridlbc.schemes.protocol.Marched` record with a single slice, so the solver's storage
  and packaging serve both. The operators already take the boundary of each closed axis from
  :mod:`gridlbc.boundary`, where an exit boundary is added.
- A backend: a sibling of :mod:`gridlbc.backends.numba` with the same kernels.
"""

from __future__ import annotations

from .implicit import IMPLICIT, LINEAR_SOLVERS, ImplicitScheme, ImplicitStep
from .protocol import Marched, MarchPlan, Scheme, StepBound, StepOperator, StepRule, Terminal
from .splitting import SPLITTING, SplittingScheme, SplittingStep

METHODS: dict[str, Scheme] = {"splitting": SPLITTING, "implicit": IMPLICIT}
"""Schemes by name (:class:`~gridlbc.schemes.protocol.Scheme` objects; ``METHODS[name].step`` is
the step operator's class); both are linear in z and monotone (z ≥ 0, discrete maximum principle).

- ``"splitting"`` (default): semi-Lagrangian drift + implicit tridiagonal diffusion + exact cost
  (:mod:`gridlbc.schemes.splitting`). Error O(h²/Δt + Δt); unconditionally stable; O(N) work per
  step with parallel, allocation-free kernels and compact feet. Exactly linear (superposition to
  rounding); supports exponential fitting of the drift.
- ``"implicit"``: upwind + backward Euler, error O(h + Δt) (:mod:`gridlbc.schemes.implicit`), the
  reference. Its linear system is solved by sparse LU on small 2D grids (exact to rounding) and
  by Gauss–Seidel sweeps otherwise (non-negative iterates, stopped at a max-norm change of
  ``1e-10`` of max z: linear and monotone up to that tolerance); ``linear_solver`` overrides.
"""

__all__ = [
    "IMPLICIT",
    "LINEAR_SOLVERS",
    "METHODS",
    "SPLITTING",
    "ImplicitScheme",
    "ImplicitStep",
    "MarchPlan",
    "Marched",
    "Scheme",
    "SplittingScheme",
    "SplittingStep",
    "StepBound",
    "StepOperator",
    "StepRule",
    "Terminal",
]
