"""The numba options, under their old import path: :mod:`gridlbc.backends.numba.options` is the
one place that sets them (modules outside the scheme tree still import them from here)."""

from .backends.numba.options import jit, jit_inline, jit_parallel, prange, work_blocks

__all__ = ["jit", "jit_inline", "jit_parallel", "prange", "work_blocks"]
