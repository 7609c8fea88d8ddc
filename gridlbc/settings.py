"""How to solve: :class:`SolverSettings`, its named :data:`PRESETS`, and the default steps.

Settings are separate from the problem: the same :class:`gridlbc.Problem` can be solved with any
scheme (:data:`gridlbc.schemes.METHODS`), time step, storage and fitting reference.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from .problem import Problem
from .schemes import LINEAR_SOLVERS, METHODS


@dataclass(frozen=True)
class SolverSettings:
    """How to solve: scheme, time step, storage and progress.

    Parameters
    ----------
    method : str
        One of :data:`METHODS` (``"splitting"`` or ``"implicit"``).
    dt : float, optional
        Time step; rounded down so that it divides the horizon. Default: a Courant number
        (``max |a_k| Δt / h_k``) of ``courant`` for the splitting scheme, and 1 for the implicit
        one, with at least ``min_steps`` steps; with a state cost, the splitting's default is
        also short enough that one step's noise crosses at most half the distance over which
        the cost rises (:func:`gridlbc.schemes.splitting.cost_sampling_step`; a longer given
        ``dt`` is warned about).
    courant : float, optional
        Target Courant number for the default dt of the splitting scheme. The semi-Lagrangian
        error is O(Δt) from the splitting plus O(h²/Δt) from interpolating at every step, so
        small steps *add* numerical diffusion (plain) or pessimism (fitted). Default 6 for the
        plain drift, of the largest rate ``max_x max_k |a_k(x)| / h_k``; and 7 when it is fitted, of
        that rate's root mean square over the nodes (:mod:`gridlbc.schemes.splitting.scheme`;
        ``benchmarks/accuracy.py`` and ``benchmarks/gymnast.py`` measure both against the
        certified optimum).
    min_steps : int, optional
        At least this many steps over the horizon (default 50 plain, 10 fitted).
    store_every : int
        Keep every k-th slice (and always t = 0 and T); z between them is interpolated linearly
        in time (which keeps superposition exact). This costs policy accuracy where the dynamics
        are fast (``benchmarks/gymnast.py --memory`` measures it). Prefer ``mmap_dir`` or float32
        slices when memory is short and the states that matter keep z above 1e-38 of the
        slice maximum.
    dtype : str
        ``"float64"`` or ``"float32"`` for the stored slices (the time stepping is float64).
        Slices are max-normalised, so float32 keeps 7 significant digits down to 1e-38 of each
        slice's maximum and flushes only values below ~1e-45 of it to zero (value +inf there);
        how many were flushed is reported in ``diagnostics.flushed_values``.
    progress : bool or None
        Print a progress bar (steps, elapsed, ETA, node-steps/s) to stderr: True always, False
        never, None (default) once the march has taken :data:`gridlbc.progress.DELAY` seconds.
    mmap_dir : str, optional
        Keep the slices in an (unlinked) memory-mapped file in this directory instead of RAM.
    linear_solver : str
        For ``method="implicit"``: one of :data:`gridlbc.schemes.implicit.LINEAR_SOLVERS` (``"auto"``:
        sparse LU for small 2D grids, Gauss–Seidel sweeps otherwise).
    fitting : "auto", None, "terminal" or a terminal cost
        For ``method="splitting"``: fit the drift's interpolation to a reference desirability
        φ = exp(−g_ref/λ) (:mod:`gridlbc.schemes.splitting`, "Exponential fitting"): exact where z ∝ φ,
        far less numerical diffusion where v is steep. ``"auto"`` (the default): ``"terminal"``
        for a scheme that supports fitting, else None. ``None``: plain barycentric
        interpolation, an operator independent of the terminal cost (separately solved
        solutions then combine exactly). ``"terminal"``: g_ref is the problem's terminal cost
        (for :func:`solve_many`, the composite g_ref = −λ log Σ_i exp(−g_i/λ)). A callable g(x):
        that cost. The diffusion is fitted to the same reference, and a single solve fitted to
        its own terminal cost runs in the log domain and interpolates v (no underflow at any
        temperature). The step stays linear in z for a fixed reference, so superposition is exact
        among solutions that share it; :func:`gridlbc.combine` combines solutions fitted to
        different references through their values (``exact`` False).
    error_estimate : bool
        Also solve on the embedded grid (every other node, step 2Δt) so that the solution
        carries an a-posteriori estimate of its error (:meth:`gridlbc.Solution.error_estimate`,
        :mod:`gridlbc.accuracy`), and warn when it exceeds
        :data:`gridlbc.accuracy.DEFAULT_TOLERANCE` where it matters. Default True; it costs
        about 2^−(d+1) of the solve.
    """

    method: str = "splitting"
    dt: float | None = None
    courant: float | None = None
    min_steps: int | None = None
    store_every: int = 1
    dtype: str = "float64"
    progress: bool | None = None
    mmap_dir: str | None = None
    linear_solver: str = "auto"
    fitting: object = "auto"
    error_estimate: bool = True

    @property
    def scheme(self):
        """The :class:`gridlbc.schemes.Scheme` named by ``method``."""
        return METHODS[self.method]

    def reference_rows(self, n_rhs: int) -> int:
        """Rows solved besides ``n_rhs`` terminal costs: one for a fitting reference that is not
        one of them (:func:`~gridlbc.settings.is_own_reference`), else none."""
        fitted = self.reference is not None
        return 1 if fitted and not is_own_reference(self.reference, n_rhs) else 0

    @property
    def reference(self):
        """The fitting reference actually used: ``fitting`` with ``"auto"`` resolved (None,
        ``"terminal"`` or a cost)."""
        if isinstance(self.fitting, str) and self.fitting == "auto":
            return "terminal" if METHODS[self.method].supports_fitting else None
        return self.fitting

    def __post_init__(self):
        if self.method not in METHODS:
            raise ValueError(
                f"unknown method {self.method!r}: choose one of {', '.join(sorted(METHODS))}"
            )
        if self.dt is not None and not (np.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt must be positive and finite, got {self.dt}")
        if self.courant is not None and not (self.courant > 0):
            raise ValueError(f"courant must be positive, got {self.courant}")
        if (self.min_steps is not None and int(self.min_steps) < 1) or int(self.store_every) < 1:
            raise ValueError("min_steps and store_every must be at least 1")
        try:  # numpy's names and types too: np.float32, "f4", np.dtype("float32")
            dtype = None if self.dtype is None else np.dtype(self.dtype).name
        except TypeError:
            dtype = None
        if dtype not in ("float64", "float32"):
            raise ValueError(f"dtype must be 'float64' or 'float32', got {self.dtype!r}")
        object.__setattr__(self, "dtype", dtype)
        if self.linear_solver not in LINEAR_SOLVERS:
            raise ValueError(
                f"linear_solver must be one of {', '.join(LINEAR_SOLVERS)}, "
                f"got {self.linear_solver!r}"
            )
        if not (
            self.fitting is None or self.fitting in ("auto", "terminal") or callable(self.fitting)
        ):
            raise ValueError(
                f"fitting must be 'auto', None, 'terminal' or a terminal cost g(x), "
                f"got {self.fitting!r}"
            )
        if self.reference is not None and not METHODS[self.method].supports_fitting:
            fitted = [name for name, scheme in METHODS.items() if scheme.supports_fitting]
            raise ValueError(
                f"fitting applies to method={' or '.join(map(repr, fitted))}, not "
                f"{self.method!r}: drop fitting or give method={' or '.join(map(repr, fitted))}"
            )
        if self.linear_solver != "auto" and not METHODS[self.method].supports_linear_solver:
            solving = [name for name, scheme in METHODS.items() if scheme.supports_linear_solver]
            raise ValueError(
                f"linear_solver applies to method={' or '.join(map(repr, solving))}, not "
                f"{self.method!r}, which solves no linear system: drop linear_solver or give "
                f"method={' or '.join(map(repr, solving))}"
            )
        if self.mmap_dir is not None and not os.path.isdir(self.mmap_dir):
            raise ValueError(f"mmap_dir must be an existing directory, got {self.mmap_dir!r}")


PRESETS = {
    "default": SolverSettings(),
    "reference": SolverSettings(method="implicit", courant=1.0),
    "fast": SolverSettings(courant=14.0, min_steps=5),
}
"""Named settings; pass ``settings="fast"`` etc. to :func:`solve`. ``"default"``: the library's
most accurate per second (the fitted splitting). ``"reference"``: the implicit upwind scheme at
Courant 1, first order: a baseline to compare a scheme with, not the most accurate.
``"fast"``: the default at Courant 14 (twice the fitted default's 7) and at least 5 steps, so
about half its steps where the drift sets the step: less accurate, and its error estimate says
by how much (it warns as the default does). It names no method, so a task with an exit set and
a horizon is solved by the implicit march, as by default
(``gridlbc.solver.settings_for``)."""


def resolve_settings(settings, options) -> SolverSettings:
    """``settings`` (None: the default preset; a preset name; a SolverSettings) with ``options``
    (SolverSettings fields) overriding it; unknown names are errors that list the valid ones."""
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
            f"{', '.join(fields)} (and tol=, states=, times=, max_nodes=, max_seconds= for a "
            "solve to a tolerance)"
        )
    return SolverSettings(**{**settings.__dict__, **options})


def is_own_reference(fitting, n_rhs: int) -> bool:
    """A single terminal cost fitted to itself is its own reference: no extra row is solved."""
    return fitting == "terminal" and n_rhs == 1


def memory_estimate(
    problem: Problem, settings: SolverSettings, n_slices: int, n_rhs: int = 1
) -> dict[str, int]:
    """Bytes a solve will hold: stored slices (and the fitting reference's, when it is a row of
    its own), working arrays (two float64 copies of z and the terminal data) and the step
    operator; ``"ram"`` sums what must fit in memory (the slices
    live on disk when ``mmap_dir`` is set)."""
    grid = problem.require_grid("solve")
    fitted = settings.reference is not None
    rows = n_rhs + settings.reference_rows(n_rhs)
    stored = n_slices * rows * grid.size * np.dtype(settings.dtype).itemsize  # + log φ, fitted
    # + log φ, the curvature term and (at most two bytes per node) its stencils' places, fitted
    curved = 2.25 if fitted else 0
    working = int((3 * rows + grid.ndim + curved) * grid.size * 8)
    operator = settings.scheme.estimate_bytes(grid)
    ram = working + operator + (0 if settings.mmap_dir else stored)
    return {"stored": stored, "working": working, "operator": operator, "ram": ram}
