"""The one place that sets numba's options for every kernel in the library.

Kernels are cached on disk (``cache=True``) so a second process does not pay the compile time, and
never use ``fastmath``: reassociation would break the bitwise reproducibility that the
superposition checks rely on.
"""

from __future__ import annotations

import numba

jit = numba.njit(cache=True, nogil=True)
"""Decorator for serial kernels."""

jit_inline = numba.njit(cache=True, nogil=True, inline="always")
"""Decorator for small serial helpers that numba inlines into their callers (no call overhead
inside the per-node loops of a kernel)."""

jit_parallel = numba.njit(cache=True, nogil=True, parallel=True)
"""Decorator for kernels whose outer loop is a ``numba.prange`` over independent work."""

prange = numba.prange


def work_blocks(n_items: int) -> int:
    """Number of parallel work blocks for ``n_items`` independent items: a few per thread, so
    that the load balances."""
    return max(1, min(n_items, 8 * numba.get_num_threads()))
