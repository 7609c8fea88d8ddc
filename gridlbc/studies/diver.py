"""The diver beyond the grid (paper §6.1–6.2, Figs. 6 and 8): trajectory-based linear Bellman
combination on the 8-D problem of :func:`gridlbc.studies.problems.diver_problem`.

Each component is a locally optimal dive (:func:`gridlbc.trajectory.optimize`) with its quadratic
value expansion and LQR tracker (:func:`gridlbc.trajectory.expand`). Two experiments:

- **Interpolation** (Fig. 6): an under-rotating dive (entry cost centred c = −δ) and an
  over-rotating one (c = +δ), combined to enter vertically (c = 0) with weights w from projecting
  exp(−ḡ/λ) onto the components' exp(−g_i/λ) (:func:`gridlbc.project`). The entry costs differ in
  θ1 alone, so the Gram matrix of the 8-D Gaussians is that of the θ1 marginals times one common
  factor, which cancels: the weights are those of the 1-D projection (wrapping is negligible
  where exp(−g/λ) is narrow against 2π).
- **Coordination** (Fig. 8): three vertical dives from take-off angular momenta κ = 0.85, 1 and
  1.15 of nominal, combined with w = 1, tested from κ in between and beyond.

Each controller (LBC, the naive blend Σ w_i u_i / Σ w_i, single trackers) is rolled out without
noise (the paper's setting) and judged by the target problem's cost J, the entry error and the
deterministic optimum from the same take-off; with the problem's noise, :func:`gridlbc.certify`
gives its cost and the certified optimum v* with the effective sample size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..certify import certify
from ..combine import combine, naive_blend
from ..costs import Quadratic
from ..project import projection
from ..simulate import simulate
from .problems import DIVER_ENTRY_WEIGHTS, diver_problem, diver_start


@dataclass(frozen=True)
class DiveRun:
    """A noise-free closed-loop dive and, optionally, its certificate under noise.

    Attributes
    ----------
    label : str
    momentum_scale : float
        κ of the take-off.
    times, states, controls : ndarray
        The rollout (``(k,)``, ``(k, 8)``, ``(k − 1, 3)``).
    cost : float
        J of the target problem, noise-free.
    entry_error : float
        |θ1(T)| wrapped, the arms' angle from vertical at entry (rad).
    shape_error : float
        ‖(θ2, θ3, θ4)(T)‖, how far from straight (rad).
    certificate : Certificate or None
        :func:`gridlbc.certify` of the controller on the noisy target problem.
    """

    label: str
    momentum_scale: float
    times: np.ndarray
    states: np.ndarray
    controls: np.ndarray
    cost: float
    entry_error: float
    shape_error: float
    certificate: object = None


def wrapped(angles) -> np.ndarray:
    """Angles into [−π, π)."""
    return np.mod(np.asarray(angles) + np.pi, 2 * np.pi) - np.pi


def dive_run(problem, policy, label, momentum_scale, dt, certify_samples=0, seed=0) -> DiveRun:
    """Roll ``policy`` out noise-free from the take-off κ = ``momentum_scale`` on ``problem``
    (and certify it with ``certify_samples`` noisy samples, if any)."""
    x0 = diver_start(momentum_scale)
    run = simulate(problem, policy, x0, dt=dt, noise=False)
    final = run.final_states[0]
    certificate = None
    if certify_samples:
        certificate = certify(problem, policy, x0, n_samples=certify_samples, dt=dt, seed=seed)
    return DiveRun(label, momentum_scale, run.times, run.states[0], run.controls[0],
                   float(run.costs[0]), float(abs(wrapped(final[0]))),
                   float(np.linalg.norm(wrapped(final[1:4]))), certificate)


def optimal_run(problem, trajectory, label, momentum_scale) -> DiveRun:
    """The deterministic optimum as a :class:`DiveRun` (its own tape, no feedback)."""
    final = trajectory.states[-1]
    return DiveRun(label, momentum_scale, trajectory.times, trajectory.states, trajectory.controls,
                   float(trajectory.cost), float(abs(wrapped(final[0]))),
                   float(np.linalg.norm(wrapped(final[1:4]))))


def interpolation_weights(offset: float, temperature: float):
    """The projection of the vertical entry onto entries at ∓``offset`` (θ1 marginals, see the
    module docstring): a :class:`gridlbc.Projection`."""
    w1 = DIVER_ENTRY_WEIGHTS[0]
    target = Quadratic([0.0], [w1])
    components = [Quadratic([-offset], [w1]), Quadratic([offset], [w1])]
    return projection(target, components, temperature=temperature)


@dataclass(frozen=True)
class DiverStudy:
    """Both experiments' runs, grouped by controller label."""

    offset: float
    weights: np.ndarray
    projection_residual: float
    interpolation: tuple[DiveRun, ...]
    coordination: tuple[DiveRun, ...]
    component_scales: tuple[float, ...]


def run_interpolation(optimize, expand, offset=0.3, dt=0.005, certify_samples=0, restarts=8,
                      seed=0, temperature=None):
    """Fig. 6: under- and over-rotating dives combined to enter vertically. Returns
    (projection, runs)."""
    kwargs = {} if temperature is None else {"temperature": temperature}
    target = diver_problem(0.0, **kwargs)
    x0 = diver_start(1.0)
    parts = []
    for c in (-offset, offset):
        problem = diver_problem(c, **kwargs)
        trajectory = optimize(problem, x0, restarts=restarts, seed=seed)
        parts.append((problem, trajectory, expand(problem, trajectory)))
    fit = interpolation_weights(offset, target.temperature)
    w = fit.weights
    runs = [dive_run(target, combine([p[2] for p in parts], w).policy, "LBC", 1.0, dt,
                     certify_samples, seed),
            dive_run(target, naive_blend([p[2] for p in parts], w).policy, "naive blend", 1.0,
                     dt, certify_samples, seed)]
    for name, (problem, trajectory, component) in zip(("under-rotating", "over-rotating"), parts):
        runs.append(dive_run(target, component.policy, f"{name} tracker", 1.0, dt,
                             certify_samples, seed))
    best = optimize(target, x0, restarts=restarts, seed=seed)
    runs.append(optimal_run(target, best, "vertical optimum", 1.0))
    return fit, runs


def run_coordination(optimize, expand, scales=(0.85, 1.0, 1.15), tests=None, dt=0.005,
                     certify_samples=0, restarts=8, seed=0, temperature=None):
    """Fig. 8: vertical dives from κ = ``scales`` combined with w = 1, tested from ``tests``
    (default eight κ from 0.8 to 1.2). Returns the runs."""
    kwargs = {} if temperature is None else {"temperature": temperature}
    problem = diver_problem(0.0, **kwargs)
    components = []
    for kappa in scales:
        trajectory = optimize(problem, diver_start(kappa), restarts=restarts, seed=seed)
        components.append(expand(problem, trajectory))
    lbc = combine(components).policy
    naive = naive_blend(components, np.ones(len(components))).policy
    single = components[list(scales).index(1.0)].policy
    tests = np.linspace(0.8, 1.2, 8) if tests is None else tests
    runs = []
    for kappa in tests:
        runs.append(dive_run(problem, lbc, "LBC", kappa, dt, certify_samples, seed))
        runs.append(dive_run(problem, naive, "naive blend", kappa, dt, certify_samples, seed))
        runs.append(dive_run(problem, single, "single tracker (κ = 1)", kappa, dt,
                             certify_samples, seed))
        best = optimize(problem, diver_start(kappa), restarts=restarts, seed=seed)
        runs.append(optimal_run(problem, best, "optimum", kappa))
    return runs


# -- pictures ---------------------------------------------------------------------------------

_FLIGHT = (1.0, 4.0, 9.81)
"""Horizontal and initial vertical speed of the centre of mass (m/s) and g, for drawing only: the
dynamics of the body about its centre of mass do not depend on them."""


def _world_points(states, times) -> np.ndarray:
    """Joint points ``(k, 5, 2)`` in the world: the body about a centre of mass on its parabola."""
    from .problems import diver

    vx, vy, g = _FLIGHT
    com = np.stack([vx * times, vy * times - 0.5 * g * times**2], axis=1)
    return diver().positions(states) + com[:, None, :]


def _draw_body(ax, points, color, alpha=1.0, lw=2.5):
    ax.plot(points[:, 0], points[:, 1], "-", color=color, alpha=alpha, lw=lw,
            solid_capstyle="round")
    ax.plot(points[0, 0], points[0, 1], "o", color=color, alpha=alpha, ms=3)  # the hands


def plot_study(interpolation, coordination, path=None):
    """Fig. 6 and Fig. 8 side by side: strobed dives of the interpolation experiment, and the
    entry poses over κ for LBC and the single tracker, with costs against κ."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 5.2))
    ax6, ax8, axc = axes
    colors = {"LBC": "tab:blue", "naive blend": "tab:red", "under-rotating tracker": "tab:olive",
              "over-rotating tracker": "tab:purple", "vertical optimum": "black",
              "single tracker (κ = 1)": "tab:orange", "optimum": "black"}
    shown = [r for r in interpolation if r.label in ("LBC", "naive blend")]
    for offset, run in zip((0.0, 2.2), shown):
        points = _world_points(run.states, run.times)
        for k in np.linspace(0, len(run.times) - 1, 7).astype(int):
            _draw_body(ax6, points[k] + [offset, 0], colors[run.label],
                       alpha=0.25 + 0.75 * k / (len(run.times) - 1))
        ax6.text(offset + 0.5, 2.4, f"{run.label}\nJ = {run.cost:.3g}, "
                 f"entry {np.degrees(run.entry_error):.0f}°", ha="center", fontsize=9)
    ax6.axhline(-1.9, color="tab:cyan", lw=1)
    ax6.set(aspect="equal", title="interpolation (Fig. 6): aim between under- and over-rotation",
            xticks=[], yticks=[])
    labels = ["LBC", "single tracker (κ = 1)"]
    kappas = sorted({r.momentum_scale for r in coordination})
    for row, label in enumerate(labels):
        for col, kappa in enumerate(kappas):
            run = next(r for r in coordination if r.label == label and r.momentum_scale == kappa)
            points = run.states[-1:]
            from .problems import diver

            body = diver().positions(points)[0] + [col * 0.9, -row * 2.6]
            _draw_body(ax8, body, colors[label])
        ax8.text(-0.6, -row * 2.6, label, rotation=90, va="center", ha="right", fontsize=9)
    for col, kappa in enumerate(kappas):
        ax8.text(col * 0.9, 1.4, f"κ {kappa:.2f}", ha="center", fontsize=8)
    ax8.set(aspect="equal", title="coordination (Fig. 8): entry poses, hands down is vertical",
            xticks=[], yticks=[])
    for label in ("LBC", "naive blend", "single tracker (κ = 1)", "optimum"):
        rows = sorted((r for r in coordination if r.label == label), key=lambda r: r.momentum_scale)
        axc.plot([r.momentum_scale for r in rows], [r.cost for r in rows], "o-",
                 color=colors[label], label=label, ms=4)
    axc.set(xlabel="take-off angular momentum κ (× nominal)", ylabel="noise-free cost J",
            yscale="log", title="coordination: cost against κ (components at 0.85, 1, 1.15)")
    axc.legend(fontsize=8)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def animate_dives(runs, path, fps: int = 25):
    """A GIF of the given :class:`DiveRun` s side by side (same times)."""
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    times = runs[0].times
    frames = np.minimum(np.searchsorted(times, np.arange(0.0, times[-1] + 1e-9, 1.0 / fps)),
                        len(times) - 1)
    frames = np.concatenate([frames, np.full(fps, frames[-1])])  # hold the entry for 1 s
    fig, axes = plt.subplots(1, len(runs), figsize=(3.2 * len(runs), 4.2), squeeze=False)
    bodies, titles = [], []
    for ax, run in zip(axes[0], runs):
        points = _world_points(run.states, run.times)
        lo, hi = points.reshape(-1, 2).min(0) - 0.3, points.reshape(-1, 2).max(0) + 0.3
        ax.set(aspect="equal", xlim=(lo[0], hi[0]), ylim=(lo[1], hi[1]), xticks=[], yticks=[])
        line, = ax.plot([], [], "-o", color="tab:blue", lw=3, ms=3)
        bodies.append((line, points))
        titles.append(ax.set_title(run.label, fontsize=9))

    def draw(k):
        for (line, points), title, run in zip(bodies, titles, runs):
            line.set_data(points[k, :, 0], points[k, :, 1])
            title.set_text(f"{run.label}  t = {run.times[k]:.2f} s")
        return [b[0] for b in bodies] + titles

    animation = FuncAnimation(fig, draw, frames=frames, blit=False)
    animation.save(path, writer=PillowWriter(fps=fps))
    plt.close(fig)
