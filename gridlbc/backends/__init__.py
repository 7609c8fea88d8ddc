"""Compiled kernels behind the schemes, one folder per backend.

The schemes (:mod:`gridlbc.schemes`) and the numpy-facing layers (:mod:`gridlbc.interpolate`,
:mod:`gridlbc.storage`) do the setup in numpy and call kernels that take and return arrays in
place. Those kernels are the backend; today the only one is :mod:`gridlbc.backends.numba`, whose
modules are named by what they compute:

- ``interpolation``: the cell of a coordinate, the Kuhn simplex and weights, node gradients;
- ``feet``: the compact encoding of the characteristic feet;
- ``drift``: the semi-Lagrangian gather (plain and fitted), the fitting division, Courant rates;
- ``curvature``: the curvature term of the fitted drift;
- ``diffusion``: tridiagonal (closed) and cyclic (periodic) implicit diffusion, cost and maxima;
- ``fitted_cells``, ``fitted_node``, ``fitted_diffusion``: the erf-integrated fitted diffusion;
- ``special``: erfcx for the kernels;
- ``storage``: storing a renormalised slice;
- ``implicit``: Gauss–Seidel sweeps of the implicit scheme;
- ``costs``: the wrap-aware quadratic form of the library's quadratic costs.

Adding a backend (GPU, JAX, …) means a sibling folder with the same functions (same arguments,
same in-place outputs) and pointing the callers at it. The data the kernels exchange is part of
the contract; its two shared constants are here.
"""

QUANTUM = 65535
"""Quantisation of the feet's sorted fractional coordinates in the compact layout (a foot moves by
at most 1/(2·QUANTUM) of a cell; see :mod:`gridlbc.schemes.splitting.feet`)."""

REFERENCE_FLOOR = 1e-300
"""Floor of a fitting reference φ: 1/φ and the fitted factors stay finite where φ underflows."""
