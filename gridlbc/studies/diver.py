"""The diver beyond the grid (paper §6.1–6.2, Figs. 6 and 8): trajectory-based linear Bellman
combination on the 8-D problem of :func:`gridlbc.studies.problems.diver_problem`.

Each component is a locally optimal dive (:func:`gridlbc.trajectory.optimize`) with its quadratic
value expansion and LQR tracker (:func:`gridlbc.trajectory.expand`). Two experiments:

- **Interpolation** (Fig. 6): an under-rotating dive (entry cost centred c = −δ) and an
  over-rotating one (c = +δ), combined to enter vertically (c = 0) with weights w from projecting
  exp(−ḡ/λ) onto the components' exp(−g_i/λ) (:func:`gridlbc.project`). The entry costs differ in
  θ1's centre alone, so every Gram entry is that of the θ1 marginals times the same factor from
  the other coordinates (on the momenta, which carry no cost, a divergent one: the weights are
  its limit), and the weights are those of the 1-D projection (wrapping is negligible where
  exp(−g/λ) is narrow against 2π).
- **Coordination** (Fig. 8): three vertical dives from take-off angular momenta κ = 0.85, 1 and
  1.15 of nominal, combined with w = 1, tested from κ in between and beyond.

Each controller (LBC, the naive blend Σ w_i u_i / Σ w_i, single trackers) is rolled out without
noise (the paper's setting) and judged by the target problem's cost J, the entry error and the
deterministic optimum from the same take-off (rolled out with its own tracker, so that every row
has the same time stepping); with the problem's noise, :func:`gridlbc.certify`
gives its cost and the certified optimum v* with the effective sample size.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..certify import certify
from ..combine import CompositeCost, combine, naive_blend
from ..costs import Quadratic, wrap_angle
from ..errors import CertificateWarning
from ..project import projection
from ..simulate import simulate
from ..trajectory import expand, optimize
from .problems import DIVER_ENTRY_WEIGHTS, diver, diver_problem, diver_start


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
        :func:`gridlbc.certify` of the controller on the noisy target problem, the controller as
        its own proposal (its tail k̂ says whether that v* estimate can be used).
    noisy_costs : ndarray or None
        The realised cost of each noisy path (:func:`gridlbc.simulate`, the same paths as the
        certificate's): every controller at a take-off gets the same noise, so differences of
        these are paired.
    policy : callable or None
        The controller ``policy(x, t)`` (e.g. as a proposal for another certificate).
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
    noisy_costs: np.ndarray | None = None
    policy: object = None

    @property
    def noisy_cost(self) -> tuple[float, float]:
        """(mean, standard error) of :attr:`noisy_costs`."""
        if self.noisy_costs is None:
            raise ValueError(f"{self.label}: no noisy paths (certify_samples=0)")
        c = self.noisy_costs
        return float(c.mean()), float(c.std(ddof=1) / np.sqrt(c.size))

    def paired_difference(self, other: DiveRun) -> tuple[float, float]:
        """This run's noisy cost minus ``other``'s on the same paths' noise: (mean, its SE)."""
        if self.noisy_costs is None or other.noisy_costs is None:
            raise ValueError("paired_difference needs noisy paths on both runs")
        d = self.noisy_costs - other.noisy_costs
        return float(d.mean()), float(d.std(ddof=1) / np.sqrt(d.size))


def dive_run(problem, policy, label, momentum_scale, dt, certify_samples=0, seed=0) -> DiveRun:
    """Roll ``policy`` out noise-free from the take-off κ = ``momentum_scale`` on ``problem``
    (and certify it with ``certify_samples`` noisy samples, if any)."""
    x0 = diver_start(momentum_scale)
    run = simulate(problem, policy, x0, dt=dt, noise=False)
    final = run.final_states[0]
    certificate = costs = None
    if certify_samples:
        with warnings.catch_warnings():  # the tail k̂ and ESS are reported with the run
            warnings.simplefilter("ignore", CertificateWarning)
            certificate = certify(
                problem, policy, x0, n_samples=certify_samples, dt=dt, seed=seed, progress=False
            )
        costs = simulate(problem, policy, x0, certify_samples, dt=dt, seed=seed).costs
    return DiveRun(
        label,
        momentum_scale,
        run.times,
        run.states[0],
        run.controls[0],
        float(run.costs[0]),
        float(abs(wrap_angle(final[0]))),
        float(np.linalg.norm(wrap_angle(final[1:4]))),
        certificate,
        costs,
        policy,
    )


def interpolation_weights(offset: float, temperature: float):
    """The projection of the vertical entry onto entries at ∓``offset`` (θ1 marginals, see the
    module docstring): a :class:`gridlbc.Projection`."""
    w1 = DIVER_ENTRY_WEIGHTS[0]
    target = Quadratic([0.0], [w1])
    components = [Quadratic([-offset], [w1]), Quadratic([offset], [w1])]
    return projection(target, components, temperature=temperature)


def run_interpolation(
    offset=0.25, dt=0.005, certify_samples=0, seed=0, temperature=None, **optimize_options
):
    """Fig. 6: under- and over-rotating dives combined to enter vertically. Returns
    (projection, runs). ``optimize_options`` go to :func:`gridlbc.trajectory.optimize`."""
    kwargs = {} if temperature is None else {"temperature": temperature}
    target = diver_problem(0.0, **kwargs)
    x0 = diver_start(1.0)
    parts = []
    for c in (-offset, offset):
        problem = diver_problem(c, **kwargs)
        trajectory = optimize(problem, x0, seed=seed, **optimize_options)
        parts.append((problem, trajectory, expand(problem, trajectory)))
    fit = interpolation_weights(offset, target.temperature)
    w = fit.weights
    runs = [
        dive_run(
            target, combine([p[2] for p in parts], w).policy, "LBC", 1.0, dt, certify_samples, seed
        ),
        dive_run(
            target,
            naive_blend([p[2] for p in parts], w).policy,
            "naive blend",
            1.0,
            dt,
            certify_samples,
            seed,
        ),
    ]
    for name, (_problem, _trajectory, component) in zip(("under-rotating", "over-rotating"), parts):
        runs.append(
            dive_run(target, component.policy, f"{name} tracker", 1.0, dt, certify_samples, seed)
        )
    best = optimize(
        target, x0, seed=seed, initial_controls=parts[0][1].controls, **optimize_options
    )
    runs.append(
        dive_run(
            target, expand(target, best).policy, "vertical optimum", 1.0, dt, certify_samples, seed
        )
    )
    # What LBC aims at: the composite entry cost −λ log Σ w_i exp(−g_i/λ), optimised directly
    # and costed on the vertical target.
    composite = target.replace(
        terminal_cost=CompositeCost(tuple(p[0].terminal_cost for p in parts), w, target.temperature)
    )
    aimed = optimize(
        composite, x0, seed=seed, initial_controls=parts[0][1].controls, **optimize_options
    )
    runs.append(
        dive_run(
            target,
            expand(composite, aimed).policy,
            "composite optimum",
            1.0,
            dt,
            certify_samples,
            seed,
        )
    )
    return fit, runs


def composite_profile(offset, temperature, angles):
    """The composite entry cost −λ log Σ w_i exp(−g_i/λ) of the interpolation, at arms' angles
    ``angles`` with the body straight: where LBC's combined goal has its minima."""
    w = interpolation_weights(offset, temperature).weights
    costs = tuple(
        diver_problem(c, temperature=temperature).terminal_cost for c in (-offset, offset)
    )
    states = np.zeros((len(angles), 8))
    states[:, 0] = angles
    return CompositeCost(costs, w, temperature)(states)


def run_coordination(
    scales=(0.85, 1.0, 1.15),
    tests=None,
    dt=0.005,
    certify_samples=0,
    seed=0,
    temperature=None,
    n_intervals=100,
    **optimize_options,
):
    """Fig. 8: vertical dives from κ = ``scales`` combined with w = 1, tested from ``tests``
    (default eight κ from 0.8 to 1.2), also with the paper's deterministic v̄ in α. Returns
    (components, components with deterministic v̄, runs)."""
    kwargs = {} if temperature is None else {"temperature": temperature}
    problem = diver_problem(0.0, **kwargs)
    optimize_options["n_intervals"] = n_intervals
    trajectories = [
        optimize(problem, diver_start(kappa), seed=seed, **optimize_options) for kappa in scales
    ]
    components = [expand(problem, trajectory) for trajectory in trajectories]
    deterministic = [expand(problem, trajectory, stochastic=False) for trajectory in trajectories]
    lbc = combine(components).policy
    lbc_deterministic = combine(deterministic).policy
    naive = naive_blend(components, np.ones(len(components))).policy
    single = components[list(scales).index(1.0)].policy
    tests = np.linspace(0.8, 1.2, 8) if tests is None else tests
    runs = []
    for kappa in tests:
        runs.append(dive_run(problem, lbc, "LBC", kappa, dt, certify_samples, seed))
        lbc_tape = runs[-1].controls
        runs.append(
            dive_run(
                problem, lbc_deterministic, "LBC, deterministic v̄", kappa, dt, certify_samples, seed
            )
        )
        runs.append(dive_run(problem, naive, "naive blend", kappa, dt, certify_samples, seed))
        runs.append(
            dive_run(problem, single, "single tracker (κ = 1)", kappa, dt, certify_samples, seed)
        )
        # Started from LBC's own tape (among the built-in starts), so that the optimum found is
        # at least as good as LBC's open loop.
        start = lbc_tape[((np.arange(n_intervals) + 0.5) * len(lbc_tape) / n_intervals).astype(int)]
        best = optimize(
            problem, diver_start(kappa), seed=seed, initial_controls=start, **optimize_options
        )
        runs.append(
            dive_run(
                problem, expand(problem, best).policy, "optimum", kappa, dt, certify_samples, seed
            )
        )
    return components, deterministic, runs


def blend_at_start(components, momentum_scale):
    """(v̂_i(x0, 0) per component, α_i(x0, 0) of their w = 1 combination) at take-off κ."""
    x0 = diver_start(momentum_scale)
    values = np.array([float(c.value(x0, 0.0)) for c in components])
    return values, combine(components).blend_weights(x0, 0.0)


# -- pictures ---------------------------------------------------------------------------------

_FLIGHT = (3.0, 4.0, 9.81)
"""Horizontal and initial vertical speed of the centre of mass (m/s) and g, for drawing only: the
dynamics of the body about its centre of mass do not depend on them."""

_COLORS = {
    "LBC": "tab:blue",
    "naive blend": "tab:red",
    "under-rotating tracker": "tab:olive",
    "over-rotating tracker": "tab:purple",
    "vertical optimum": "black",
    "composite optimum": "tab:green",
    "single tracker (κ = 1)": "tab:orange",
    "optimum": "black",
    "LBC, deterministic v̄": "tab:cyan",
}


def _world_points(states, times) -> np.ndarray:
    """Joint points ``(k, 5, 2)`` in the world: the body about a centre of mass on its parabola."""
    vx, vy, g = _FLIGHT
    com = np.stack([vx * times, vy * times - 0.5 * g * times**2], axis=1)
    return diver().positions(states) + com[:, None, :]


def _draw_body(ax, points, color, alpha=1.0, lw=2.5):
    ax.plot(
        points[:, 0], points[:, 1], "-", color=color, alpha=alpha, lw=lw, solid_capstyle="round"
    )
    ax.plot(points[0, 0], points[0, 1], "o", color=color, alpha=alpha, ms=4)  # the hands


_FIG6_PANELS = (
    "under-rotating tracker",
    "over-rotating tracker",
    "LBC",
    "naive blend",
    "vertical optimum",
    "composite optimum",
)
"""The dives of the interpolation experiment drawn in the top row: the two components, then
their combinations and the optima."""


def plot_study(interpolation, coordination, path=None):
    """Fig. 6 and Fig. 8: strobed dives of the interpolation experiment (top: the two component
    dives, LBC, the naive blend and the optima), the entry poses over κ for LBC and the single
    tracker and the noise-free costs against κ (middle), and, where the runs carry noisy paths,
    the noisy costs J ± 2 SE against κ and each controller's difference from the single tracker
    ± 3 paired SE (bottom: a bar across zero is a tie)."""
    import matplotlib.pyplot as plt

    noisy = any(r.noisy_costs is not None for r in coordination)
    fig = plt.figure(figsize=(18, 13.5 if noisy else 9))
    grid = fig.add_gridspec(3 if noisy else 2, 6, height_ratios=[1, 1, 1] if noisy else [1, 1])
    by_label = {r.label: r for r in interpolation}
    shown = [by_label[label] for label in _FIG6_PANELS if label in by_label]
    for col, run in enumerate(shown):
        ax = fig.add_subplot(grid[0, col])
        points = _world_points(run.states, run.times)
        for k in np.linspace(0, len(run.times) - 1, 8).astype(int):
            _draw_body(
                ax, points[k], _COLORS[run.label], alpha=0.2 + 0.8 * k / (len(run.times) - 1)
            )
        title = (
            f"{run.label}: J = {run.cost:.3g}\nentry {np.degrees(run.entry_error):.0f}° "
            f"from vertical, shape {np.degrees(run.shape_error):.0f}°"
        )
        if run.noisy_costs is not None:
            J, se = run.noisy_cost
            title += f"\nnoisy J = {J:.1f} ± {se:.1f}"
        ax.set(aspect="equal", xticks=[], yticks=[], xlim=(-1.5, 4.5), ylim=(-2.8, 2.4))
        ax.set_title(title, fontsize=10)
    fig.text(
        0.01,
        0.985,
        "Fig. 6, interpolation: under- and over-rotating dives combined to enter "
        "vertically (hands dotted, light to dark in time)",
        fontsize=11,
    )
    ax8 = fig.add_subplot(grid[1, :3])
    kappas = sorted({r.momentum_scale for r in coordination})
    for row, label in enumerate(("LBC", "single tracker (κ = 1)")):
        for col, kappa in enumerate(kappas):
            run = next(r for r in coordination if r.label == label and r.momentum_scale == kappa)
            _draw_body(
                ax8, diver().positions(run.states[-1:])[0] + [col * 1.3, -row * 2.8], _COLORS[label]
            )
        ax8.text(-0.9, -row * 2.8, label, rotation=90, va="center", ha="right", fontsize=9)
    for col, kappa in enumerate(kappas):
        ax8.text(col * 1.3, 1.5, f"κ = {kappa:.2f}", ha="center", fontsize=8)
    ax8.set(
        aspect="equal",
        xticks=[],
        yticks=[],
        ylim=(-4.3, 1.8),
        title="Fig. 8, coordination: entry poses (vertical: straight, hands down)",
    )
    labels = ("LBC", "LBC, deterministic v̄", "naive blend", "single tracker (κ = 1)", "optimum")
    rows = {
        label: sorted((r for r in coordination if r.label == label), key=lambda r: r.momentum_scale)
        for label in labels
    }
    axc = fig.add_subplot(grid[1, 3:])
    for label in labels:
        kappa = [r.momentum_scale for r in rows[label]]
        axc.plot(
            kappa, [r.cost for r in rows[label]], "o-", color=_COLORS[label], label=label, ms=4
        )
    axc.set(
        xlabel="take-off angular momentum κ (× nominal)",
        ylabel="noise-free cost J",
        yscale="log",
        title="coordination, noise-free: cost against κ (components at 0.85, 1, 1.15)",
    )
    axc.legend(fontsize=8)
    if noisy:
        n_paths = next(r.noisy_costs.size for r in coordination if r.noisy_costs is not None)
        axn = fig.add_subplot(grid[2, :3])
        axd = fig.add_subplot(grid[2, 3:])
        single = {r.momentum_scale: r for r in rows["single tracker (κ = 1)"]}
        for label in labels[:-1]:
            noisy_rows = [r for r in rows[label] if r.noisy_costs is not None]
            kappa = np.array([r.momentum_scale for r in noisy_rows])
            J = np.array([r.noisy_cost for r in noisy_rows])
            axn.errorbar(
                kappa,
                J[:, 0],
                yerr=2 * J[:, 1],
                fmt="s-",
                color=_COLORS[label],
                ms=4,
                capsize=2,
                label=label,
            )
            if label == "single tracker (κ = 1)":
                continue
            d = np.array([r.paired_difference(single[r.momentum_scale]) for r in noisy_rows])
            tie = np.abs(d[:, 0]) < 3 * d[:, 1]
            axd.errorbar(
                kappa,
                d[:, 0],
                yerr=3 * d[:, 1],
                fmt="-",
                color=_COLORS[label],
                capsize=2,
                label=label,
            )
            axd.plot(kappa[~tie], d[~tie, 0], "s", color=_COLORS[label], ms=5)
            axd.plot(kappa[tie], d[tie, 0], "s", mfc="white", color=_COLORS[label], ms=5)
        axn.set(
            xlabel="take-off angular momentum κ (× nominal)",
            ylabel="noisy cost J (mean ± 2 SE)",
            title=f"coordination with noise ({n_paths} paths, the same noise for every controller)",
        )
        axn.legend(fontsize=8)
        axd.axhline(0.0, color="tab:orange", lw=1.5)
        axd.set(
            xlabel="take-off angular momentum κ (× nominal)",
            ylabel="J − J(single tracker), paired (± 3 SE)",
            title="with noise, against the single κ = 1 tracker: below 0 is cheaper; "
            "open squares: a tie",
        )
        axd.legend(fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.975))
    if path is not None:
        fig.savefig(path, dpi=100)
    return fig


def animate_dives(runs, path, fps: int = 25):
    """A GIF of the given :class:`DiveRun` s side by side (same times)."""
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    times = runs[0].times
    frames = np.minimum(
        np.searchsorted(times, np.arange(0.0, times[-1] + 1e-9, 1.0 / fps)), len(times) - 1
    )
    frames = np.concatenate([frames, np.full(fps, frames[-1])])  # hold the entry for 1 s
    fig, axes = plt.subplots(1, len(runs), figsize=(3.2 * len(runs), 4.2), squeeze=False)
    bodies, titles = [], []
    for ax, run in zip(axes[0], runs):
        points = _world_points(run.states, run.times)
        lo, hi = points.reshape(-1, 2).min(0) - 0.3, points.reshape(-1, 2).max(0) + 0.3
        ax.set(aspect="equal", xlim=(lo[0], hi[0]), ylim=(lo[1], hi[1]), xticks=[], yticks=[])
        (line,) = ax.plot([], [], "-o", color=_COLORS.get(run.label, "tab:blue"), lw=3, ms=3)
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
