"""The ``gridlbc demo`` job: solve, combine, verify and draw, on the pendulum swing-up.

1. Solve the swing-up to the upright (T = 3, λ = 1, g = xᵀdiag(10, 0.5)x) on a θ × ω grid,
   with the plain splitting scheme and with its drift fitted to the terminal cost.
2. Check each solver's prediction v(x₀, 0) = −λ log z(x₀, 0) against the certified optimum
   v*(x₀) (:func:`gridlbc.certify`, importance sampling with the solver's own policy as the
   proposal), and report what that policy costs: the prediction's error is measured against
   the truth, not against the policy's own rollouts.
3. Solve two goals (upright leaning left / right) with one fitted operator, combine them with
   w = (1, 1) and compare with a direct solve of the composite terminal cost
   g = −λ log Σ exp(−g_i/λ) with the same reference: superposition holds to rounding.
4. Write value, desirability and policy heat maps (cost space vs reward space) to ``out``.
"""

from __future__ import annotations

import math
import time
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from ..certify import certify
from ..combine import combine
from ..costs import Quadratic
from ..errors import GridlbcWarning
from ..interactive import PageReport, write_page
from ..solver import solve, solve_many
from .convergence import sde_optimum
from .problems import SWINGUP_START, swingup_problem
from .verify import SWINGUP_ROLLOUT_DT


@contextmanager
def _noted(say):
    """Print the library's warnings raised in the block as part of the demo's story (the
    solve's own words up to where it points at the docs), not as Python's tracebacks."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", GridlbcWarning)
        yield
    for w in caught:
        if issubclass(w.category, GridlbcWarning):
            say(f"   the solve warns ({w.category.__name__}): {str(w.message).split(', see ')[0]}")
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def plot_fields(solution, path: Path, title: str, t: float = 0.0):
    """Value v, desirability z and policy u* of a 2-D solution at time t, side by side."""
    import matplotlib.pyplot as plt

    grid = solution.grid
    th = np.linspace(grid.axes[0].lo, grid.axes[0].hi, 241)
    om = np.linspace(grid.axes[1].lo, grid.axes[1].hi, 241)
    X = np.stack(np.meshgrid(th, om, indexing="xy"), -1).reshape(-1, 2)
    v = solution.value(X, t).reshape(om.size, th.size)
    z = np.exp(-(v - v.min()) / solution.temperature)
    u = solution.policy(X, t)[:, 0].reshape(om.size, th.size)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True)
    panels = [
        (v, "value v = −λ log z (cost space)", "viridis"),
        (z, "desirability z / max z (reward space)", "magma"),
        (u, "policy u* = λR⁻¹Bᵀ∇z / z", "RdBu_r"),
    ]
    extent = (th[0], th[-1], om[0], om[-1])
    for ax, (field, label, cmap) in zip(axes, panels):
        if cmap == "RdBu_r":
            lim = np.percentile(np.abs(field), 99)
            im = ax.imshow(
                field, origin="lower", extent=extent, aspect="auto", cmap=cmap, vmin=-lim, vmax=lim
            )
        else:
            im = ax.imshow(field, origin="lower", extent=extent, aspect="auto", cmap=cmap)
        ax.set_title(label)
        ax.set_xlabel("θ (rad from upright)")
        ax.set_ylabel("ω (rad/s)")
        fig.colorbar(im, ax=ax)
    fig.suptitle(title)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run_demo(
    out: Path, grid_size: int = 201, progress: bool = True, n_samples: int = 400, seed: int = 1
) -> dict:
    """Run the demo; returns the measured numbers and writes figures to ``out``."""
    import matplotlib

    matplotlib.use("Agg")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    say = print if progress else (lambda *a, **k: None)
    results = {}

    problem = swingup_problem(grid_size)
    say(f"1. swing-up: {problem.describe()}")
    labels = {None: "plain ", "terminal": "fitted"}
    solutions, predictions = {}, {}
    for fitting, label in labels.items():
        with _noted(say):  # its warnings after its line
            sol = solutions[fitting] = solve(problem, progress=progress, fitting=fitting)
            predictions[fitting] = float(sol.value(SWINGUP_START, 0.0))
            d = sol.diagnostics
            say(
                f"   {label} {d.method}: {d.steps} steps of dt = {d.dt:.4f} in "
                f"{d.wall_time:.2f} s; predicted v(x0) = {predictions[fitting]:.3f}"
            )
    say(
        "2. the certified optimum v*(x0) of the SDE (Euler–Maruyama at dt and 2 dt, extrapolated to "
        "dt → 0) with each policy as proposal, and the policy's cost J at dt:"
    )
    for fitting, sol in solutions.items():
        started = time.perf_counter()
        predicted = predictions[fitting]
        cert = certify(
            problem,
            sol.policy,
            SWINGUP_START,
            n_samples=n_samples,
            dt=SWINGUP_ROLLOUT_DT,
            seed=seed,
            progress=False,
            richardson=True,
        )
        optimum, optimum_se = sde_optimum(cert)
        error = (predicted - optimum) / optimum
        say(
            f"   {labels[fitting]}: v* = {optimum:.3f} ± {optimum_se:.3f} "
            f"({cert.optimal_value:.3f} at dt = {cert.dt:g}; ESS {cert.effective_sample_size:.0f} "
            f"of {n_samples}), prediction {100 * error:+.1f} % of v*, policy cost J = "
            f"{cert.policy_cost:.3f} ± {cert.policy_cost_se:.3f} "
            f"({time.perf_counter() - started:.1f} s)"
        )
        prefix = "" if fitting else "plain_"
        results.update(
            {
                f"{prefix}predicted": predicted,
                f"{prefix}optimal_value": optimum,
                f"{prefix}optimal_value_se": optimum_se,
                f"{prefix}policy_cost": cert.policy_cost,
                f"{prefix}relative_error": error,
            }
        )
    sol = solutions["terminal"]
    d = sol.diagnostics

    goals = [Quadratic([-0.6, 0.0], [10.0, 0.5]), Quadratic([0.6, 0.0], [10.0, 0.5])]
    with _noted(say):  # the solves' warnings after the section's lines
        combined = combine(solve_many(problem, goals, fitting="terminal"))  # fitted to Σ_i h_i
        # the composite terminal cost g = −λ log Σ exp(−g_i/λ), fitted to the same reference
        direct = solve(combined.problem, fitting=combined.problem.terminal_cost)
        rng = np.random.default_rng(seed)
        X = np.column_stack([rng.uniform(-np.pi, np.pi, 2000), rng.uniform(-8, 8, 2000)])
        errs = {}
        for name in ("value", "policy"):
            a = getattr(combined, name)(X, 0.0)
            b = getattr(direct, name)(X, 0.0)
            errs[name] = float(np.max(np.abs(a - b) / np.maximum(np.abs(b), 1.0)))
        say(
            f"3. coordination of two goals (θ = ±0.6): combine vs direct composite solve, max "
            f"relative difference off-grid: value {errs['value']:.1e}, policy {errs['policy']:.1e}"
        )
        alpha = combined.blend_weights(np.array([[1.5, 0.0], [-1.5, 0.0]]), 0.0)
        say(
            f"   blend weights α at θ = +1.5: {alpha[0].round(3)}, at θ = −1.5: {alpha[1].round(3)}"
        )
    results.update(superposition_value=errs["value"], superposition_policy=errs["policy"])

    plot_fields(
        sol,
        out / "demo_swingup.png",
        f"Pendulum swing-up ({sol.grid.describe()}, {d.method}, fitted): t = 0",
    )
    plot_fields(
        combined,
        out / "demo_combined.png",
        "Linear Bellman combination of two goals θ = ±0.6 (w = 1, 1): t = 0",
    )
    say(f"4. figures written to {out}/demo_swingup.png and demo_combined.png")
    return results


# -- the built-in page of ``gridlbc interactive`` ---------------------------------------------

INTERACTIVE_GOALS = ((-0.4, 0.0), (0.4, 0.0), (math.pi, 0.0))
"""Goals (θ, ω) of the built-in page: upright leaning left, leaning right, hanging down."""

INTERACTIVE_GOAL_WEIGHTS = (4.0, 0.5)
"""diag W of each goal's g = (x − c)ᵀW(x − c): wide enough that projection interpolates between
the two upright goals (a target between them is represented with a residual below one half)."""

INTERACTIVE_HORIZON = 5.0
"""Long enough for the noise-free closed loop from the swing-up start to reach a goal (in the
demo's 3 s it stops short)."""

INTERACTIVE_WEIGHTS = (1.0, 1.0, 0.0)
"""Initial weights: swing up to either upright goal, the hanging one switched off."""

INTERACTIVE_LABELS = (
    "upright, leaning left (θ = −0.4)",
    "upright, leaning right (θ = +0.4)",
    "hanging down (θ = π)",
)


def interactive_demo(
    out, grid_size: int = 101, progress: bool = True, **page_options
) -> PageReport:
    """Write the built-in page of ``gridlbc interactive`` to ``out``.

    The swing-up pendulum (λ = 1, R = 1) over :data:`INTERACTIVE_HORIZON`, solved on
    ``grid_size`` θ nodes for the :data:`INTERACTIVE_GOALS` with one operator fitted to Σ_i h_i
    (so that they combine exactly), starting from near hanging down, decimated to 4 MB of slices
    (the page's size: docs page :doc:`benchmarks`). ``page_options`` go to :func:`gridlbc.interactive.write_page` (and override
    the demo's weights, state or size).
    """
    problem = swingup_problem(grid_size, horizon=INTERACTIVE_HORIZON)
    goals = [Quadratic(list(c), INTERACTIVE_GOAL_WEIGHTS) for c in INTERACTIVE_GOALS]
    solutions = solve_many(problem, goals, fitting="terminal", progress=progress)
    options: dict[str, Any] = {  # write_page's keywords, of several types
        "weights": INTERACTIVE_WEIGHTS,
        "state": SWINGUP_START,
        "max_bytes": 4_000_000,
        "labels": INTERACTIVE_LABELS,
        "title": "Linear Bellman combination, live: pendulum swing-up",
    }
    options.update(page_options)
    return write_page(solutions, out, **options)
