"""A self-contained web page where linear Bellman combination happens live (``gridlbc interactive``).

The page embeds the components' stored desirability slices z_i = Z_i e^{ℓ_i} (base64, float32 or
float64) and evaluates, in the browser, exactly what :func:`gridlbc.combine` evaluates on them:

    z_i(x, t) = Σ_s τ_s(t) I[Z_{i,s}](x)                     (barycentric, Kuhn triangulation)
    α_i       = w_i z_i / Σ_j w_j z_j,     v = −λ log Σ_i w_i z_i
    u         = λ R⁻¹ Σ_i w_i I[Bᵀ∇z_i] / Σ_i w_i z_i       (= Σ_i α_i u_i)

with the per-slice log-scales, linear interpolation in time, periodic wrap and clamping of
:mod:`gridlbc.interpolate` and :mod:`gridlbc.solution`, and ∇z by the same finite differences.
Weights come from sliders or from :func:`gridlbc.projection` of a clicked goal (the same Gram
system, closed form or quadrature on the embedded grid); a click starts the combined
controller's deterministic rollout (:func:`gridlbc.simulate` with ``noise=False``: Euler steps
of T/300, periodic coordinates wrapped).

Large solutions are *decimated* before embedding (:func:`decimate`): the coarser solution's
slices are the original's own evaluation at the coarse nodes and a subset of its stored times,
so the page is exact for the decimated solutions and as accurate as that interpolation for the
originals. :func:`write_page` reports both.

Supported systems: 2-D :class:`~gridlbc.systems.Pendulum` and :class:`~gridlbc.systems.PointMass`
(the page needs their drift for the rollout and a 2-D state for the heat maps).
"""

from __future__ import annotations

import base64
import json
import math
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

import numpy as np

from ..backends import REFERENCE_FLOOR
from ..combine import check_components, check_weights
from ..costs import Constant, Quadratic
from ..grid import Axis, Grid
from ..io import quadratic_record, region_record
from ..project import CONDITION_LIMIT, NEGATIVE_TOLERANCE, RESIDUAL_TOLERANCE, SUM_TOLERANCE
from ..representation import LinearZ, LogZ, RelativeZ
from ..solution import Solution
from ..systems import Pendulum, PointMass

SUPPORTED_SYSTEMS = (Pendulum, PointMass)
"""Systems whose drift the page implements (for the rollout)."""

DEFAULT_MAX_BYTES = 16_000_000
"""Budget for the embedded slices (before base64, which adds a third): solutions up to this size
are embedded whole, so that the page computes exactly what ``gridlbc.combine`` computes on them."""

DEFAULT_TIMES = 41
"""Stored time slices kept per component when a solution is too large to embed whole."""

ROLLOUT_STEPS = 300
"""Euler steps of the page's rollout over the horizon (``gridlbc.simulate``'s default)."""

STATIONARY_ROLLOUT_TIME = 10.0
"""The page's rollout of a first-exit (stationary) solution stops at the exit set or after this
time."""

RASTER = (320, 240)
"""Evaluation points of each heat map, (horizontal, vertical)."""


def _slice_indices(n_stored: int, n_times: int) -> np.ndarray:
    """At most ``n_times`` stored slices, always the first and the last, denser towards the
    horizon T where z changes fastest: slice (S − 1)(1 − (1 − k/K)²), k = 0 … K, rounded
    (the time to go shrinks quadratically), with the largest K that keeps ``n_times``."""
    if n_times >= n_stored:
        return np.arange(n_stored)
    best = np.array([0, n_stored - 1])
    for K in range(1, 4 * n_stored):
        k = np.arange(K + 1) / K
        kept = np.unique(np.round((n_stored - 1) * (1 - (1 - k) ** 2)).astype(int))
        if kept.size > n_times:
            break
        best = kept
    return best


def decimate(
    solution: Solution, nodes=None, n_times: int | None = None, dtype: str = "float32"
) -> Solution:
    """A coarser Solution built from ``solution``'s own evaluation.

    Parameters
    ----------
    solution : Solution
    nodes : int or sequence of int, optional
        Nodes per axis of the coarse grid (one number for all axes; never more than the
        original's). The coarse grid spans the same box: a periodic axis keeps its period with
        ``n`` nodes, a bounded axis keeps ``[lo, hi]``. Default: the original's.
    n_times : int, optional
        At most this many stored slices, always t = 0 and T, closer together towards T where z
        changes fastest (see :func:`_slice_indices`). Default: all.
    dtype : str
        ``"float32"`` (7 significant digits; values below ~1e-45 of their slice's maximum, where
        v exceeds the slice's minimum by more than 103 λ, flush to zero and count in
        ``diagnostics.flushed_values``) or ``"float64"``.

    Returns
    -------
    Solution
        Slices Z(x_node, t_j) = z(x_node, t_j) / max_node z(·, t_j) with z the original's
        interpolant (:meth:`Solution.scaled_fields`), on the coarse grid at the kept times.
        The original interpolates log z or is fitted to a reference: the result is relative to a
        reference too (:class:`~gridlbc.representation.RelativeZ`), the original's interpolated
        log z or log φ at the coarse nodes, so that the page evaluates it as the original is
        evaluated.
    """
    grid = solution.grid
    shape = grid.shape if nodes is None else tuple(np.atleast_1d(np.asarray(nodes, dtype=int)))
    if len(shape) == 1:
        shape = shape * grid.ndim
    if len(shape) != grid.ndim:
        raise ValueError(
            f"nodes must be one count or {grid.ndim} (one per axis), got {list(shape)}"
        )
    if any(int(n) < 3 for n in shape):
        raise ValueError(f"nodes must be at least 3 per axis, got {list(shape)}")
    coarse = Grid(
        [Axis(a.lo, a.hi, min(int(n), a.n), a.periodic, a.name) for a, n in zip(grid.axes, shape)]
    )
    n_stored = len(solution.times)
    if n_times is not None and (int(n_times) < 2) and n_stored > 1:
        raise ValueError(f"n_times must be at least 2 (t = 0 and T), got {n_times}")
    kept = _slice_indices(n_stored, n_stored if n_times is None else int(n_times))
    if dtype not in ("float32", "float64"):
        raise ValueError(f"dtype must be 'float32' or 'float64', got {dtype!r}")
    X = coarse.nodes()
    slices = np.empty((kept.size, coarse.size))
    scales = np.empty(kept.size)
    fitted = not isinstance(solution.representation, LinearZ)
    reference = (
        RelativeZ(np.empty((kept.size, coarse.size), dtype), np.empty(kept.size))
        if fitted
        else None
    )
    for r, j in enumerate(kept):
        fields = solution.fields(X, solution.times[j], gradient=False)
        L, z, _ = fields.scaled()
        top = z.max()
        if not top > 0:
            raise ValueError(
                f"the desirability underflowed at every coarse node at t = "
                f"{solution.times[j]:g}: the solution cannot be decimated"
            )
        slices[r] = z / top
        scales[r] = L + math.log(top)
        # fitted: log φ at the coarse nodes, the original's own log z or its I[log φ]
        if reference is not None:
            ell = fields.log_base
            assert ell is not None  # LogZ and RelativeZ interpolate a log-factor
            ell = np.maximum(
                ell, ell.max() + math.log(REFERENCE_FLOOR)
            )  # finite where z underflowed
            reference.log_slices[r] = ell - ell.max()
            reference.log_scales[r] = ell.max()
    stored = slices.astype(dtype)
    flushed = int(np.count_nonzero(slices) - np.count_nonzero(stored))
    diagnostics = replace(
        solution.diagnostics,
        stored_bytes=int(stored.nbytes),
        flushed_values=flushed,
        underflow_nodes=int(np.count_nonzero(stored[0] == 0)),
    )
    return type(solution)(
        solution.problem.replace(grid=coarse),
        solution.times[kept].copy(),
        stored,
        scales,
        diagnostics,
        solution.operator,
        LinearZ() if reference is None else reference,
    )


@dataclass(frozen=True)
class Embedding:
    """What a page embeds: the (possibly decimated) components and how they were reduced.

    Attributes
    ----------
    components : tuple of Solution
        The solutions the page evaluates (``gridlbc.combine`` of these is what it shows).
    source_shape : tuple of int
        Nodes per axis of the original solutions.
    source_times : int
        Stored slices of the original solutions.
    decimated : bool
        Whether ``components`` are coarser than the originals (else they are the originals).
    """

    components: tuple[Solution, ...]
    source_shape: tuple[int, ...]
    source_times: int
    decimated: bool

    @property
    def shape(self) -> tuple[int, ...]:
        return self.components[0].grid.shape

    @property
    def n_times(self) -> int:
        return len(self.components[0].times)

    @property
    def dtype(self) -> str:
        return str(self.components[0].slices.dtype)

    @property
    def nbytes(self) -> int:
        return sum(int(s.slices.nbytes) for s in self.components) + sum(
            int(r.log_slices.nbytes) for r in _shared_references(self.components)[0]
        )

    def describe(self) -> str:
        shape = "×".join(map(str, self.shape))
        text = (
            f"{len(self.components)} components × {self.n_times} time slices × {shape} nodes "
            f"({self.dtype}, {self.nbytes / 1e6:.2f} MB)"
        )
        if self.decimated:
            source = "×".join(map(str, self.source_shape))
            text += f", decimated from {source} nodes × {self.source_times} slices"
        flushed = sum(s.diagnostics.flushed_values for s in self.components)
        if flushed:
            text += (
                f"; {flushed} nodal values (v more than 103 λ above the slice's minimum) "
                "flushed to zero by float32, grey on the maps (use float64 to keep them)"
            )
        return text


def embed(
    solutions, nodes=None, n_times=None, max_bytes: int = DEFAULT_MAX_BYTES, dtype: str = "float32"
) -> Embedding:
    """Choose what to embed: the solutions as they are when they fit in ``max_bytes``, else
    :func:`decimate` them to ``dtype``, at most ``n_times`` (default :data:`DEFAULT_TIMES`)
    slices and the largest common fraction of the nodes per axis that fits; ``nodes`` or
    ``n_times`` given: decimate to them."""
    solutions, _ = check_components(solutions)
    first = solutions[0]
    if any(not np.array_equal(s.times, first.times) for s in solutions):
        raise ValueError(
            "the page needs one time grid: solve all components with the same dt and "
            "store_every (their stored times differ)"
        )
    system = first.problem.system
    if not isinstance(system, SUPPORTED_SYSTEMS) or first.grid.ndim != 2:
        raise ValueError(
            f"gridlbc interactive supports 2-D Pendulum and PointMass solutions (the page needs "
            f"their drift and a 2-D state for the heat maps), got {type(system).__name__} on "
            f"{first.grid.describe()}"
        )
    max_bytes = int(max_bytes)
    if max_bytes <= 0:
        raise ValueError(f"max_bytes must be positive, got {max_bytes}")
    shape, n_stored = first.grid.shape, len(first.times)
    references = _shared_references(solutions)[0]
    whole = sum(int(s.slices.nbytes) for s in solutions) + sum(
        int(r.log_slices.nbytes) for r in references
    )
    if nodes is None and n_times is None and whole <= max_bytes:
        # The page interpolates z, or z relative to a reference: a solution that stores log z is
        # converted to z at its own nodes, fitted to its own log z, and reported as decimated
        # (the page is exact for the converted solution, and the report gives its error against
        # the original).
        converted = [isinstance(s.representation, LogZ) for s in solutions]
        return Embedding(
            tuple(decimate(s, None, None, dtype) if c else s for s, c in zip(solutions, converted)),
            shape,
            n_stored,
            any(converted),
        )
    if n_times is None:
        n_times = min(n_stored, DEFAULT_TIMES)
    if nodes is None:
        # a decimated solution that interpolates log z or a reference keeps a reference: the
        # references of solutions solved together are one, embedded once
        rows = (
            len(solutions)
            + len(references)
            + sum(isinstance(s.representation, LogZ) for s in solutions)
        )
        per_node = rows * _slice_indices(n_stored, int(n_times)).size * np.dtype(dtype).itemsize
        top = max(shape)
        for m in range(top, 2, -1):
            nodes = [max(3, round(n * m / top)) for n in shape]
            if per_node * math.prod(nodes) <= max_bytes:
                break
    return Embedding(
        tuple(decimate(s, nodes, n_times, dtype) for s in solutions), shape, n_stored, True
    )


def _page_cost(cost):
    """A Quadratic as the page reads it (:func:`gridlbc.io.quadratic_record` with ``None`` for
    the periods of non-periodic coordinates: JSON has no inf), else ``None``."""
    if not isinstance(cost, Quadratic):
        return None
    record = quadratic_record(cost)
    if record["periods"] is not None:
        record["periods"] = [p if math.isfinite(p) else None for p in record["periods"]]
    return record


def _page_region(record):
    """An exit set's :func:`gridlbc.io.region_record` as the page reads it (``None`` for an
    infinite bound or radius: JSON has no inf), or ``None`` where E is not made of the library's
    shapes (the page then knows it by its nodes)."""
    if record is None:
        return None
    if "union" in record:
        return {"union": [_page_region(part) for part in record["union"]]}
    ((shape, vectors),) = record.items()
    return {shape: {k: [x if math.isfinite(x) else None for x in v] for k, v in vectors.items()}}


def _page_exit_cost(solution: Solution) -> dict:
    """A component's exit cost g_E as the page reads it: a quadratic (:func:`_page_cost`) or a
    constant exactly, anything else by its values at the nodes, which the page interpolates."""
    cost = solution.problem.exit_cost
    if isinstance(cost, Constant):
        return {"constant": float(cost.value)}
    quadratic = _page_cost(cost)
    if quadratic is not None:
        return {"quadratic": quadratic}
    return {"nodes": _base64(solution.problem.exit_values().astype(solution.slices.dtype))}


def _colormap(name: str) -> str:
    """256 RGB entries of a matplotlib colormap as a hex string."""
    from matplotlib import colormaps

    rgb = (colormaps[name](np.linspace(0, 1, 256))[:, :3] * 255).round().astype(np.uint8)
    return rgb.tobytes().hex()


def _component_label(solution: Solution, i: int) -> str:
    cost = solution.problem.terminal_cost
    if isinstance(cost, Quadratic):
        centre = ", ".join(f"{c:.3g}" for c in cost.center)
        return f"goal {i + 1}: c = ({centre})"
    return f"component {i + 1}"


def _shared_references(solutions) -> tuple[list[RelativeZ], list[int | None]]:
    """The distinct fitting references of ``solutions`` (equal arrays count once: solutions
    solved together, or decimated from such, share theirs) and, per solution, the index of its
    own in that list (None without one)."""
    distinct: list[RelativeZ] = []
    index: list[int | None] = []
    for s in solutions:
        ref = s.reference
        if ref is None:
            index.append(None)
            continue
        for k, other in enumerate(distinct):
            if other is ref or (
                np.array_equal(other.log_scales, ref.log_scales)
                and np.array_equal(other.log_slices, ref.log_slices)
            ):
                index.append(k)
                break
        else:
            index.append(len(distinct))
            distinct.append(ref)
    return distinct, index


def _base64(array: np.ndarray) -> str:
    """The array's bytes, little-endian, as base64 text."""
    return base64.b64encode(
        np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<")).tobytes()
    ).decode("ascii")


def page_data(
    embedding: Embedding,
    weights=None,
    state=None,
    title: str | None = None,
    labels=None,
    note: str = "",
) -> dict:
    """The JSON document the page reads (everything it shows comes from here)."""
    comps = embedding.components
    first = comps[0]
    problem, grid, system = first.problem, first.grid, first.problem.system
    w = check_weights(weights, len(comps))
    x0 = (
        grid.lo + 0.5 * (grid.hi - grid.lo)
        if state is None
        else grid.check_states(state, "state")[0]
    )
    B = np.asarray(system.input_matrix(grid.node_coordinates([0])), dtype=float)[0]
    # A stationary (first-exit) solution has one slice and no time: the page, made for time
    # slices, gets it twice over [0, STATIONARY_ROLLOUT_TIME] (so z does not change with t). A
    # problem with an exit set E gives the page E (its shapes, where it is made of the library's,
    # else its nodes: a state is in E where the interpolated membership of the nodes is at least
    # 1/2, as gridlbc.load reads a callable E) and each component's exit cost g_E (a quadratic or
    # a constant, else its values at the nodes, interpolated); the page gives z = exp(-g_E/lambda)
    # in E and stops its rollout there.
    stationary = problem.stationary
    horizon = STATIONARY_ROLLOUT_TIME if stationary else problem.horizon
    times = [0.0, horizon] if stationary else first.times.tolist()

    def stored(array: np.ndarray) -> np.ndarray:
        return np.repeat(array, 2, axis=0) if stationary else array

    names = [a.name or n for a, n in zip(grid.axes, system.state_names)]
    labels = labels or [_component_label(s, i) for i, s in enumerate(comps)]
    references = _shared_references(comps)
    return {
        "format": "gridlbc-interactive",
        "title": title or f"Linear Bellman combination: {type(system).__name__}",
        "note": note,
        "system": {"name": type(system).__name__, "parameters": system.parameters()},
        "axes": [
            {"lo": a.lo, "hi": a.hi, "n": a.n, "periodic": a.periodic, "name": nm}
            for a, nm in zip(grid.axes, names)
        ],
        "horizon": horizon,
        "stationary": stationary,
        "exit": None
        if problem.exit is None
        else base64.b64encode(problem.exit_mask().astype(np.uint8).tobytes()).decode("ascii"),
        "exit_region": _page_region(region_record(problem.exit)),
        "temperature": problem.temperature,
        "R": problem.R.tolist(),
        "R_inv": problem.R_inv.tolist(),
        "B": B.tolist(),
        "state_cost": None
        if problem.state_cost is None
        else (_page_cost(problem.state_cost) or "other"),
        "times": times,
        "dtype": embedding.dtype,
        "components": [
            {
                "label": lab,
                "terminal_cost": _page_cost(s.problem.terminal_cost),
                "log_scales": stored(s.log_scales).tolist(),
                "slices": _base64(stored(s.slices)),
                "reference": k,
                "exit_cost": None if problem.exit is None else _page_exit_cost(s),
            }
            for lab, s, k in zip(labels, comps, references[1])
        ],
        "references": [
            {
                "log_scales": r.log_scales.tolist(),
                "log_slices": _base64(r.log_slices.astype(first.slices.dtype)),
            }
            for r in references[0]
        ],
        "initial": {"weights": w.tolist(), "state": np.asarray(x0, float).tolist(), "time": 0.0},
        "embedding": embedding.describe(),
        "raster": list(RASTER),
        "rollout_steps": ROLLOUT_STEPS,
        "projection": {
            "negative_tolerance": NEGATIVE_TOLERANCE,
            "sum_tolerance": SUM_TOLERANCE,
            "residual_tolerance": RESIDUAL_TOLERANCE,
            "condition_limit": CONDITION_LIMIT,
        },
        "colormaps": {"value": _colormap("viridis"), "policy": _colormap("RdBu_r")},
    }


def page_html(data: dict) -> str:
    """The page: the template with its script, style and ``data`` inlined."""
    files = resources.files(__package__)
    template = files.joinpath("page.html").read_text(encoding="utf-8")
    script = files.joinpath("page.js").read_text(encoding="utf-8")
    style = files.joinpath("page.css").read_text(encoding="utf-8")
    # "<" escaped so that no string in the data can close the script element
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")
    title = data["title"].replace("&", "&amp;").replace("<", "&lt;")
    return (
        template.replace("{{TITLE}}", title)
        .replace("{{STYLE}}", style)
        .replace("{{DATA}}", payload)
        .replace("{{SCRIPT}}", script)
    )


@dataclass(frozen=True)
class PageReport:
    """What :func:`write_page` wrote.

    Attributes
    ----------
    path : Path
    size : int
        Bytes of the page.
    embedding : Embedding
    max_value_error, median_value_error : float
        max and median |v_embedded − v_original| of the initial weights' combination at 2000
        random states and five times (0 when not decimated; inf where only one underflowed).
    max_value_spread : float
        The largest max − min of the original combined value at those states, for scale.
    """

    path: Path
    size: int
    embedding: Embedding
    max_value_error: float
    median_value_error: float
    max_value_spread: float

    def summary(self) -> str:
        text = f"wrote {self.path} ({self.size / 1e6:.2f} MB): {self.embedding.describe()}"
        if self.embedding.decimated:
            text += (
                f"; the page evaluates gridlbc.combine exactly on the decimated solutions, "
                f"which differ from the originals in v by "
                f"{self.median_value_error:.3g} (median) and at most "
                f"{self.max_value_error:.3g} (v spans {self.max_value_spread:.3g}) at 2000 "
                "random states and 5 times"
            )
        return text


def _decimation_error(originals, embedding: Embedding, weights, seed: int = 0):
    """max and median |v_embedded − v_original| of the combination over 2000 random states at
    each of t = 0 and four random times, and the range of the original's value there."""
    from ..combine import combine

    if not embedding.decimated:
        return 0.0, 0.0, 0.0
    grid = originals[0].grid
    rng = np.random.default_rng(seed)
    X = rng.uniform(grid.lo, grid.hi, (2000, grid.ndim))
    full, small = combine(originals, weights), combine(embedding.components, weights)
    errors: list[np.ndarray] = []
    spread = 0.0
    problem = originals[0].problem
    times = [0.0] if problem.stationary else np.append(0.0, rng.uniform(0, problem.horizon, 4))
    for t in times:
        a, b = full.value(X, t), small.value(X, t)
        ok = np.isfinite(a) & np.isfinite(b)
        if np.any(np.isfinite(a) != np.isfinite(b)):
            return math.inf, math.inf, float(np.ptp(a[ok])) if ok.any() else math.inf
        errors.append(np.abs(a - b)[ok])
        spread = max(spread, float(np.ptp(a[ok])))
    gaps = np.concatenate(errors)
    return float(gaps.max()), float(np.median(gaps)), spread


def write_page(
    solutions,
    path,
    *,
    weights=None,
    state=None,
    nodes=None,
    n_times=None,
    max_bytes: int = DEFAULT_MAX_BYTES,
    dtype: str = "float32",
    title: str | None = None,
    labels=None,
    note: str = "",
) -> PageReport:
    """Write the interactive page for ``solutions`` (sequence of :class:`gridlbc.Solution`).

    ``weights`` and ``state`` are the initial blend weights (default all ones) and rollout start
    (default the box centre); ``nodes``, ``n_times``, ``max_bytes`` and ``dtype`` choose what is
    embedded (:func:`embed`). Returns a :class:`PageReport` with the page size and, for decimated
    solutions, how far the embedded combination is from the original one.
    """
    solutions = tuple(solutions)
    embedding = embed(solutions, nodes, n_times, max_bytes, dtype)  # validates the components
    w = check_weights(weights, len(solutions))
    data = page_data(embedding, w, state, title, labels, note)
    path = Path(path)
    html = page_html(data)
    path.write_text(html, encoding="utf-8")
    error, median, spread = _decimation_error(solutions, embedding, w)
    return PageReport(path, len(html.encode("utf-8")), embedding, error, median, spread)
