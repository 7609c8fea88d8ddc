"""The paper's gymnast (acrobot) swing-up study: the problem, its test state and its figures,
and the trajectory trackers of the paper's Fig. 7 (:data:`TRACKER_STARTS`, :class:`GreedySwitch`,
:func:`plot_trackers`; the tables come from ``benchmarks/gymnast_trackers.py``).

Problem (paper §6.2): the :class:`gridlbc.systems.Acrobot` in canonical momenta,
T = 3 s, λ = 1, R = 1, q = 0 and the terminal cost

    g(x) = xᵀ diag(10, 10, 0.5, 0.5) x        (θ1 wrapped to the nearest image of 0),

on the box θ1 ∈ [−π, π) (periodic) × θ2 ∈ [−H, H] × |p1| ≤ P1 × |p2| ≤ P2, from the test state
(θ1, θ2) = (−105°, −15°) at rest.

The hip. A gymnast's legs cannot pass through the arms, so by default the hip angle lives on a
closed axis with stops at H = π (the box edge is a state constraint) and g is the plain
quadratic in θ2. This is the problem whose deterministic optimum (``gridlbc.trajectory.optimize``)
sets the accuracy target: its cost, its distance from the handstand, the hip range it uses and the
momenta it reaches are tabled in docs page :doc:`benchmarks` (the acrobot). ``hip_range=None``
makes the hip a free joint instead (θ2 periodic, g wrap-aware in θ2): the optimum then rotates the
legs through the arms and is much cheaper (same page, "Which hip").

The momentum box P1 = 16, P2 = 9 leaves a margin around the optimal swing-up's momenta (the
box edge must not bend optimal paths) while spending as few nodes as possible on momenta the
swing-up never uses: a wider box costs resolution h = 2P/(n − 1), and numerical diffusion grows
with h.
"""

from __future__ import annotations

import numpy as np

from ..costs import wrap_angle
from ..systems import Acrobot

TRACKER_STARTS = np.radians(
    [[-90.0, 0.0], [-110.0, -20.0], [-120.0, -5.0], [-80.0, -25.0], [-100.0, 5.0], [-95.0, -30.0]]
)
"""(θ1, θ2) of the trackers' start states, at rest: the paper's two (Fig. 7) first, then four
more around the test state for the coverage study."""


def at_rest(angles) -> np.ndarray:
    """States (θ1, θ2, 0, 0) for angles ``(N, 2)`` (or one pair): ``(N, 4)``."""
    angles = np.atleast_2d(np.asarray(angles, dtype=float))
    return np.concatenate([angles, np.zeros_like(angles)], axis=1)


class GreedySwitch:
    """Switching between components: at each state follow the one with the largest blend weight
    α_i = w_i z_i / Σ_j w_j z_j of ``combination`` (the discrete choice that the paper's
    smooth blend replaces)."""

    def __init__(self, combination):
        self.combination = combination

    def policy(self, x, t) -> np.ndarray:
        x = np.atleast_2d(x)
        best = np.argmax(self.combination.blend_weights(x, t), axis=1)
        u = np.zeros((len(x), self.combination.problem.system.control_dim))
        for i, c in enumerate(self.combination.components):
            rows = best == i
            if np.any(rows):
                u[rows] = c.policy(x[rows], t)
        return u


def plot_trackers(trackers: dict, runs: dict, times, alpha, path=None):
    """The trackers' nominal paths and noise-free rollouts from the test state in the (θ1, θ2)
    plane (angles unwrapped: the handstand is any multiple of 360° in θ1), the torques, and the
    blend weights α_i(t) along the LBC rollout.

    ``trackers`` maps a label to a Trajectory; ``runs`` a label to ``(states (k, 4), controls
    (k − 1, 1))`` on ``times``; ``alpha`` is ``(k, n)`` along the rollout labelled "LBC".
    Returns the figure (saved to ``path`` when given).
    """
    import matplotlib.pyplot as plt

    fig, (ax_path, ax_u, ax_a) = plt.subplots(1, 3, figsize=(15, 4.6))
    for label, trajectory in trackers.items():
        deg = np.degrees(trajectory.states[:, :2])
        ax_path.plot(deg[:, 0], deg[:, 1], "--", lw=2.5, alpha=0.5, label=f"{label} (nominal)")
        ax_path.plot(*deg[0], "o", color=ax_path.lines[-1].get_color())
    for label, (states, controls) in runs.items():
        deg = np.degrees(np.unwrap(states[:, :2], axis=0))  # rollouts wrap θ1; paths do not
        # LBC follows one tracker closely for most of the run: draw it wide and faint
        # underneath, so the tracker it follows stays visible on top
        style = {"lw": 4.0, "alpha": 0.45, "zorder": 1} if label == "LBC" else {"lw": 1.2}
        (line,) = ax_path.plot(deg[:, 0], deg[:, 1], "-", label=label, **style)
        ax_u.plot(times[:-1], np.ravel(controls), "-", color=line.get_color(), label=label, **style)
    start = np.degrees(next(iter(runs.values()))[0][0, :2])
    ax_path.plot(*start, "k*", ms=12, label="test start")
    for turn in (-720, -360, 0):
        ax_path.plot(turn, 0, "kP", ms=10, label="handstand" if turn == 0 else None)
    ax_path.set(
        xlabel="θ1 [deg] (0 = upright)",
        ylabel="θ2 [deg]",
        title="nominal paths (dashed), noise-free rollouts from (−105°, −15°)",
    )
    ax_path.legend(fontsize=7)
    ax_u.set(xlabel="t [s]", ylabel="hip torque u [N·m]", title="hip torque of the rollouts")
    ax_u.legend(fontsize=7)
    for i in range(alpha.shape[1]):
        ax_a.plot(times, alpha[:, i], label=f"α{i + 1}")
    ax_a.set(
        xlabel="t [s]",
        ylabel="blend weight",
        ylim=(-0.05, 1.05),
        title="LBC blend weights along its rollout",
    )
    ax_a.legend(fontsize=8)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def angle_distance(states) -> np.ndarray:
    """Distance of (θ1, θ2) from the handstand (0, 0), angles wrapped to [−π, π): ``(N,)``."""
    x = np.atleast_2d(np.asarray(states, dtype=float))
    return np.linalg.norm(wrap_angle(x[:, :2]), axis=1)


def _link_points(system: Acrobot, states: np.ndarray) -> np.ndarray:
    """Hand, hip and foot positions (x right, y up) for states ``(k, 4)``: ``(k, 3, 2)``."""
    t1, t2 = states[:, 0], states[:, 1]
    hip = system.l1 * np.stack([-np.sin(t1), np.cos(t1)], axis=1)
    foot = hip + system.l2 * np.stack([-np.sin(t1 + t2), np.cos(t1 + t2)], axis=1)
    return np.stack([np.zeros_like(hip), hip, foot], axis=1)


def plot_swingup(times, runs: dict, path=None, reference=None):
    """Angles, momenta and torque against time for labelled runs, plus stick-figure snapshots.

    ``runs`` maps a label to ``(states (k, 4), controls (k − 1,))`` on ``times``; ``reference``
    optionally gives ``(times, states, controls)`` of the deterministic optimum, drawn dashed.
    Returns the figure (saved to ``path`` when given).
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 7))
    (ax_angle, ax_mom), (ax_u, ax_stick) = axes
    curves = dict(runs)
    if reference is not None:
        curves = {"deterministic optimum": reference[1:], **curves}
    for label, (states, controls) in curves.items():
        t = reference[0] if label == "deterministic optimum" else times
        style = "--" if label == "deterministic optimum" else "-"
        wrapped = wrap_angle(states[:, :2])
        (line,) = ax_angle.plot(t, np.degrees(wrapped[:, 0]), style, label=f"θ1 {label}")
        ax_angle.plot(t, np.degrees(wrapped[:, 1]), style, color=line.get_color(), alpha=0.5)
        ax_mom.plot(t, states[:, 2], style, color=line.get_color(), label=f"p1 {label}")
        ax_mom.plot(t, states[:, 3], style, color=line.get_color(), alpha=0.5)
        ax_u.step(
            t[:-1], np.ravel(controls), style, where="post", color=line.get_color(), label=label
        )
    ax_angle.set(xlabel="t [s]", ylabel="θ1 (dark), θ2 (light) [deg]", title="angles from upright")
    ax_mom.set(xlabel="t [s]", ylabel="p1 (dark), p2 (light)", title="canonical momenta")
    ax_u.set(xlabel="t [s]", ylabel="hip torque u", title="control")
    ax_u.legend(fontsize=8)
    label, (states, _) = next(iter(runs.items()))
    points = _link_points(Acrobot(), states)
    for k in np.linspace(0, len(states) - 1, 12).astype(int):
        shade = 0.2 + 0.8 * k / (len(states) - 1)
        ax_stick.plot(points[k, :, 0], points[k, :, 1], "-o", color=(0.1, 0.2, 0.6, shade), ms=3)
    ax_stick.plot(points[:, 2, 0], points[:, 2, 1], ":", color="grey", lw=0.8)
    ax_stick.set(
        aspect="equal",
        xlim=(-2.2, 2.2),
        ylim=(-2.2, 2.2),
        title=f"{label}\n(light to dark in time)",
    )
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def animate_swingup(times, states, path, fps: int = 25, title: str = "gymnast swing-up"):
    """Write an animated GIF of the gymnast following ``states`` ``(k, 4)`` on ``times``."""
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    times, states = np.asarray(times), np.asarray(states)
    frames = np.searchsorted(times, np.arange(0.0, times[-1] + 1e-9, 1.0 / fps))
    frames = np.minimum(frames, len(times) - 1)
    points = _link_points(Acrobot(), states)
    fig, ax = plt.subplots(figsize=(4, 4))
    ax.set(aspect="equal", xlim=(-2.2, 2.2), ylim=(-2.2, 2.2), xticks=[], yticks=[])
    ax.plot([-0.3, 0.3], [0, 0], color="k", lw=3)
    (body,) = ax.plot([], [], "-o", color="tab:blue", lw=3, ms=6)
    (trail,) = ax.plot([], [], ":", color="grey", lw=0.8)
    label = ax.set_title(title)

    def draw(k):
        body.set_data(points[k, :, 0], points[k, :, 1])
        trail.set_data(points[: k + 1, 2, 0], points[: k + 1, 2, 1])
        label.set_text(f"{title}  t = {times[k]:.2f} s")
        return body, trail, label

    animation = FuncAnimation(fig, draw, frames=frames, blit=False)
    animation.save(path, writer=PillowWriter(fps=fps))
    plt.close(fig)
