"""The figure gallery: the paper's ideas on systems you can picture (``gridlbc figures``).

One function per figure; each takes the output folder and a size knob (grid nodes per axis,
Monte-Carlo samples) so that tests can run it small, and returns the paths it wrote.
:func:`make_all` writes them all (``quick=True``: small sizes, for a look in seconds).

- :func:`cost_reward_space` — v = −λ log z, z and u* of the pendulum swing-up (paper Fig. 2).
- :func:`projection` — projecting a target reward h̄ = exp(−ḡ/λ) onto component rewards
  h_i = exp(−g_i/λ), when it works (Fig. 3) and when the components are too far apart (Fig. 4).
- :func:`interpolation` — an intermediate goal on the pendulum: linear Bellman combination with
  the projected weights vs the naive blend of policies vs the direct solve (Fig. 6 idea).
- :func:`coordination` — blend weights α over time for a two-goal point mass pushed mid-way
  (Fig. 9 idea).
- :func:`gymnast` — the acrobot swing-up from the paper's test state (Fig. 7 setting), a still
  and a GIF (the study of :mod:`gridlbc.studies.gymnast`).
- :func:`certified_convergence` — the swing-up's predicted value and its policy's cost against
  the certified optimum as the grid is refined (:func:`gridlbc.certify`).
- :func:`convergence` — error against grid spacing and the small-temperature study
  (:mod:`gridlbc.studies.convergence`).
"""

from __future__ import annotations

import math
import time
import warnings
from pathlib import Path

import numpy as np

from ..combine import CompositeCost, combine, naive_blend
from ..costs import Quadratic
from ..problem import Problem
from ..project import ProjectionWarning
from ..project import projection as project_weights
from ..simulate import simulate
from ..solver import solve, solve_many
from .problems import (
    GOAL_WEIGHTS,
    GYMNAST_START,
    SWINGUP_START,
    coordination_problem,
    gymnast_problem,
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


def _wrap(theta):
    """Angles to [−π, π)."""
    return np.mod(np.asarray(theta) + math.pi, 2 * math.pi) - math.pi


# -- 1. cost space vs reward space -------------------------------------------------------------------


def cost_reward_space(out, n: int = 201) -> list[Path]:
    """Value, desirability and policy of the pendulum swing-up at t = 0 on an n × n grid."""
    from .demo import plot_fields

    problem = swingup_problem(n)
    solution = solve(problem)
    path = Path(out) / "cost_reward_space.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    plot_fields(solution, path, f"Pendulum swing-up, cost space vs reward space "
                f"({problem.grid.describe()}, T = {problem.horizon:g}, λ = "
                f"{problem.temperature:g}, g = 10θ² + 0.5ω²): t = 0")
    return [path]


# -- 2. projection of terminal rewards ----------------------------------------------------------------


PROJECTION_CASES = (
    ("components close enough (paper Fig. 3)", (-0.5, 0.5), 0.5, 0.2),
    ("components too far apart (paper Fig. 4)", (0.0, 1.0), 25.0, 0.5),
)
"""(title, component centres, weight W of g = W (x − c)², target centre ḡ) in one dimension."""


def projection(out, points: int = 801, temperature: float = 1.0) -> list[Path]:
    """Project a 1-D target reward onto two component rewards, in reward and in cost space.

    Top: h_i = exp(−g_i/λ), the target h̄ and the reconstruction Σ w_i h_i. Bottom: the costs g_i,
    ḡ and the cost the combination really optimises, −λ log Σ w_i h_i, with its minima marked.
    """
    plt = _pyplot()
    lam = temperature
    x = np.linspace(-1.5, 2.5, points)[:, None]
    fig, axes = plt.subplots(2, 2, figsize=(12, 7), sharex=True, constrained_layout=True)
    for col, (title, centres, W, target_centre) in enumerate(PROJECTION_CASES):
        components = [Quadratic([c], [W]) for c in centres]
        target = Quadratic([target_centre], [W])
        result = project_weights(target, components, temperature=lam)
        w = result.weights
        h = [np.exp(-c(x) / lam) for c in components]
        blended = CompositeCost(tuple(components), w, lam)(x)
        top, bottom = axes[:, col]
        for i, h_i in enumerate(h):
            top.plot(x, h_i, color=f"C{i}", label=f"h{i + 1}, w{i + 1} = {w[i]:.3f}")
            bottom.plot(x, components[i](x), color=f"C{i}", label=f"g{i + 1}")
        top.plot(x, np.exp(-target(x) / lam), "k--", label="target h̄")
        top.plot(x, sum(wi * hi for wi, hi in zip(w, h)), "C3", lw=2, label="Σ wᵢ hᵢ")
        bottom.plot(x, target(x), "k--", label="target ḡ")
        bottom.plot(x, blended, "C3", lw=2, label="−λ log Σ wᵢ hᵢ (what LBC optimises)")
        minima = np.flatnonzero((blended[1:-1] < blended[:-2]) & (blended[1:-1] < blended[2:])) + 1
        bottom.plot(x[minima, 0], blended[minima], "v", color="C3", ms=9,
                    label=f"its minima: x = {', '.join(f'{v:.2f}' for v in x[minima, 0])}")
        verdict = (f"{len(result.messages)} ProjectionWarnings" if result.messages
                   else "no warnings")
        top.set_title(f"{title}\nΣw = {result.weight_sum:.2f}, residual "
                      f"‖h̄ − Σwh‖/‖h̄‖ = {result.residual:.2f}; {verdict}", fontsize=10)
        top.set_ylabel("reward h = exp(−g/λ)")
        bottom.set_ylabel("cost g")
        bottom.set_xlabel("state x")
        bottom.set_ylim(-0.5, 6)
        top.legend(fontsize=8, loc="upper right")
        bottom.legend(fontsize=8, loc="upper right")
    fig.suptitle(f"Projecting a target terminal reward onto component rewards (λ = {lam:g}, "
                 "g = W (x − c)²)")
    return [_save(fig, out, "projection.png")]


# -- 3. interpolation -------------------------------------------------------------------------------


def interpolation(out, n: int = 151, samples: int = 1000, seed: int = 0, a: float = 0.5,
                  target_theta: float = 0.0, weights=(2.0, 0.5)) -> list[Path]:
    """Pendulum swing-up to an intermediate goal: LBC vs naive blend vs direct optimum.

    Components: upright leaning θ = −a and θ = +a; target θ̄ between them; all with
    g = (x − c)ᵀdiag(weights)(x − c). The weights come from projecting h̄ onto {h_1, h_2}; LBC
    uses u = Σ α_i u_i with α_i = w_i z_i / Σ w_j z_j, the naive blend u = Σ w_i u_i / Σ w_i.
    All are rolled out from the same start with the same noise (same seed) and charged the
    *target* task's cost. The defaults are those of ``gridlbc verify``'s interpolation check.
    """

    plt = _pyplot()
    weights = list(weights)
    components = [Quadratic([-a, 0.0], weights), Quadratic([a, 0.0], weights)]
    target = Quadratic([target_theta, 0.0], weights)
    problem = swingup_problem(n).replace(terminal_cost=target)
    lam = problem.temperature
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ProjectionWarning)  # shown in the figure instead
        result = project_weights(target, components, problem.grid, temperature=lam)
    first, second, direct = solve_many(problem, components + [target])
    controllers = {
        f"goal θ = −{a:g} alone": first.policy,
        f"goal θ = +{a:g} alone": second.policy,
        "naive blend Σwᵢuᵢ/Σwᵢ": naive_blend([first, second], result.weights).policy,
        "LBC Σαᵢuᵢ": combine([first, second], result.weights).policy,
        "direct solve of ḡ": direct.policy,
    }
    colors = ["0.6", "0.75", "C1", "C3", "k"]
    clean = {k: simulate(problem, p, SWINGUP_START, 1, noise=False) for k, p in controllers.items()}
    noisy = {k: simulate(problem, p, SWINGUP_START, samples, seed=seed) for k, p in controllers.items()}

    fig, axes = plt.subplots(2, 2, figsize=(13, 8.5), constrained_layout=True)
    (ax_h, ax_t), (ax_hist, ax_cost) = axes
    theta = np.linspace(-1.2, 1.2, 481)
    states = np.column_stack([theta, np.zeros_like(theta)])
    h = [np.exp(-problem.replace(terminal_cost=c).terminal_values(states) / lam)
         for c in components]
    for i, (h_i, w_i) in enumerate(zip(h, result.weights)):
        ax_h.plot(theta, h_i, color=colors[i], label=f"h{i + 1} (θ = {components[i].center[0]:+g}),"
                  f" w{i + 1} = {w_i:.3f}")
    ax_h.plot(theta, np.exp(-target(states) / lam), "k--", label=f"target h̄ (θ̄ = {target_theta:g})")
    ax_h.plot(theta, sum(w * hi for w, hi in zip(result.weights, h)), "C3", lw=2, label="Σ wᵢ hᵢ")
    ax_h.set(xlabel="θ_T (rad from upright), ω_T = 0", ylabel="terminal reward h = exp(−g/λ)",
             title=f"projected weights: residual {result.residual:.2f}, Σw = "
                   f"{result.weight_sum:.2f}")
    ax_h.legend(fontsize=8)

    for (label, run), color in zip(clean.items(), colors):
        lw = 1 if "alone" in label else 2
        ax_t.plot(run.times, np.unwrap(run.states[0, :, 0]), color=color, lw=lw, label=label)
    ax_t.axhline(target_theta, color="k", ls=":", lw=1)
    ax_t.set(xlabel="t (s)", ylabel="θ (rad, unwrapped)",
             title=f"noise-free closed loop from θ = {SWINGUP_START[0]:g}, ω = 0")
    ax_t.legend(fontsize=8)

    bins = np.linspace(-np.pi, np.pi, 61)
    for (label, run), color in list(zip(noisy.items(), colors))[2:]:
        ax_hist.hist(_wrap(run.final_states[:, 0]), bins=bins, histtype="step", lw=2, color=color,
                     label=f"{label}: median |θ_T − θ̄| = "
                           f"{np.median(np.abs(_wrap(run.final_states[:, 0] - target_theta))):.2f}")
    ax_hist.axvline(target_theta, color="k", ls=":", lw=1)
    ax_hist.set(xlabel="final θ_T (rad)", ylabel="samples",
                title=f"final angles with noise (λ = {lam:g}), {samples} samples each")
    ax_hist.legend(fontsize=8)

    names = list(noisy)
    means = [noisy[k].mean_cost for k in names]
    errors = [noisy[k].standard_error for k in names]
    ax_cost.barh(range(len(names)), means, xerr=errors, color=colors, capsize=4)
    predicted = float(direct.value(SWINGUP_START, 0.0)[0])
    ax_cost.axvline(predicted, color="k", ls="--", lw=1,
                    label=f"direct solve's prediction v(x₀) = {predicted:.2f}")
    for k, (m, e) in enumerate(zip(means, errors)):
        ax_cost.text(m + e + 0.2, k, f"{m:.2f} ± {e:.2f}", va="center", fontsize=9)
    ax_cost.set_yticks(range(len(names)), names, fontsize=9)
    ax_cost.set_xlim(0, 1.25 * max(means))
    ax_cost.set(xlabel="mean cost of the target task ± SE (same noise for all)",
                title="expected cost J = E[ḡ(x_T) + ∫½u² dt]")
    ax_cost.legend(fontsize=8, loc="lower right")
    fig.suptitle(f"Interpolating an intermediate goal on the pendulum ({problem.grid.describe()}, "
                 f"T = {problem.horizon:g}, g = {weights[0]:g}(θ − c)² + {weights[1]:g}ω²)")
    return [_save(fig, out, "interpolation.png")]


# -- 4. coordination with a push ----------------------------------------------------------------------


def simulate_with_push(problem: Problem, policy, x0, push_time: float, kick, n_samples: int = 1,
                       seed=None, noise: bool = True, dt: float = 0.01):
    """Roll ``policy`` out on [0, T] with the state kicked by ``kick`` at ``push_time``.

    Two :func:`gridlbc.simulate` calls: on [0, t_p] (the problem with horizon t_p), then from the
    pushed states on [t_p, T] (horizon T − t_p, the policy's clock shifted by t_p). Returns
    ``(times, states (n, k, d))`` on the joined time grid, where t_p appears twice: the state just
    before the kick, then just after it.
    """
    if not 0 < push_time < problem.horizon:
        raise ValueError(f"push_time must lie in (0, T = {problem.horizon:g}), got {push_time}")
    before = simulate(problem.replace(horizon=push_time), policy, x0, n_samples, dt=dt,
                      seed=seed, noise=noise)
    pushed = before.final_states + np.asarray(kick, dtype=float)
    after = simulate(problem.replace(horizon=problem.horizon - push_time),
                     lambda x, t: policy(x, t + push_time), pushed, n_samples, dt=dt,
                     seed=None if seed is None else seed + 1, noise=noise)
    times = np.concatenate([before.times, push_time + after.times])
    return times, np.concatenate([before.states, pushed[:, None], after.states[:, 1:]], axis=1)


def coordination(out, n: int = 81, samples: int = 12, seed: int = 0) -> list[Path]:
    """α over time of a two-goal combined controller (w = 1, 1), pushed mid-way.

    The point mass starts at x = 0.3 at rest, nearer the goal x = +1, so α₊ ≈ 1; at t = 1 s a
    push sets its velocity to −2.5 m/s and the combination switches to the goal x = −1 on its own:
    α = w_i z_i / Σ w_j z_j follows which goal is now cheaper to reach.
    """
    plt = _pyplot()
    problem = coordination_problem(n)
    goals = [problem.terminal_cost, Quadratic([1.0, 0.0], GOAL_WEIGHTS)]
    combined = combine(solve_many(problem, goals))
    x0, push_time, kick = np.array([0.3, 0.0]), 1.0, np.array([0.0, -1.5])
    runs = {"noise-free": simulate_with_push(combined.problem, combined.policy, x0, push_time, kick,
                                             noise=False),
            "with noise": simulate_with_push(combined.problem, combined.policy, x0, push_time, kick,
                                             samples, seed=seed)}
    fig, (ax_alpha, ax_x) = plt.subplots(2, 1, figsize=(10, 7), sharex=True,
                                         constrained_layout=True)
    for label, (times, states) in runs.items():
        alpha = np.stack([combined.blend_weights(states[:, k], min(t, problem.horizon))[:, 1]
                          for k, t in enumerate(times)], axis=1)
        style = ({"color": "C0", "lw": 2.5} if label == "noise-free"
                 else {"color": "C1", "lw": 0.7, "alpha": 0.6})
        for s in range(states.shape[0]):
            name = label if s == 0 else None
            ax_alpha.plot(times, alpha[s], label=name, **style)
            ax_x.plot(times, states[s, :, 0], label=name, **style)
    for ax in (ax_alpha, ax_x):
        ax.axvline(push_time, color="k", ls=":", lw=1)
        ax.grid(alpha=0.3)
    ax_alpha.text(push_time + 0.03, 0.5, f"push: velocity {kick[1]:+g} m/s", fontsize=9)
    ax_alpha.set(ylabel="α₊ = z₊ / (z₋ + z₊)", ylim=(-0.03, 1.03),
                 title="blend weight of the controller for goal x = +1")
    ax_alpha.legend(fontsize=9, loc="lower left")
    for goal in (-1, 1):
        ax_x.axhline(goal, color="0.5", ls="--", lw=1)
    ax_x.set(xlabel="t (s)", ylabel="position x (m)", title="position; goals at x = ±1 (dashed)")
    fig.suptitle(f"Coordination: point mass with two acceptable outcomes (w = 1, 1), "
                 f"{problem.grid.describe()}, λ = {problem.temperature:g}")
    return [_save(fig, out, "coordination.png")]


# -- 5. the gymnast ---------------------------------------------------------------------------------


def gymnast(out, n: int = 71, dt: float = 0.05, fitting="terminal",
            reference: bool = True) -> list[Path]:
    """The acrobot swing-up from (−105°, −15°) at rest on an n⁴ grid: still frames and a GIF.

    The grid-optimal policy is rolled out without noise; ``reference`` adds the deterministic
    optimum (:func:`gridlbc.trajectory.optimize`) dashed. The defaults are the best
    setting measured by ``benchmarks/gymnast.py`` (71⁴, Δt = 0.05, drift fitted to the terminal
    cost: noise-free cost 15.9, ending 0.75 rad from the handstand, against the optimum's 13.18);
    the solve takes about 1.5 minutes and 7 GiB.
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


def convergence(out, spacings=(4, 8, 16, 32), sizes=(64, 128, 256),
                temperatures=(1.0, 0.3, 0.1, 0.03, 0.01), temperature_grid: int = 128
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

    tables = [pointmass_study(spacings=tuple(1.0 / k for k in spacings)),
              pendulum_study(sizes=tuple(sizes))]
    paths = [_save(plot_convergence(tables), out, "convergence.png")]
    study = temperature_study(temperatures=tuple(temperatures), n=temperature_grid)
    paths.append(_save(plot_temperature(study), out, "temperature.png"))
    return paths


def plot_certified_convergence(study, labels=None):
    """Predicted v(x₀, 0) (solid) and the policy's cost J ± SE (dashed) of each configuration of a
    :class:`~gridlbc.studies.convergence.CertifiedStudy` against n, with the certified optimum
    v* ± SE (black line, grey band); ``labels`` picks configurations (default: all)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.8), constrained_layout=True)
    v, se = study.truth.optimal_value, study.truth.optimal_value_se
    sizes = sorted({r.shape[0] for r in study.rows})
    ax.axhspan(v - 2 * se, v + 2 * se, color="0.85", label="certified v* ± 2 SE")
    ax.axhline(v, color="k", lw=1.2)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for color, label in zip(colors, labels or study.labels()):
        rows = study.select(label)
        n = [r.shape[0] for r in rows]
        ax.plot(n, [r.predicted for r in rows], "o-", color=color, label=f"{label}: predicted")
        ax.errorbar(n, [r.policy_cost for r in rows], [2 * r.policy_cost_se for r in rows],
                    fmt="s--", color=color, capsize=3, label=f"{label}: its policy's cost J")
    ax.set_xscale("log", base=2)
    ax.set_xticks(sizes, [str(k) for k in sizes])
    ax.set_xlabel("grid nodes per axis n (θ; ω has n + 1)")
    ax.set_ylabel("cost from x₀")
    scheme, n_truth, _ = study.proposal
    ax.set_title(f"Predicted value and policy cost vs the certified optimum v*(x₀) = {v:.2f}\n"
                 f"(importance sampling, proposal: {scheme} {n_truth}², "
                 f"ESS {study.truth.effective_sample_size:.0f} of {study.truth.n_samples})",
                 fontsize=10)
    ax.legend(fontsize=8, ncol=2)
    ax.grid(alpha=0.3)
    return fig


def certified_convergence(out, sizes=(32, 64, 128, 256), samples: int = 400,
                          truth_samples: int = 2000, seed: int = 0) -> list[Path]:
    """The pendulum swing-up from :data:`SWINGUP_START` as the grid is refined: each scheme's
    predicted value and its policy's cost against the certified optimum (rollouts at Δt = 0.002;
    ``benchmarks/swingup_accuracy.py`` prints the table)."""
    from .convergence import certified_study

    study = certified_study(swingup_problem, tuple(sizes), SWINGUP_START,
                            (("splitting", None), ("fitted", None)), samples=samples,
                            truth_samples=truth_samples, rollout_dt=0.002, seed=seed)
    return [_save(plot_certified_convergence(study), out, "certified_convergence.png")]


# -- all --------------------------------------------------------------------------------------------


FIGURES = {
    "cost_reward_space": (cost_reward_space, {}, {"n": 61}),
    "projection": (projection, {}, {"points": 401}),
    "interpolation": (interpolation, {}, {"n": 61, "samples": 200}),
    "coordination": (coordination, {}, {"n": 41, "samples": 6}),
    "gymnast": (gymnast, {}, {"n": 13, "reference": False}),
    "certified_convergence": (certified_convergence, {},
                              {"sizes": (16, 32), "samples": 40, "truth_samples": 80}),
    "convergence": (convergence, {}, {"spacings": (2, 4), "sizes": (32, 64),
                                      "temperatures": (1.0, 0.1), "temperature_grid": 48}),
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
