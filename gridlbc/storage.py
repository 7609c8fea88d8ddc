"""Where a solve keeps its slices: the memory check made before any work (against the estimate
of :func:`gridlbc.settings.memory_estimate`), the slice arrays (in RAM or an unlinked
memory-mapped file) and the kernel that stores a slice.
"""

from __future__ import annotations

import math
import mmap
import os
import shutil
import tempfile

import numpy as np

from .backends.numba.storage import store_kernel

__all__ = [
    "available_memory",
    "check_memory",
    "slice_storage",
    "store_kernel",  # the backend's kernel that writes a renormalised slice
]


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation (MemAvailable on Linux), or None."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(estimate: dict[str, int], what: str, mmap_dir: str | None):
    available = available_memory()

    def gib(b):
        return f"{b / 2**30:.2f} GiB"

    detail = ", ".join(f"{k} {gib(v)}" for k, v in estimate.items() if k != "ram")
    if available is not None and estimate["ram"] > 0.9 * available:
        raise MemoryError(
            f"{what} needs about {gib(estimate['ram'])} of memory ({detail}) but only "
            f"{gib(available)} is available: keep fewer slices (store_every), store float32, "
            "put the slices in a memory-mapped file (mmap_dir), or use a coarser grid"
        )
    if mmap_dir is not None:
        free = shutil.disk_usage(mmap_dir).free
        if estimate["stored"] > 0.95 * free:
            raise MemoryError(
                f"{what} needs {gib(estimate['stored'])} of disk in {mmap_dir!r} for the slices but "
                f"only {gib(free)} is free: keep fewer slices (store_every) or store float32"
            )


def slice_storage(shape: tuple[int, ...], dtype: np.dtype, mmap_dir: str | None) -> np.ndarray:
    """Uninitialised slice arrays: in RAM, or in an unlinked file in ``mmap_dir``.

    In RAM they get an anonymous memory map of their own, paged as the kernel does by default:
    numpy advises transparent huge pages for large arrays, and where the kernel then compacts
    memory to back them, the first write of every slice is several times slower."""
    if mmap_dir is None:
        nbytes = math.prod(shape) * np.dtype(dtype).itemsize
        if nbytes == 0:
            return np.empty(shape, dtype=dtype)
        unix = hasattr(mmap, "MAP_PRIVATE") and hasattr(mmap, "MAP_ANONYMOUS")
        private = {"flags": mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS} if unix else {}
        return np.frombuffer(mmap.mmap(-1, nbytes, **private), dtype=dtype).reshape(shape)
    # An unlinked temporary file, closed once mapped (the mapping holds the file): its disk
    # space is returned when the Solution is released.
    with tempfile.TemporaryFile(dir=mmap_dir) as handle:
        return np.memmap(handle, dtype=dtype, mode="w+", shape=shape)
