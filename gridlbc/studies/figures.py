"""The figure gallery: the paper's ideas on systems you can picture (``gridlbc figures``).

One function per figure; each takes the output folder and a size knob (grid nodes per axis,
Monte-Carlo samples) so that tests can run it small, and returns the paths it wrote.
:func:`make_all` writes them all (``quick=True``: small sizes, for a look in seconds).

- :func:`cost_reward_space` — v = −λ log z, z and u* of the pendulum swing-up (paper Fig. 2).
- :func:`projection` — projecting a target reward h̄ = exp(−ḡ/λ) onto component rewards
  h_i = exp(−g_i/λ), when it works (Fig. 3), when it needs a negative weight, and when the
  components are too narrow for their spacing (Fig. 4), with the warnings said.
- :func:`interpolation` — an intermediate goal behind a wall: linear Bellman combination with
  the projected weights vs the naive blend of policies vs each component vs the direct solve,
  every cost certified against the optimum (Fig. 6 idea).
- :func:`coordination` — blend weights α over time for a two-goal point mass pushed mid-way, with
  certified costs before and after the push (Fig. 9).
- :func:`gymnast` — the acrobot swing-up from the paper's test state (Fig. 7 setting), a still
  and a GIF (the study of :mod:`gridlbc.studies.gymnast`).
- :func:`certified_convergence` — the swing-up's predicted value and its policy's cost against
  the certified optimum as the grid is refined (:func:`gridlbc.certify`).
- :func:`exit_bays` — a first-exit task (park in one of three bays): exit-cost components
  combined into new optimal controllers, certified, and their blend weights as exit probabilities.
- :func:`convergence` — error against grid spacing and the small-temperature study
  (:mod:`gridlbc.studies.convergence`).
"""

from __future__ import annotations

import textwrap
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from ..certify import certify
from ..combine import CompositeCost, combine, naive_blend
from ..costs import Quadratic
from ..problem import Problem
from ..project import ProjectionWarning, project
from ..project import projection as project_weights
from ..simulate import simulate
from ..solver import solve, solve_many
from .problems import (
    GOAL_WEIGHTS,
    GYMNAST_START,
    OBSTACLE_GOALS,
    OBSTACLE_START,
    OBSTACLE_TARGET,
    OBSTACLE_WEIGHTS,
    SWINGUP_START,
    CapsuleObstacle,
    coordination_problem,
    gymnast_problem,
    obstacle_problem,
    obstacle_trajectories,
    swingup_problem,
)

DPI = 100


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, out, name: str) -> Path:
    path = Path(out) / name
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=DPI)
    _pyplot().close(fig)
    return path


# -- 1. cost space vs reward space -------------------------------------------------------------------


def cost_reward_space(out, n: int = 201) -> list[Path]:
    """Value, desirability and policy of the pendulum swing-up at t = 0 on an n × n grid."""
    from .demo import plot_fields

    problem = swingup_problem(n)
    solution = solve(problem)
    path = Path(out) / "cost_reward_space.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    plot_fields(
        solution,
        path,
        f"Pendulum swing-up, cost space vs reward space "
        f"({solution.grid.describe()}, T = {problem.horizon:g}, λ = "
        f"{problem.temperature:g}, g = 10θ² + 0.5ω²): t = 0",
    )
    return [path]


# -- 2. projection of terminal rewards ----------------------------------------------------------------


PROJECTION_CASES = (
    ("represented well (paper Fig. 3)", (-0.5, 0.5), 0.5, 0.2),
    ("target outside the components", (-0.5, 0.5), 0.5, 1.2),
    ("components too narrow for their spacing (paper Fig. 4)", (0.0, 1.0), 25.0, 0.5),
)
"""(title, component centres, weight W of g = W (x − c)², target centre ḡ) in one dimension."""


def projection(out, points: int = 801, temperature: float = 1.0) -> list[Path]:
    """Project a 1-D target reward onto two component rewards: one target the basis represents
    well, one it must extrapolate (a negative weight), one it cannot reach (Σw far from 1).

    Top: h_i = exp(−g_i/λ), the target h̄ and the reconstruction Σ w_i h_i, with the
    :class:`gridlbc.ProjectionWarning` messages that :func:`gridlbc.project` issues. Bottom: the
    costs g_i, ḡ and the cost the combination really optimises, −λ log Σ w_i h_i (+∞ where
    Σ w_i h_i ≤ 0), with its minima marked.
    """
    plt = _pyplot()
    lam = temperature
    x = np.linspace(-1.5, 2.5, points)[:, None]
    fig, axes = plt.subplots(
        2, len(PROJECTION_CASES), figsize=(17, 8), sharex=True, constrained_layout=True
    )
    for col, (title, centres, W, target_centre) in enumerate(PROJECTION_CASES):
        components = [Quadratic([c], [W]) for c in centres]
        target = Quadratic([target_centre], [W])
        with warnings.catch_warnings(record=True) as issued:
            warnings.simplefilter("always", ProjectionWarning)
            w = project(target, components, temperature=lam)
        said = [str(m.message) for m in issued if issubclass(m.category, ProjectionWarning)]
        result = project_weights(target, components, temperature=lam)  # for the residual
        h = [np.exp(-c(x) / lam) for c in components]
        blended = CompositeCost(tuple(components), w, lam)(x)
        top, bottom = axes[:, col]
        for i, h_i in enumerate(h):
            top.plot(
                x,
                h_i,
                color=f"C{i}",
                label=f"h{i + 1} (c = {centres[i]:g}), w{i + 1} = {w[i]:+.3f}",
            )
            bottom.plot(x, components[i](x), color=f"C{i}", label=f"g{i + 1}")
        top.plot(x, np.exp(-target(x) / lam), "k--", label=f"target h̄ (c = {target_centre:g})")
        top.plot(x, sum(wi * hi for wi, hi in zip(w, h)), "C3", lw=2, label="Σ wᵢ hᵢ")
        top.axhline(0, color="0.5", lw=0.5)
        bottom.plot(x, target(x), "k--", label="target ḡ")
        bottom.plot(x, blended, "C3", lw=2, label="−λ log Σ wᵢ hᵢ (what LBC optimises)")
        finite = np.isfinite(blended)
        minima = np.flatnonzero((blended[1:-1] < blended[:-2]) & (blended[1:-1] < blended[2:])) + 1
        bottom.plot(
            x[minima, 0],
            blended[minima],
            "v",
            color="C3",
            ms=9,
            label=f"its minima: x = {', '.join(f'{v:.2f}' for v in x[minima, 0])}",
        )
        if not finite.all():
            bottom.axvspan(
                x[~finite, 0].min(),
                x[~finite, 0].max(),
                color="C3",
                alpha=0.1,
                label="Σ wᵢ hᵢ ≤ 0: cost +∞",
            )
        top.set_title(
            f"{title}\nΣw = {w.sum():.2f}, residual ‖h̄ − Σwh‖/‖h̄‖ = {result.residual:.2f}",
            fontsize=10,
        )
        verdict = (
            "gridlbc.project warns:\n"
            + "\n".join("• " + textwrap.fill(m, 52, subsequent_indent="  ") for m in said)
            if said
            else "gridlbc.project: no warning"
        )
        top.text(
            0.02,
            0.97,
            verdict,
            transform=top.transAxes,
            va="top",
            fontsize=7.5,
            color="C3" if said else "0.3",
            bbox={"facecolor": "white", "alpha": 0.85, "edgecolor": "0.8"},
        )
        top.set_ylabel("reward h = exp(−g/λ)")
        top.set_ylim(-0.7 if w.min() < 0 else -0.05, 1.45)
        bottom.set_ylabel("cost g")
        bottom.set_xlabel("state x")
        bottom.axvline(target_centre, color="k", ls=":", lw=1)
        bottom.set_ylim(-0.5, 8.5)
        top.legend(fontsize=8, loc="upper right")
        bottom.legend(fontsize=8, loc="upper center", ncol=2, framealpha=0.95)
    fig.suptitle(
        f"Projecting a target terminal reward onto two component rewards (λ = {lam:g}, "
        "g = W (x − c)²): when the basis represents it and when it does not"
    )
    return [_save(fig, out, "projection.png")]


# -- 3. interpolation -------------------------------------------------------------------------------


COMPLETION_RADIUS = 0.25
"""A rollout of the interpolation figure "reaches" the intermediate goal c̄ when its final state
lies within this distance of it."""


def _wall(problem: Problem) -> CapsuleObstacle:
    """The wall task's state cost: the capsule obstacle of :func:`~.problems.obstacle_problem`."""
    wall = problem.state_cost
    if not isinstance(wall, CapsuleObstacle):
        raise TypeError(
            "the interpolation figure needs the wall task (obstacle_problem), whose state cost "
            f"is a CapsuleObstacle, got {type(wall).__name__}"
        )
    return wall


def _inside_wall(problem: Problem, run) -> np.ndarray:
    """Per rollout of ``run`` on the wall task and per time: whether the state is inside the
    wall (its cost above half the wall's height), shape (n, k)."""
    wall = _wall(problem)
    states = run.states
    return wall(states.reshape(-1, 2)).reshape(states.shape[:2]) > wall.height / 2


def route_signed_final_y(run) -> np.ndarray:
    """Per rollout of ``run`` on the wall task: its final y, signed towards the end of the wall
    it went round (+ for the upper end, − for the lower; the end is the side of its largest
    excursion |y|), shape (n,). Its mean is how far the rollouts stop short of the intermediate
    goal c̄ (y = 0) on the side they come from, the sign of a route-conditioned mean removed;
    a solved goal lies at +0.09 on this scale."""
    y = run.states[..., 1]
    side = np.where(y.max(axis=1) >= -y.min(axis=1), 1.0, -1.0)
    return side * run.final_states[:, 1]


def interpolation(
    out,
    n: int = 151,
    samples: int = 32000,
    seed: int = 0,
    traces: int = 30,
    dt: float = 0.01,
    restarts: int = 32,
) -> list[Path]:
    """An intermediate goal behind a wall: LBC vs the naive blend vs each component alone.

    A point in the plane (:func:`~gridlbc.studies.problems.obstacle_problem`: dx = u dt + noise,
    T = 3, λ = 0.2) starts in front of the middle of a long wall and must end at the intermediate
    goal c̄ directly behind it. The components are trajectory components (paper §5,
    :func:`~gridlbc.studies.problems.obstacle_trajectories`) for goals just above and just below
    c̄ (:data:`~gridlbc.studies.problems.OBSTACLE_GOALS`): the upper one is a locally optimal path
    round the wall's upper end with its LQR tracker and quadratic value expansion v̂, the lower
    one its mirror image. The weights come from projecting h̄ = exp(−ḡ/λ) onto {h_1, h_2}
    (:func:`gridlbc.project`); the goals sit less than σ = √(λ/2W_y) from c̄, so the composite
    cost g_w = −λ log Σ w_i h_i has a single minimum, at c̄.

    LBC, u = Σ α_i u_i with α_i = w_i exp(−v̂_i/λ) / Σ_j w_j exp(−v̂_j/λ), follows whichever path
    the noise has made cheaper; behind the wall, where both expansions hold, the other
    component's weight rises and its unsaturated tracker pulls towards its own goal,
    so LBC stops nearer c̄ than either component alone (the route-signed final y,
    :func:`route_signed_final_y`: mean ± SE, and its difference to LBC's ± paired SE). The
    naive blend u = Σ w_i u_i / Σ w_i averages the two trackers u_i = ū_i + K_i (x − x̄_i) with
    fixed, equal weights. The lower tracker is the upper one mirrored (y → −y), so the average
    maps mirrored states to mirrored controls: on the axis y = 0 its sideways control vanishes,
    and without noise it drives straight along the axis, through the wall.

    Every controller is certified on g_w (:func:`gridlbc.certify`: J ± SE, the certified
    optimum v* and the gap J − v* ± paired SE), and its cost difference to LBC is measured with
    common random numbers (the same noise for every controller, so the paired SE is far smaller
    than either cost's). The grid gives the references: the exact LBC of the grid components for
    the same goals (:func:`gridlbc.solve_many`, one operator: the optimum of g_w to rounding)
    and the direct solve of ḡ, the intermediate goal's own optimal controller. Completion is the
    share of rollouts ending within :data:`COMPLETION_RADIUS` of c̄.
    """
    plt = _pyplot()
    problem = obstacle_problem(n)
    grid = problem.require_grid("the interpolation figure")
    lam, start, wall = problem.temperature, OBSTACLE_START, _wall(problem)
    goals = [Quadratic(c, OBSTACLE_WEIGHTS) for c in OBSTACLE_GOALS]
    fit = project_weights(problem.terminal_cost, goals, grid, temperature=lam)
    upper, lower = obstacle_trajectories(problem, restarts=restarts)
    lbc = combine([upper, lower], fit.weights)
    naive = naive_blend([upper, lower], fit.weights)
    *grid_components, direct = solve_many(problem, [*goals, problem.terminal_cost], dt=dt)
    exact = combine(grid_components, fit.weights)
    beta = lbc.blend_weights(start, 0.0)
    names = (
        "LBC Σαᵢuᵢ",
        "naive blend Σwᵢuᵢ/Σwᵢ",
        f"upper goal (y = {OBSTACLE_GOALS[0][1]:+g}) alone",
        f"lower goal (y = {OBSTACLE_GOALS[1][1]:+g}) alone",
        "exact LBC (grid components)",
        "direct solve of ḡ (grid)",
    )
    policies = dict(
        zip(
            names,
            (lbc.policy, naive.policy, upper.policy, lower.policy, exact.policy, direct.policy),
        )
    )
    colors = dict(zip(names, ("C0", "C1", "0.35", "0.65", "C4", "C2")))
    # the two controllers compared bold, the grid references dashed
    styles = {
        k: {
            "color": colors[k],
            "lw": 2.5 if k in names[:2] else 1.3,
            "ls": "--" if k in names[4:] else "-",
        }
        for k in names
    }
    task = lbc.problem  # the composite task g_w
    certificates = {
        k: certify(task, p, start, samples, dt=dt, seed=seed, progress=False)
        for k, p in policies.items()
    }
    # Common random numbers: one seed drives every controller with the same noise, so the
    # per-sample differences of realised cost give a paired SE of J(u) − J(LBC).
    runs = {k: simulate(task, p, start, samples, dt=dt, seed=seed + 1) for k, p in policies.items()}
    paired = {}
    for k, run in runs.items():
        d = run.costs - runs[names[0]].costs
        paired[k] = (d.mean(), d.std(ddof=1) / np.sqrt(samples))
    inside = {k: _inside_wall(problem, run) for k, run in runs.items()}
    distance = {
        k: np.linalg.norm(run.final_states - OBSTACLE_TARGET, axis=1) for k, run in runs.items()
    }
    stop = {k: route_signed_final_y(run) for k, run in runs.items()}

    fig = plt.figure(figsize=(24, 13), constrained_layout=True)
    upper_row, lower_row = fig.subfigures(2, 1, height_ratios=(1.1, 1))
    top = list(upper_row.subplots(1, 3))
    ax_reach, ax_stop, ax_wall, ax_cost = lower_row.subplots(1, 4)
    (x_lo, x_hi), (y_lo, y_hi) = ((a.lo, a.hi) for a in grid.axes)
    X, Y = np.meshgrid(np.linspace(x_lo, x_hi, 201), np.linspace(y_lo, y_hi, 301))
    plane = np.column_stack([X.ravel(), Y.ravel()])
    value = exact.value(plane, 0.0).reshape(X.shape)
    levels = np.linspace(value.min(), np.percentile(value, 97), 25)
    panels = ((top[0], names[:1]), (top[1], names[1:2]), (top[2], names[2:4]))
    for ax, keys in panels:
        shading = ax.contourf(X, Y, value, levels, cmap="Greys_r", extend="max", alpha=0.8)
        ax.contour(
            X, Y, wall(plane).reshape(X.shape), [wall.height / 2], colors="C3", linewidths=1.5
        )
        for key in keys:
            for path in runs[key].states[: traces // len(keys)]:
                (line,) = ax.plot(path[:, 0], path[:, 1], color=colors[key], lw=0.6, alpha=0.75)
            line.set_label(
                f"{key}: {100 * inside[key].any(axis=1).mean():.1f} % enter the wall, "
                f"{100 * np.mean(distance[key] < COMPLETION_RADIUS):.1f} % end within "
                f"{COMPLETION_RADIUS:g} of c̄"
            )
        for component in (upper, lower):
            path = component.trajectory.states
            ax.plot(
                path[:, 0],
                path[:, 1],
                "k--",
                lw=1,
                label="the components' paths" if component is upper else None,
            )
        for i, goal in enumerate(OBSTACLE_GOALS):
            ax.plot(*goal, "X", color="w", mec="k", ms=8, label="solved goals" if i == 0 else None)
        ax.plot(*OBSTACLE_TARGET, "*", color="gold", mec="k", ms=15, label="intermediate goal c̄")
        ax.plot(*start, "o", color="w", mec="k", ms=7, label="start")
        ax.plot([], [], color="C3", label="wall (q = H/2)")
        ax.set(xlabel="x", ylabel="y", aspect="equal", xlim=(x_lo, x_hi), ylim=(y_lo, y_hi))
        ax.legend(fontsize=7, loc="lower left", framealpha=0.9)
    top[0].set_title(
        f"{names[0]}: {traces} noisy rollouts\nβ = ({beta[0]:.2f}, {beta[1]:.2f}): "
        "the noise picks an end; behind the wall it mixes towards c̄"
    )
    top[1].set_title(f"{names[1]}: {traces} noisy rollouts\nno sideways push: through the wall")
    top[2].set_title(
        f"each component alone: {traces // 2} noisy rollouts each\neach goes round its own end"
    )
    upper_row.colorbar(
        shading, ax=top[2], shrink=0.8, label="optimal value v(x, 0) of g_w (grid, grey)"
    )

    radius = np.linspace(0, 0.6, 241)
    for key in names:
        share = 100 * np.mean(distance[key][:, None] < radius, axis=0)
        ax_reach.plot(
            radius, share, **styles[key], label=f"{key}: median {np.median(distance[key]):.3f}"
        )
    ax_reach.axvline(COMPLETION_RADIUS, color="k", lw=0.8, ls=":")
    ax_reach.set(
        xlabel="r",
        ylabel="% of rollouts ending within r of c̄",
        xlim=(0, radius[-1]),
        ylim=(0, 100),
        title=f"reaching the intermediate goal c̄ = {OBSTACLE_TARGET}\n"
        f"{samples} rollouts each, final distance |x_T − c̄|",
    )
    ax_reach.legend(
        fontsize=7.5, loc="lower right", title="median final distance", title_fontsize=8
    )

    bins = np.linspace(-0.35, 0.65, 81)
    shown = [names[0], *names[2:]]  # the naive blend's route is not one end: it goes through
    for key in shown:
        y = stop[key]
        d = y - stop[names[0]]
        mean, error = y.mean(), y.std(ddof=1) / np.sqrt(samples)
        extra = (
            ""
            if key == names[0]
            else f", {d.mean():+.3f} ± {d.std(ddof=1) / np.sqrt(samples):.3f} vs LBC"
        )
        ax_stop.hist(
            y,
            bins,
            histtype="step",
            density=True,
            **styles[key],
            label=f"{key}: {mean:+.3f} ± {error:.3f}{extra}",
        )
        ax_stop.axvline(mean, **(styles[key] | {"lw": 1.0}))
    ax_stop.axvline(0.0, color="gold", lw=3, alpha=0.7, zorder=0)
    ax_stop.axvline(abs(OBSTACLE_GOALS[0][1]), color="k", lw=0.8, ls=":")
    ax_stop.set(
        xlabel="final y, signed towards the end of the wall the rollout went round",
        ylabel="density",
        xlim=(bins[0], bins[-1]),
        title=f"how far short of c̄ (y = 0, gold) the rollouts stop\non the side they "
        f"come from (dotted: that side's goal, {abs(OBSTACLE_GOALS[0][1]):g})",
    )
    ax_stop.set_ylim(0, 1.7 * ax_stop.get_ylim()[1])
    ax_stop.legend(
        fontsize=7.5, loc="upper left", title="mean ± SE, difference ± paired SE", title_fontsize=8
    )

    times = runs[names[0]].times
    for key in names:
        ax_wall.plot(
            times,
            100 * inside[key].mean(axis=0),
            **styles[key],
            label=f"{key}: {100 * inside[key].any(axis=1).mean():.1f} % ever",
        )
    ax_wall.set(
        xlabel="time t",
        ylabel="% of rollouts inside the wall (q > H/2)",
        xlim=(0, problem.horizon),
        ylim=(0, 100),
        title=f"the naive blend drives through the wall\n{samples} rollouts each, common noise",
    )
    ax_wall.legend(
        fontsize=7.5, loc="upper right", title="share that ever enters the wall", title_fontsize=8
    )

    labels = list(names[1:])
    means = np.array([paired[k][0] for k in labels])
    errors = np.array([paired[k][1] for k in labels])
    rows = np.arange(len(labels))
    ax_cost.barh(
        rows, means, xerr=errors, color=[colors[k] for k in labels], capsize=4, height=0.5
    )  # its label below it, clear of the bar
    reference = certificates[names[4]]  # the exact optimum as proposal: the smallest SE of v*
    ours = certificates[names[0]]
    ax_cost.axvline(
        0,
        color="C0",
        lw=2,
        label=f"LBC: J = {ours.policy_cost:.3f} ± "
        f"{ours.policy_cost_se:.3f}, J − v* = {ours.gap:+.3f} ± {ours.gap_se:.3f}",
    )
    for i, label in enumerate(labels):
        c = certificates[label]
        ax_cost.text(
            0.02,
            i + 0.42,
            f"{means[i]:+.3f} ± {errors[i]:.3f} "
            f"({means[i] / errors[i]:+.0f} SE); J = {c.policy_cost:.3f} ± "
            f"{c.policy_cost_se:.3f}, J − v* = {c.gap:+.3f} ± {c.gap_se:.3f}",
            transform=ax_cost.get_yaxis_transform(),
            va="center",
            fontsize=8,
        )
    ax_cost.set_xscale("symlog", linthresh=0.1)
    ax_cost.set_yticks(rows, labels, fontsize=9)
    ax_cost.invert_yaxis()
    ax_cost.set(
        xlabel="J − J_LBC ± paired SE (symlog), common noise, task g_w",
        title=f"cost above LBC's on g_w (gridlbc.certify, {samples} samples)\n"
        f"certified v* = {reference.optimal_value:.3f} ± "
        f"{reference.optimal_value_se:.3f}\nthe naive blend and each component "
        "cost more",
    )
    ax_cost.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13))
    W = OBSTACLE_WEIGHTS
    fig.suptitle(
        f"Interpolating an intermediate goal behind a wall with trajectory components: "
        f"dx = u dt + noise, T = {problem.horizon:g}, λ = {lam:g},\n"
        f"g = {W[0]:g}(x − cₓ)² + {W[1]:g}(y − c_y)², projected w = "
        f"({fit.weights[0]:.3f}, {fit.weights[1]:.3f}); wall q = {wall.height:g} within "
        f"{wall.radius:g} of x = 0, |y| ≤ {wall.end[1]:g}; grid references on "
        f"{'×'.join(map(str, grid.shape))}",
        fontsize=11,
    )
    return [_save(fig, out, "interpolation.png")]


# -- 4. coordination with a push ----------------------------------------------------------------------


def simulate_with_push(
    problem: Problem,
    policy,
    x0,
    push_time: float,
    kick,
    n_samples: int = 1,
    seed=None,
    noise: bool = True,
    dt: float = 0.01,
):
    """Roll ``policy`` out on [0, T] with the state kicked by ``kick`` at ``push_time``.

    Two :func:`gridlbc.simulate` calls: on [0, t_p] (the problem with horizon t_p), then from the
    pushed states on [t_p, T] (horizon T − t_p, the policy's clock shifted by t_p). Returns
    ``(times, states (n, k, d))`` on the joined time grid, where t_p appears twice: the state just
    before the kick, then just after it.
    """
    T = problem.require_horizon("a pushed rollout")
    if not 0 < push_time < T:
        raise ValueError(f"push_time must lie in (0, T = {T:g}), got {push_time}")
    before = simulate(
        problem.replace(horizon=push_time), policy, x0, n_samples, dt=dt, seed=seed, noise=noise
    )
    pushed = before.final_states + np.asarray(kick, dtype=float)
    after = simulate(
        problem.replace(horizon=T - push_time),
        lambda x, t: policy(x, t + push_time),
        pushed,
        n_samples,
        dt=dt,
        seed=None if seed is None else seed + 1,
        noise=noise,
    )
    times = np.concatenate([before.times, push_time + after.times])
    return times, np.concatenate([before.states, pushed[:, None], after.states[:, 1:]], axis=1)


def remaining_task(problem: Problem, policy, start_time: float):
    """The task left at ``start_time``: the problem on [t_s, T] (horizon T − t_s) and the policy
    with its clock shifted, ``policy(x, t + t_s)``; e.g. to certify costs from a pushed state."""
    return (
        problem.replace(horizon=problem.require_horizon("remaining_task()") - start_time),
        lambda x, t: policy(x, t + start_time),
    )


def coordination(
    out, n: int = 81, samples: int = 2000, seed: int = 0, traces: int = 8, dt: float = 0.005
) -> list[Path]:
    """α over time of a two-goal combined controller (w = 1, 1), pushed mid-way (paper Fig. 9).

    The point mass starts at x = 0.3 at rest, nearer the goal x = +1, so α₊ → 1; at t = 1 s a
    push changes its velocity by −1.5 m/s and the combination switches to the goal x = −1 on its
    own: α_i = w_i z_i / Σ w_j z_j follows which goal is now cheaper to reach. Costs on the
    composite task g = −λ log(e^{−g₋/λ} + e^{−g₊/λ}) are certified (:func:`gridlbc.certify`)
    from the start and from the pushed state, for the combination and for each goal's
    controller alone, against the certified optimum.
    """
    plt = _pyplot()
    problem = coordination_problem(n)
    goals = [problem.terminal_cost, Quadratic([1.0, 0.0], GOAL_WEIGHTS)]
    left, right = solve_many(problem, goals)
    combined = combine([left, right])
    x0, push_time, kick = np.array([0.3, 0.0]), 1.0, np.array([0.0, -1.5])
    runs = {
        "noise-free": simulate_with_push(
            combined.problem, combined.policy, x0, push_time, kick, noise=False
        ),
        "with noise": simulate_with_push(
            combined.problem, combined.policy, x0, push_time, kick, traces, seed=seed
        ),
    }
    times, states = runs["noise-free"]
    pushed = states[0, np.searchsorted(times, push_time) + 1]  # just after the kick
    controllers = {
        "LBC Σαᵢuᵢ (w = 1, 1)": combined.policy,
        "goal x = −1 alone": left.policy,
        "goal x = +1 alone": right.policy,
    }
    certificates = {}
    for when, start, t_s in (
        ("from x₀ at t = 0", x0, 0.0),
        (f"from the pushed state at t = {push_time:g} s", pushed, push_time),
    ):
        for name, policy in controllers.items():
            task, shifted = remaining_task(combined.problem, policy, t_s)
            certificates[when, name] = certify(
                task, shifted, start, samples, dt=dt, seed=seed, progress=False
            )

    fig = plt.figure(figsize=(14, 8.5), constrained_layout=True)
    grid_spec = fig.add_gridspec(3, 2, width_ratios=(1.6, 1))
    ax_alpha = fig.add_subplot(grid_spec[0, 0])
    ax_x = fig.add_subplot(grid_spec[1, 0], sharex=ax_alpha)
    ax_v = fig.add_subplot(grid_spec[2, 0], sharex=ax_alpha)
    ax_cost = fig.add_subplot(grid_spec[:, 1])
    for label, (times, states) in runs.items():
        alpha = np.stack(
            [
                combined.blend_weights(states[:, k], min(t, problem.horizon))[:, 1]
                for k, t in enumerate(times)
            ],
            axis=1,
        )
        style = (
            {"color": "C0", "lw": 2.5, "zorder": 3}
            if label == "noise-free"
            else {"color": "C1", "lw": 0.6, "alpha": 0.5}
        )
        for s in range(states.shape[0]):
            legend = label if s == 0 else None
            ax_alpha.plot(times, alpha[s], label=legend, **style)
            ax_x.plot(times, states[s, :, 0], label=legend, **style)
            ax_v.plot(times, states[s, :, 1], label=legend, **style)
    for ax in (ax_alpha, ax_x, ax_v):
        ax.axvline(push_time, color="k", ls=":", lw=1)
        ax.grid(alpha=0.3)
    ax_alpha.text(push_time + 0.03, 0.45, f"push: velocity {kick[1]:+g} m/s", fontsize=9)
    ax_alpha.set(
        ylabel="α₊ = z₊ / (z₋ + z₊)",
        ylim=(-0.03, 1.03),
        title="blend weight of the controller for goal x = +1 (α₋ = 1 − α₊)",
    )
    ax_alpha.legend(fontsize=9, loc="lower left")
    for goal in (-1, 1):
        ax_x.axhline(goal, color="0.5", ls="--", lw=1)
    ax_x.set(ylabel="position x (m)", title="position; goals at rest at x = ±1 (dashed)")
    ax_v.set(xlabel="t (s)", ylabel="velocity (m/s)", title="velocity")

    names = list(controllers)
    colors = ["C3", "0.55", "0.75"]
    for group, when in enumerate(dict.fromkeys(w for w, _ in certificates)):
        rows = [certificates[when, name] for name in names]
        base = group * (len(names) + 1.5)
        positions = base + np.arange(len(names))
        means = [c.policy_cost for c in rows]
        ax_cost.barh(
            positions, means, xerr=[c.policy_cost_se for c in rows], color=colors, capsize=3
        )
        for y, c in zip(positions, rows):
            ax_cost.text(
                c.policy_cost + c.policy_cost_se + 0.05,
                y,
                f"{c.policy_cost:.3f} ± {c.policy_cost_se:.3f}",
                va="center",
                fontsize=8,
            )
        best = rows[0]  # the combination is the proposal closest to optimal
        ax_cost.plot(
            [best.optimal_value] * 2,
            [base - 0.6, base + len(names) - 0.4],
            "k--",
            lw=1.2,
            label="certified optimum v*" if group == 0 else None,
        )
        ax_cost.text(
            best.optimal_value,
            base + len(names) - 0.3,
            f"{when}: v* = {best.optimal_value:.3f} ± {best.optimal_value_se:.3f}",
            fontsize=8.5,
            ha="center",
        )
    ticks = [base + k for base in (0, len(names) + 1.5) for k in range(len(names))]
    ax_cost.set_yticks(ticks, names * 2, fontsize=8.5)
    ax_cost.invert_yaxis()
    ax_cost.set_xlim(0, 1.3 * max(c.policy_cost for c in certificates.values()))
    ax_cost.set(
        xlabel=f"cost of the composite task ± SE (certified, {samples} samples)",
        title="expected cost J of the rest of the task vs the optimum",
    )
    ax_cost.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13))
    fig.suptitle(
        f"Coordination with a push: point mass with two acceptable outcomes (w = 1, 1), "
        f"{problem.require_grid('the coordination figure').describe()}, "
        f"λ = {problem.temperature:g}"
    )
    return [_save(fig, out, "coordination.png")]


# -- 5. the gymnast ---------------------------------------------------------------------------------


def gymnast(
    out, n: int = 71, dt: float = 0.05, fitting="terminal", reference: bool = True
) -> list[Path]:
    """The acrobot swing-up from (−105°, −15°) at rest on an n⁴ grid: still frames and a GIF.

    The grid-optimal policy is rolled out without noise; ``reference`` adds the deterministic
    optimum (:func:`gridlbc.trajectory.optimize`) dashed. The defaults are the best
    setting measured by ``benchmarks/gymnast.py`` (71⁴, Δt = 0.05, drift fitted to the terminal
    cost; its noise-free cost and final distance against the optimum's, and the solve's time and
    memory: docs page :doc:`studies`).
    """
    from .gymnast import animate_swingup, plot_swingup

    problem = gymnast_problem(n)
    solution = solve(problem, dt=dt, dtype="float32", fitting=fitting)
    run = simulate(problem, solution.policy, GYMNAST_START, 1, dt=0.002, noise=False)
    ref = None
    if reference:
        from ..trajectory import optimize

        optimum = optimize(problem, GYMNAST_START, n_intervals=300)
        ref = (optimum.times, optimum.states, optimum.controls)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    label = f"{n}⁴ grid, noise-free cost {run.costs[0]:.1f}"
    fig = plot_swingup(run.times, {label: (run.states[0], run.controls[0])}, reference=ref)
    still = _save(fig, out, "gymnast_swingup.png")
    gif = out / "gymnast.gif"
    animate_swingup(run.times, run.states[0], gif, title=f"gymnast {n}⁴")
    return [still, gif]


# -- 6. convergence ---------------------------------------------------------------------------------


def convergence(
    out,
    spacings=(4, 8, 16, 32),
    sizes=(64, 128, 256),
    temperatures=(1.0, 0.3, 0.1, 0.03, 0.01),
    temperature_grid: int = 128,
) -> list[Path]:
    """Error against h for the z-space and HJB solvers, and v, u as λ → 0
    (:mod:`gridlbc.studies.convergence`; ``benchmarks/convergence.py`` prints the tables)."""
    from .convergence import (
        pendulum_study,
        plot_convergence,
        plot_temperature,
        pointmass_study,
        temperature_study,
    )

    tables = [
        pointmass_study(spacings=tuple(1.0 / k for k in spacings)),
        pendulum_study(sizes=tuple(sizes)),
    ]
    paths = [_save(plot_convergence(tables), out, "convergence.png")]
    study = temperature_study(temperatures=tuple(temperatures), n=temperature_grid)
    paths.append(_save(plot_temperature(study), out, "temperature.png"))
    return paths


def plot_certified_convergence(study, labels=None):
    """Predicted v(x₀, 0) (solid) and the policy's cost J ± SE (dashed) of each configuration of a
    :class:`~gridlbc.studies.convergence.CertifiedStudy` against n, with the SDE's certified
    optimum v* ± 2 SE (black line, grey band: what the predictions estimate) and the chain's at
    the rollouts' step (dotted: what the policies' costs J are at least); ``labels`` picks
    configurations (default: all)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.8), constrained_layout=True)
    (v, se), (chain, _) = study.optimum, study.chain_optimum
    sizes = sorted({r.shape[0] for r in study.rows})
    ax.axhspan(v - 2 * se, v + 2 * se, color="0.85", label="certified v* ± 2 SE (the SDE's)")
    ax.axhline(v, color="k", lw=1.2)
    ax.axhline(
        chain, color="k", lw=1.0, ls=":", label=f"v* of the chain at Δt = {study.truth.dt:g}"
    )
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for color, label in zip(colors, labels or study.labels()):
        rows = study.select(label)
        n = [r.shape[0] for r in rows]
        ax.plot(n, [r.predicted for r in rows], "o-", color=color, label=f"{label}: predicted")
        ax.errorbar(
            n,
            [r.policy_cost for r in rows],
            [2 * r.policy_cost_se for r in rows],
            fmt="s--",
            color=color,
            capsize=3,
            label=f"{label}: its policy's cost J",
        )
    ax.set_xscale("log", base=2)
    ax.set_xticks(sizes, [str(k) for k in sizes])
    ax.set_xlabel("grid nodes per axis n (θ; ω has n + 1)")
    ax.set_ylabel("cost from x₀")
    scheme, n_truth, _ = study.proposal
    ax.set_title(
        f"Predicted value and policy cost vs the certified optimum v*(x₀) = {v:.2f}\n"
        f"(importance sampling extrapolated in its step, proposal: {scheme} {n_truth}², "
        f"ESS {study.truth.effective_sample_size:.0f} of {study.truth.n_samples})",
        fontsize=10,
    )
    ax.legend(fontsize=8, ncol=2)
    ax.grid(alpha=0.3)
    return fig


def certified_convergence(
    out, sizes=(32, 64, 128, 256), samples: int = 400, truth_samples: int = 2000, seed: int = 0
) -> list[Path]:
    """The pendulum swing-up from :data:`SWINGUP_START` as the grid is refined: each scheme's
    predicted value and its policy's cost against the certified optimum (rollouts at Δt = 0.002;
    ``benchmarks/swingup_accuracy.py`` prints the table)."""
    from .convergence import certified_study

    study = certified_study(
        swingup_problem,
        tuple(sizes),
        SWINGUP_START,
        (("splitting", None), ("fitted", None)),
        samples=samples,
        truth_samples=truth_samples,
        rollout_dt=0.002,
        seed=seed,
    )
    return [_save(plot_certified_convergence(study), out, "certified_convergence.png")]


# -- exit bays: composition of first-exit tasks --------------------------------------------------


BAY_WEIGHTS = ((1.0, 1.0, 1.0), (1.0, 0.02, 0.02), (0.02, 0.02, 1.0))
"""The combinations of the bays figure: any bay, the left one, the right one."""


def exit_bays(
    out, n: int = 161, samples: int = 2000, traces: int = 12, dt: float = 0.005, seed: int = 0
) -> list[Path]:
    """A point mass parks in one of three bays (a first-exit task, :func:`~.problems.bays_problem`):
    three components, each paying 0 at its own bay, solved once; their combinations with the
    weights :data:`BAY_WEIGHTS` are the optimal controllers of the composite exit costs
    (SPEC §9), made without solving again. For each: the value map with rollouts from
    :data:`~.problems.BAY_START`, the prediction against the certified optimum, and the blend
    weights α_i(x₀) = w_i z_i/Σ w_j z_j against the share of rollouts that parked in each bay
    (with the components' cost e^{−5/λ} ≈ 5e−5 elsewhere, α_i is the optimal process's
    probability of ending in bay i)."""
    from .problems import BAY_CENTRES, BAY_START, bay_cost, bays_problem

    plt = _pyplot()
    base = bays_problem(n)
    components = solve_many(base, [bay_cost(i) for i in range(3)])  # one factorisation
    fig, axes = plt.subplots(1, 4, figsize=(19, 4.6), constrained_layout=True)
    grid = base.require_grid("the bays figure")
    X, V = np.meshgrid(*grid.points(), indexing="ij")
    shares, alphas = [], []
    colours = ("tab:blue", "tab:orange", "tab:green")
    for ax, w in zip(axes[:3], BAY_WEIGHTS):
        combined = combine(components, w)
        value = combined.value(grid.nodes()).reshape(grid.shape)
        mesh = ax.pcolormesh(X, V, value, shading="auto", cmap="viridis", vmax=8.0)
        fig.colorbar(mesh, ax=ax, label="v (predicted)")
        ax.contour(X, V, base.exit_mask().reshape(grid.shape), [0.5], colors="white")
        runs = simulate(
            combined.problem, combined.policy, BAY_START, samples, dt=dt, seed=seed, max_time=15.0
        )
        bay = np.argmin(np.abs(runs.final_states[:, :1] - np.asarray(BAY_CENTRES)), axis=1)
        assert runs.exit_times is not None  # the problem has an exit set
        exit_times = runs.exit_times
        parked = ~np.isnan(exit_times)
        shares.append([np.mean(parked & (bay == i)) for i in range(3)])
        alphas.append(combined.blend_weights(BAY_START))
        for r in range(traces):
            end = int(np.searchsorted(runs.times, exit_times[r])) + 1 if parked[r] else None
            path = runs.states[r, :end]
            ax.plot(path[:, 0], path[:, 1], color=colours[bay[r]], lw=0.8, alpha=0.9)
        ax.plot(*BAY_START, "w*", ms=12)
        c = certify(
            combined.problem,
            combined.policy,
            BAY_START,
            samples,
            dt=dt,
            seed=seed + 1,
            max_time=15.0,
            progress=False,
        )
        predicted = float(combined.value(BAY_START))
        estimate = float(combined.error_estimate(BAY_START))
        ax.set_title(
            f"w = ({', '.join(f'{v:g}' for v in w)}): v(x₀) predicted {predicted:.3f} "
            f"(est. error {estimate:.3f}),\n"
            f"certified {c.optimal_value:.3f} ± {c.optimal_value_se:.3f} (Δt {dt:g}), "
            f"policy cost J = {c.policy_cost:.3f} ± {c.policy_cost_se:.3f}",
            fontsize=9,
        )
        ax.set_xlabel("position")
        ax.set_ylabel("velocity")
    ax = axes[3]
    width = 0.25
    for i in range(3):  # one bar per bay in each group of a weight setting
        spots = np.arange(len(BAY_WEIGHTS)) + (i - 1) * width
        share = np.array([s[i] for s in shares])
        se = np.sqrt(share * (1 - share) / samples)
        ax.bar(spots, share, width, yerr=2 * se, color=colours[i], label=f"parked in bay {i + 1}")
        ax.plot(spots, [a[i] for a in alphas], "kD", ms=5, label="α_i(x₀)" if i == 0 else None)
    labels = ["w = (" + ", ".join(f"{v:g}" for v in w) + ")" for w in BAY_WEIGHTS]
    ax.set_xticks(np.arange(len(BAY_WEIGHTS)), labels, fontsize=8)
    ax.set_ylabel("share of rollouts (±2 SE)")
    ax.set_title("blend weights α_i(x₀) = where it parks", fontsize=10)
    ax.legend(fontsize=8)
    fig.suptitle(
        f"Tasks that end: park in one of three bays (point mass, {n}² grid, "
        f"λ = {base.temperature:g}); three exit-cost components solved once, recombined",
        fontsize=11,
    )
    return [_save(fig, out, "exit_bays.png")]


# -- all --------------------------------------------------------------------------------------------


FIGURES: dict[str, tuple[Callable[..., list[Path]], dict[str, Any], dict[str, Any]]] = {
    "cost_reward_space": (cost_reward_space, {}, {"n": 61}),
    "projection": (projection, {}, {"points": 401}),
    "interpolation": (
        interpolation,
        {},
        {"n": 41, "samples": 300, "traces": 10, "dt": 0.02, "restarts": 8},
    ),
    "coordination": (coordination, {}, {"n": 41, "samples": 200, "traces": 4, "dt": 0.02}),
    "gymnast": (gymnast, {}, {"n": 13, "reference": False}),
    "certified_convergence": (
        certified_convergence,
        {},
        {"sizes": (16, 32), "samples": 40, "truth_samples": 80},
    ),
    "exit_bays": (exit_bays, {}, {"n": 41, "samples": 100, "traces": 4, "dt": 0.02}),
    "convergence": (
        convergence,
        {},
        {"spacings": (2, 4), "sizes": (32, 64), "temperatures": (1.0, 0.1), "temperature_grid": 48},
    ),
}
"""name → (function, full-size options, quick options)."""


def make_all(out, quick: bool = False, only=None, progress: bool = True) -> list[Path]:
    """Write every figure (or those named in ``only``) to ``out``; returns the paths written."""
    names = list(FIGURES) if only is None else list(only)
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        raise ValueError(f"unknown figure {unknown[0]!r}: choose from {', '.join(FIGURES)}")
    say = print if progress else (lambda *a, **k: None)
    written = []
    for name in names:
        function, full, small = FIGURES[name]
        started = time.perf_counter()
        say(f"{name}: ...", end="", flush=True)
        paths = function(out, **(small if quick else full))
        written += paths
        say(f"\r{name}: {', '.join(str(p) for p in paths)} ({time.perf_counter() - started:.1f} s)")
    return written
