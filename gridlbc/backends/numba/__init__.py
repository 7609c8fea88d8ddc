"""The numba backend: every compiled kernel of the library's solvers (see :mod:`gridlbc.backends`
for the list). Numba's options are set in one place, :mod:`gridlbc.backends.numba.options`."""
