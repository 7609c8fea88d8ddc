"""Backward time stepping of the linear Bellman PDE: :func:`solve` and :func:`solve_many`.

From the terminal data z(·, T) = exp(−g/λ) a step operator S (a monotone linear map, see
:mod:`gridlbc.splitting` and :mod:`gridlbc.implicit`) is applied n = T/Δt times,

    z(·, t − Δt) = S z(·, t).

To keep z in range every slice is renormalised, z = Z e^ℓ with max Z = 1: the scale ℓ is carried
exactly in the log domain, so nothing underflows as a whole and linear combinations stay exact.
Nodes whose Z underflows to zero are counted in the diagnostics (their value is +∞).
"""

from __future__ import annotations

import math
import os
import sys
import time
from dataclasses import dataclass

import numpy as np

from .implicit import ImplicitStep
from .problem import Problem
from .solution import SolveDiagnostics, Solution
from .splitting import SplittingStep

METHODS = {"splitting": SplittingStep, "implicit": ImplicitStep}
"""Step schemes by name. ``"splitting"`` is the default (far less numerical diffusion per second;
see ``benchmarks/swingup_accuracy.py``); ``"implicit"`` is the backward-Euler reference."""


@dataclass(frozen=True)
class SolverSettings:
    """How to solve: scheme, time step, storage and progress.

    Parameters
    ----------
    method : str
        One of :data:`METHODS` (``"splitting"`` or ``"implicit"``).
    dt : float, optional
        Time step; rounded down so that it divides the horizon. Default: a Courant number
        (max |a_k| Δt / h_k) of ``courant`` for the splitting scheme, and 1 for the implicit one,
        with at least ``min_steps`` steps.
    courant : float
        Target Courant number for the default dt of the splitting scheme.
    min_steps : int
        At least this many steps over the horizon.
    store_every : int
        Keep every k-th slice (and always t = 0 and T); values between are interpolated linearly
        in time.
    dtype : str
        ``"float64"`` or ``"float32"`` for the stored slices (the time stepping is float64).
    progress : bool
        Print a progress bar to stderr.
    """

    method: str = "splitting"
    dt: float | None = None
    courant: float = 2.0
    min_steps: int = 50
    store_every: int = 1
    dtype: str = "float64"
    progress: bool = False

    def __post_init__(self):
        if self.method not in METHODS:
            raise ValueError(
                f"unknown method {self.method!r}: choose one of {', '.join(sorted(METHODS))}"
            )
        if self.dt is not None and not (np.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt must be positive and finite, got {self.dt}")
        if not (self.courant > 0):
            raise ValueError(f"courant must be positive, got {self.courant}")
        if int(self.min_steps) < 1 or int(self.store_every) < 1:
            raise ValueError("min_steps and store_every must be at least 1")
        if self.dtype not in ("float64", "float32"):
            raise ValueError(f"dtype must be 'float64' or 'float32', got {self.dtype!r}")


PRESETS = {
    "default": SolverSettings(),
    "reference": SolverSettings(method="implicit", courant=1.0),
    "fast": SolverSettings(method="splitting", courant=4.0, min_steps=20),
}
"""Named settings; pass ``settings="fast"`` etc. to :func:`solve`."""


def _settings(settings, options) -> SolverSettings:
    if settings is None:
        settings = PRESETS["default"]
    elif isinstance(settings, str):
        if settings not in PRESETS:
            raise ValueError(
                f"unknown settings preset {settings!r}: choose one of {', '.join(sorted(PRESETS))}"
            )
        settings = PRESETS[settings]
    elif not isinstance(settings, SolverSettings):
        raise TypeError("settings must be a SolverSettings or the name of a preset")
    fields = SolverSettings.__dataclass_fields__
    unknown = set(options) - set(fields)
    if unknown:
        raise TypeError(
            f"unknown solve option(s) {', '.join(sorted(unknown))}: valid options are "
            f"{', '.join(fields)}"
        )
    return SolverSettings(**{**settings.__dict__, **options})


def max_courant_rate(problem: Problem) -> float:
    """max over nodes and axes of |a_k(x)| / h_k (1/time)."""
    grid = problem.grid
    drift = np.asarray(problem.system.drift(grid.nodes()), dtype=float)
    return float(np.max(np.abs(drift) / grid.spacing))


def time_grid(problem: Problem, settings: SolverSettings, rate: float) -> tuple[float, int]:
    """The step Δt and the number of steps n with n Δt = T."""
    T = problem.horizon
    if settings.dt is not None:
        if settings.dt > T:
            raise ValueError(f"dt = {settings.dt} exceeds the horizon T = {T}")
        n = math.ceil(T / settings.dt - 1e-9)
    else:
        courant = settings.courant if settings.method == "splitting" else 1.0
        n = max(settings.min_steps, math.ceil(T * rate / courant - 1e-9))
    return T / n, n


def _check_memory(n_bytes: int, what: str):
    try:
        available = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return
    if n_bytes > 0.8 * available:
        raise MemoryError(
            f"{what} needs about {n_bytes / 2**30:.1f} GiB but only {available / 2**30:.1f} GiB "
            "is free: keep fewer slices (store_every), store float32, or use a coarser grid"
        )


class _Progress:
    def __init__(self, total: int, enabled: bool, label: str):
        self.total, self.enabled, self.label = total, enabled, label
        self.start = time.perf_counter()
        self.shown = -1

    def update(self, done: int):
        if not self.enabled:
            return
        percent = int(100 * done / self.total)
        if percent != self.shown:
            self.shown = percent
            bar = "#" * (percent // 4)
            elapsed = time.perf_counter() - self.start
            sys.stderr.write(f"\r{self.label} [{bar:<25}] {percent:3d}% {elapsed:6.1f}s")
            if done == self.total:
                sys.stderr.write("\n")
            sys.stderr.flush()


def _terminal_data(problem: Problem, terminal_costs) -> tuple[np.ndarray, np.ndarray]:
    """Scaled terminal desirabilities Z (K, N), max 1 per row, and their log-scales ℓ (K,)."""
    nodes = problem.grid.nodes()
    lam = problem.temperature
    Z = np.empty((len(terminal_costs), problem.grid.size))
    scales = np.empty(len(terminal_costs))
    for r, cost in enumerate(terminal_costs):
        g = problem.replace(terminal_cost=cost).terminal_values(nodes)
        g_min = g.min()
        with np.errstate(under="ignore"):
            Z[r] = np.exp(-(g - g_min) / lam)
        scales[r] = -g_min / lam
    return Z, scales


def solve_many(problem: Problem, terminal_costs, settings=None, **options) -> list[Solution]:
    """Solve one problem for several terminal costs at once (one operator, many right-hand sides).

    ``terminal_costs`` is a sequence of callables g_i; returns one :class:`Solution` per cost,
    each exactly as :func:`solve` would return for ``problem.replace(terminal_cost=g_i)``.
    """
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a gridlbc.Problem, got {type(problem).__name__}")
    terminal_costs = list(terminal_costs)
    if not terminal_costs:
        raise ValueError("terminal_costs is empty: give at least one terminal cost")
    s = _settings(settings, options)
    grid = problem.grid
    started = time.perf_counter()
    rate = max_courant_rate(problem)
    dt, n_steps = time_grid(problem, s, rate)
    kept = sorted(set(range(0, n_steps + 1, s.store_every)) | {n_steps})
    dtype = np.dtype(s.dtype)
    K = len(terminal_costs)
    stored_bytes = len(kept) * K * grid.size * dtype.itemsize
    _check_memory(stored_bytes + 4 * K * grid.size * 8, f"solving on {grid.describe()}")

    Z, log_scale = _terminal_data(problem, terminal_costs)
    step = METHODS[s.method](problem, dt)
    setup_time = time.perf_counter() - started

    slices = np.empty((len(kept), K, grid.size), dtype=dtype)
    scales = np.empty((len(kept), K))
    slot = len(kept) - 1
    slices[slot], scales[slot] = Z, log_scale
    progress = _Progress(n_steps, s.progress, f"{s.method} {grid.describe()}")
    for n in range(n_steps - 1, -1, -1):  # step n+1 → n, t_n = n Δt
        Z = step(Z)
        peak = Z.max(axis=1)
        if not np.all(peak > 0) or not np.all(np.isfinite(peak)):
            raise FloatingPointError(
                f"desirability vanished or overflowed everywhere at t = {n * dt:g}: the costs are "
                "too large for this temperature (rescale them or raise the temperature)"
            )
        Z /= peak[:, None]
        log_scale = log_scale + np.log(peak)
        if n == kept[slot - 1]:
            slot -= 1
            slices[slot], scales[slot] = Z, log_scale
        progress.update(n_steps - n)
    wall = time.perf_counter() - started
    times = np.array(kept, dtype=float) * dt
    times[-1] = problem.horizon
    out = []
    for r, cost in enumerate(terminal_costs):
        diagnostics = SolveDiagnostics(
            method=s.method, dt=dt, steps=n_steps, store_every=s.store_every, wall_time=wall,
            setup_time=setup_time, underflow_nodes=int(np.count_nonzero(slices[0, r] <= 0)),
            stored_bytes=int(slices[:, r].nbytes), operator_bytes=step.nbytes,
            courant=rate * dt, iterations=tuple(getattr(step, "iterations", ())),
        )
        out.append(Solution(problem.replace(terminal_cost=cost), times,
                            np.ascontiguousarray(slices[:, r]), scales[:, r].copy(), diagnostics))
    return out


def solve(problem: Problem, dt: float | None = None, settings=None, **options) -> Solution:
    """Solve the linear Bellman PDE of ``problem`` backward from T to 0.

    Parameters
    ----------
    problem : Problem
    dt : float, optional
        Time step (default from the Courant number, see :class:`SolverSettings`).
    settings : SolverSettings or str, optional
        Settings or the name of a preset in :data:`PRESETS`.
    **options
        Any :class:`SolverSettings` field, e.g. ``method="implicit"``, ``store_every=5``,
        ``progress=True``.

    Returns
    -------
    Solution
        Value, desirability and policy at any (x, t), with :class:`SolveDiagnostics`.
    """
    if dt is not None:
        options["dt"] = dt
    return solve_many(problem, [problem.terminal_cost], settings, **options)[0]
