"""The certified optimum: the true optimal cost from a start state, and how far a policy is from it.

Run ANY policy u(x, t) (a grid solution, a combination, a trajectory tracker, a controller of your
own) on the problem's SDE, dx = (a + B u) dt + B dε with Cov[dε] = λ R⁻¹ dt, and accumulate per
sample

    S_u = g(x_T) + ∫₀ᵀ ( q + ½ uᵀ R u ) dt + ∫₀ᵀ uᵀ R dε          (Itô).

**Why this is exact.** The desirability is a Feynman–Kac expectation over the *uncontrolled*
process (paper §3.1: the passive dynamics), z*(x₀) = E₀[exp(−(g + ∫q dt)/λ)], because
z = exp(−v/λ) solves the linear PDE −∂ₜz = −(q/λ)z + aᵀ∇z + (λ/2) tr(B R⁻¹ Bᵀ∇²z). Girsanov's
theorem changes the measure to the process driven by u: the likelihood ratio of the passive paths to
the controlled ones is exp(−(1/λ)(∫uᵀR dε + ½∫uᵀRu dt)), with dε the noise of the controlled run.
Hence, for every policy u,

    z*(x₀) = E_u[ exp(−S_u/λ) ],        v*(x₀) = −λ log E_u[ exp(−S_u/λ) ].

The estimate does not use the policy's claimed value: u only sets the variance, which is zero for
the optimal policy (then S_u = v*(x₀) on every path). For the Euler–Maruyama chain used here the
change of measure is exact step by step (the ratio of the two Gaussian transition densities), so the
estimate is the chain's Feynman–Kac value for any u, and differs from the SDE's only by the
scheme's O(Δt) weak error. The policy's own cost J(u) = E_u[g + ∫(q + ½uᵀRu) dt] on the same
samples satisfies J(u) − v* = λ KL(P_u ‖ P*) ≥ 0: the gap measures how suboptimal u is.

**Error bars.** With weights w = exp(−S_u/λ) (computed relative to their largest, so nothing
underflows at small λ) and n samples, the delta method gives SE(v̂*) = λ σ̂(w) / (√n w̄). The gap
Ĵ − v̂* = C̄ + λ log w̄ (C the sample's cost) is estimated from the same samples, and its SE is that
of the paired linearisation C + λ w / w̄. The effective sample size (Σw)² / Σw² says how many
samples effectively carry the estimate: close to n for a near-optimal proposal, collapsing when the
proposal is far from optimal or λ is small (the weights then grow sharp). The log of a mean is
biased upward by about SE²/(2λ), negligible when the SE is.

**Tail diagnostic.** Neither the ESS nor the delta-method SE can see weight that the samples never
reached: with a heavy right tail of w, −λ log w̄ is biased upward and both look fine. The PSIS
shape k̂ (:func:`gridlbc.psis.pareto_k`; Vehtari, Simpson, Gelman, Yao & Gabry, "Pareto smoothed
importance sampling", JMLR 2024) fits a generalized Pareto tail to the largest weights: k̂ < 0.5
reliable, 0.5–0.7 slow but usable, above 0.7 (:data:`MAX_PARETO_K`) unreliable at any practical
sample count. A certificate is trusted only with enough effective samples *and* k̂ below that;
the remedy for a large k̂ is a proposal closer to optimal, not more samples.

**Pooled proposals.** Any policy is a valid proposal, so several can share the samples: with
u_1…u_J drawing n_j = c_j n paths each, the balance heuristic of multiple importance sampling
(Veach & Guibas 1995) weights a path by exp(−(g + ∫q dt)/λ) / Σ_j c_j dQ_j/dP, the passive
process's density over the pool's. Each ratio dQ_j/dP is a product of Gaussian transition
densities of the chain (:func:`gridlbc.simulate.euler_maruyama` accumulates it for every member
along every path), so the pooled estimate is exact for the chain as one proposal's is, and its
weights are at most 1/c_j times member j's own: the pool is nearly as good as its best member.
That is why :func:`gridlbc.certify` pools a judged policy with a grid solution of the problem by
default: no statistic of a poor proposal's own samples can reveal the weight they never reach.

**Box edges.** The rollouts are those of :func:`gridlbc.simulate`: periodic coordinates wrap. By
default the certificate concerns the problem the solver solves: with a grid that has closed
(non-periodic) axes, ``boundary="reflect"`` folds every step back into the box on those axes, as
the solver's reflecting state constraint keeps the probability in it, and v* is the optimum of
that constrained problem; a problem without a grid has no box, and its SDE lives on Rᵈ. With
``boundary="free"`` the SDE lives on all of Rᵈ for a gridded problem too, so samples that cross a
non-periodic edge of the grid's box keep going (a grid solution's policy is clamped to the box
there) and v* is the optimum of the problem on Rᵈ. The share of samples that crossed an edge, and
the share of the optimal path measure that did (the weighted share), say when the box matters.
The weight stays exact: the fold acts on the state, not on the noise. The controlled chain driven
by the noise dε is, step by step, the passive chain (the same steps and folds, u = 0) driven by
dε' = u dt + dε, because u enters the step only through B(u dt + dε); the fold is a fixed
function of the state after the step, whichever noise produced it. The likelihood ratio of the
passive noise law N(0, λR⁻¹dt) to the controlled one N(u dt, λR⁻¹dt) at dε' is the Girsanov
factor exp(−(uᵀR dε + ½uᵀRu dt)/λ) whatever the folds do, so E_u[exp(−S_u/λ)] is the reflected
chain's Feynman–Kac desirability exactly.

**Tasks that end** (SPEC §9). With an exit set E the same argument holds up to the stopping time
τ (the first step in E, or the end): S_u = g_E(x_τ) + ∫₀^τ (q + ½uᵀRu) dt + ∫₀^τ uᵀR dε, and
E_u[exp(−S_u/λ)] is the stopped chain's desirability, because the stopping rule is a function of
the path, which the change of measure leaves alone (optional stopping of the Girsanov
martingale). A problem without a horizon is rolled out to ``max_time``; a sample still running
then pays only what it has accrued, which biases v* and J low. :attr:`Certificate.unexited_fraction
<gridlbc.Certificate.unexited_fraction>` reports their share and :func:`gridlbc.certify` warns
above :data:`MAX_UNEXITED`.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np

from .errors import CertificateWarning, GridlbcWarning, state_text, warn_user
from .problem import Problem
from .progress import ProgressBar
from .psis import pareto_k
from .regions import has_geometry
from .simulate import (
    check_problem_and_policy,
    check_sample_count,
    euler_maruyama,
    resolve_boundary,
    rollout_horizon,
    step_count,
)

MIN_EFFECTIVE_SAMPLE_SIZE = 30.0
"""Below this effective sample size the normal approximation behind the standard errors fails and
:func:`gridlbc.certify` warns."""

MAX_PARETO_K = 0.7
"""Above this PSIS tail shape k̂ the weights' tail is too heavy for the estimate to be trusted
(Vehtari et al., JMLR 2024, §3.2) and :func:`gridlbc.certify` warns."""

MAX_UNEXITED = 0.01
"""Above this share of samples that had not reached the exit set by ``max_time`` (a first-exit
problem without a horizon), :func:`gridlbc.certify` warns: their costs are truncated."""

UNVISITED_FLOOR = 0.05
"""A grid solution's response S to the costs between its nodes counts as a feature the samples
may have missed (:func:`check_unvisited`) only above this share of max(abs(v̂*), λ), the default
tolerance of a solve's own warning (:data:`gridlbc.accuracy.DEFAULT_TOLERANCE`): S is read on
the coarser grid and errs high (docs page :doc:`accuracy`), and below it S is no evidence of
one: it reads a few percent where the certificate is right (stranger round 36, docs page
:doc:`validating`, "What the samples never visit")."""

EXTRAPOLATION_FLOOR = 1e-3
"""``certify(..., richardson=True)`` warns of an extrapolation whose residual (a third of
:attr:`Certificate.extrapolation_gap`) exceeds both its SE and this share of max(abs(v), λ): a
deterministic problem (SE 0) would otherwise be warned of the rounding of its last digits."""


STEP_CHECK_FACTOR = 4
"""The check of the time step that :func:`gridlbc.certify` makes by default
(:attr:`Certificate.step_bias`) runs at this many times its step: a first-order bias c Δt moves
v̂* by 3 c Δt there, beyond the check's sampling at a fraction of the work that twice the step
would need for the same power (stranger round 45's default step T/300, +13 %, was within 3 SEs
of a check at 2Δt with half the samples)."""

STEP_CHECK_SHARE = 0.5
"""The share of the certificate's samples the check at :data:`STEP_CHECK_FACTOR` times its step
draws (with the factor 4, an eighth of the certificate's work)."""


_ESTIMATES = (
    "optimal_value",
    "optimal_value_se",
    "policy_cost",
    "policy_cost_se",
    "gap",
    "gap_se",
    "effective_sample_size",
    "pareto_k",
    "left_box_fraction",
    "optimal_left_box_fraction",
)
"""The per-start-state fields of :class:`Certificate`, in the order :func:`_estimates` returns."""


@dataclass(frozen=True, eq=False)
class Certificate:
    """The certified optimal cost from each start state and the judged policy's distance from it.

    Shapes: for one start state x0 of shape ``(d,)`` the estimates are floats; for start states
    ``(k, d)`` they are arrays ``(k,)``, one entry per row of ``start_states`` (even for k = 1).
    Costs are in the problem's cost units; λ is the temperature.

    Attributes
    ----------
    start_states : ndarray (k, d)
        The start states (periodic coordinates wrapped into the box).
    optimal_value, optimal_value_se : float or ndarray (k,)
        v*(x₀) = −λ log mean(exp(−S_u/λ)), the true optimal cost up to the O(Δt) of the time
        step (:attr:`step_bias`), and its delta-method standard error.
    policy_cost, policy_cost_se : float or ndarray (k,)
        J(u), the mean realised cost of the judged policy, and its SE.
    gap, gap_se : float or ndarray (k,)
        J(u) − v* = λ KL(P_u ‖ P*) ≥ 0 and its SE: from the paired samples when the policy is its
        own proposal, √(SE(J)² + SE(v*)²) of independent samples otherwise.
    effective_sample_size : float or ndarray (k,)
        (Σw)² / Σw² of the weights (w = exp(−S_u/λ) for one proposal, the pooled weights of the
        module docstring for several), between 1 and ``n_samples``; with ``richardson=True`` the
        smaller of the two runs'.
    pareto_k : float or ndarray (k,)
        The PSIS tail shape k̂ of the weights (:func:`gridlbc.psis.pareto_k`): < 0.5 reliable,
        0.5–0.7 slow, > :attr:`max_pareto_k` unreliable. NaN with too few samples to fit a tail.
        With ``richardson=True`` the larger of the two runs'.
    left_box_fraction : float or ndarray (k,)
        Share of the judged policy's samples that left the grid's box on a non-periodic axis (0
        without a grid).
    optimal_left_box_fraction : float or ndarray (k,)
        The same share under the optimal process (weighted by w).
    final_states : ndarray (n, d) or (k, n, d)
        x_T of every sample of the proposal (periodic coordinates wrapped).
    n_samples : int
        Samples per start state.
    dt, temperature : float
        Euler–Maruyama step and λ.
    min_effective_sample_size : float
        Below it an estimate is flagged untrusted (and :class:`CertificateWarning` was issued).
    max_pareto_k : float
        Above it likewise.
    seed : int or None
    separate_proposal : bool
        Whether v* came from other samples than the judged policy's alone (then J, its SE and
        ``left_box_fraction`` come from the policy's own samples, its share of a pool or an
        independent run, and ``gap_se`` = √(SE(J)² + SE(v*)²)); False: one set of samples of
        the policy gave all.
    boundary : str
        ``"free"`` (the SDE on Rᵈ) or ``"reflect"`` (closed edges of the box reflect), as
        resolved (:func:`gridlbc.simulate.resolve_boundary`).
    extrapolated_value, extrapolated_value_se : float, ndarray (k,) or None
        With ``certify(..., richardson=True)``: v* extrapolated to a vanishing Euler–Maruyama
        step, 2 v̂*(Δt) − v̂*(2Δt) (Δt this certificate's :attr:`dt`; the estimator's bias is
        O(Δt); with the steps actually taken, T over a whole number of them), and its SE
        √(4 SE(Δt)² + SE(2Δt)²) (independent draws). None otherwise.
    extrapolation_gap : float, ndarray (k,) or None
        With ``certify(..., richardson=True)``: the extrapolation from (Δt, 2Δt) less the same
        from (2Δt, 4Δt), a third run at 4Δt (seed + 2): zero up to sampling where the bias is
        c Δt, and about three times the extrapolation's own error where a c₂Δt² remains.
        :func:`gridlbc.certify` warns where it is beyond 3 of its SEs and a third of it exceeds
        the extrapolation's SE (and :data:`EXTRAPOLATION_FLOOR` of max(abs(v), λ)). None
        otherwise.
    step_bias, step_bias_se : float, ndarray (k,) or None
        The time step's first-order bias at Δt, c Δt of v̂*(Δt) ≈ v*(0) + c Δt, read from a run at
        a longer step h as (v̂*(h) − v̂*(Δt)) Δt / (h − Δt) with the steps actually taken, and
        its SE (the two runs' independent). By default (``step_check=True``) from a check at
        h = :data:`STEP_CHECK_FACTOR` Δt with :data:`STEP_CHECK_SHARE` of the samples (seed + 1;
        a bias that grows faster than Δt reads high there), where :func:`gridlbc.certify` warns if
        it exceeds 3 of its SEs and v*'s own SE (and :data:`EXTRAPOLATION_FLOOR` of
        max(abs(v), λ)); with ``richardson=True`` from its run at 2Δt (equal to
        :attr:`step_contribution`). None with ``step_check=False``, or too few samples or steps
        to check (fewer than 4 samples, or than :data:`STEP_CHECK_FACTOR` steps).
    unexited_fraction : float or ndarray (k,)
        For a first-exit problem: the share of the proposal's samples that had not reached the
        exit set by the end (truncated costs, see the module docstring); 0 otherwise.
    proposal_values, proposal_values_se : ndarray (J,) or (k, J), or None
        With several proposals (``certify(..., proposal=[p₁, …, p_J])``): v̂* and its SE from
        each proposal's own samples alone, to compare with the pooled :attr:`optimal_value`;
        None with one proposal.
    proposals : tuple of str
        What drew the samples for v* (e.g. the judged policy and an automatic grid solution).
    """

    start_states: np.ndarray
    optimal_value: float | np.ndarray
    optimal_value_se: float | np.ndarray
    policy_cost: float | np.ndarray
    policy_cost_se: float | np.ndarray
    gap: float | np.ndarray
    gap_se: float | np.ndarray
    effective_sample_size: float | np.ndarray
    pareto_k: float | np.ndarray
    left_box_fraction: float | np.ndarray
    optimal_left_box_fraction: float | np.ndarray
    final_states: np.ndarray
    n_samples: int
    dt: float
    temperature: float
    min_effective_sample_size: float
    max_pareto_k: float
    seed: int | None
    separate_proposal: bool = False
    boundary: str = "free"
    extrapolated_value: float | np.ndarray | None = None
    extrapolated_value_se: float | np.ndarray | None = None
    extrapolation_gap: float | np.ndarray | None = None
    step_bias: float | np.ndarray | None = None
    step_bias_se: float | np.ndarray | None = None
    unexited_fraction: float | np.ndarray = 0.0
    proposal_values: np.ndarray | None = None
    proposal_values_se: np.ndarray | None = None
    proposals: tuple[str, ...] = ("the policy",)

    @property
    def step_contribution(self) -> float | np.ndarray | None:
        """v̂*(Δt) − the extrapolated value: the part of the estimate that is the time step's
        (None without ``richardson=True``)."""
        if self.extrapolated_value is None:
            return None
        return np.asarray(self.optimal_value) - self.extrapolated_value

    @property
    def trusted(self) -> bool | np.ndarray:
        """Whether the effective sample size reaches :attr:`min_effective_sample_size` and the
        tail shape k̂ stays below :attr:`max_pareto_k` (a NaN k̂, too few samples to fit a tail,
        leaves the verdict to the effective sample size)."""
        ok = _trusted(
            np.asarray(self.effective_sample_size),
            np.asarray(self.pareto_k),
            self.min_effective_sample_size,
            self.max_pareto_k,
        )
        return bool(ok) if ok.ndim == 0 else ok

    def interval(self, level: float = 0.95):
        """A confidence interval for v*(x₀) at ``level``, using that v* ≤ J(policy) always.

        With z the standard normal quantile of (1 + level)/2 and z′ that of (3 + level)/4,

            lower = v̂* − z SE(v̂*),      upper = min(v̂* + z′ SE(v̂*), Ĵ + z′ SE(Ĵ)),

        the upper end tightened by J(u) − v* = λ KL(P_u ‖ P*) ≥ 0, which holds for the
        Euler–Maruyama chain as for the SDE. Each of the two upper bounds fails with probability
        (1 − level)/4, so their minimum fails with at most (1 − level)/2 whether Ĵ and v̂* come
        from the same samples or not (Bonferroni). Both ends are normal approximations: they hold
        for the time-discretised chain (its O(Δt) distance from the SDE's optimum is not included)
        and only as far as the certificate is :attr:`trusted` (a heavy weight tail biases v̂*
        upward beyond its SE). With ``certify(..., richardson=True)`` the interval is instead
        extrapolated ± z SE(extrapolated), for the SDE's optimum (the bound by J, a property of
        one chain, is then not used). See docs/validating.rst.

        Parameters
        ----------
        level : float
            Nominal coverage, in (0, 1).

        Returns
        -------
        (lower, upper) : floats, or arrays (k,) for k start states
        """
        from scipy.stats import norm

        if not 0.0 < level < 1.0:
            raise ValueError(f"level must lie in (0, 1), got {level!r}")
        z = float(norm.ppf(0.5 * (1.0 + level)))
        if self.extrapolated_value is not None:
            centre = np.asarray(self.extrapolated_value)
            half = z * np.asarray(self.extrapolated_value_se)
            lo, hi = centre - half, centre + half
            return (float(lo), float(hi)) if lo.ndim == 0 else (lo, hi)
        z_upper = float(norm.ppf(0.25 * (3.0 + level)))
        value, se = np.asarray(self.optimal_value), np.asarray(self.optimal_value_se)
        bound = np.asarray(self.policy_cost) + z_upper * np.asarray(self.policy_cost_se)
        lower, upper = value - z * se, np.minimum(value + z_upper * se, bound)
        if lower.ndim == 0:
            return float(lower), float(upper)
        return lower, upper

    def summary(self) -> str:
        """One line per start state: v*, J(u), the gap (± one SE each) and the diagnostics."""
        rows = [np.atleast_1d(np.asarray(getattr(self, f), dtype=float)) for f in _ESTIMATES]
        lines = []
        edge = "reached an edge (reflected)" if self.boundary == "reflect" else "left the box"
        unexited = np.broadcast_to(np.asarray(self.unexited_fraction, dtype=float), rows[0].shape)
        for i, x0 in enumerate(self.start_states):
            v, v_se, J, J_se, gap, gap_se, ess, k_hat, left, left_opt = (r[i] for r in rows)
            flag = ""
            if unexited[i] > 0:
                flag = f"; {100 * unexited[i]:.1f} % had not exited (costs cut short)"
            if self.extrapolated_value is not None:
                best = np.atleast_1d(np.asarray(self.extrapolated_value, dtype=float))[i]
                best_se = np.atleast_1d(np.asarray(self.extrapolated_value_se, dtype=float))[i]
                flag += f"; v* extrapolated to Δt → 0: {best:.5g} ± {best_se:.2g}"
            elif self.step_bias is not None:
                bias = np.atleast_1d(np.asarray(self.step_bias, dtype=float))[i]
                bias_se = np.atleast_1d(np.asarray(self.step_bias_se, dtype=float))[i]
                flag += f"; the step's bias in v* {bias:+.2g} ± {bias_se:.2g}"
            if ess < self.min_effective_sample_size:
                flag += " — TOO FEW EFFECTIVE SAMPLES, v* not trustworthy"
            elif k_hat > self.max_pareto_k:
                flag += f" — HEAVY WEIGHT TAIL (k̂ > {self.max_pareto_k:g}), v* not trustworthy"
            lines.append(
                f"x0 = {state_text(x0)}: certified optimum v* = {v:.5g} ± "
                f"{v_se:.2g}, policy cost J = {J:.5g} ± {J_se:.2g}, gap J − v* = {gap:.4g} ± "
                f"{gap_se:.2g} (SE); effective sample size {ess:.0f} of {self.n_samples} "
                f"({100 * ess / self.n_samples:.0f} %), tail k̂ = {k_hat:.2f}, {edge} "
                f"{100 * left:.1f} % ({100 * left_opt:.1f} % under the optimum){flag}"
            )
        source = (
            f"v* from samples of {' pooled with '.join(self.proposals)}, J from the policy's own"
            if self.separate_proposal
            else "v* and J from the same samples of the policy"
        )
        lines.append(
            f"Euler–Maruyama Δt = {self.dt:.3g}, λ = {self.temperature:g}, seed {self.seed}, "
            f"box edges {self.boundary}; {source}"
        )
        return "\n".join(lines)


def _trusted(ess, k_hat, min_ess: float, max_k: float) -> np.ndarray:
    """Enough effective samples and no heavy tail (NaN k̂: no evidence either way)."""
    return (ess >= min_ess) & ~(k_hat > max_k)


def _optimal_value(
    a: np.ndarray, lam: float, counts: tuple[int, ...] = ()
) -> tuple[float, float, np.ndarray]:
    """v̂* = −λ log w̄ from log weights ``a``, its delta-method SE λ SE(w̄)/w̄, and the weights
    w = exp(a − max a) (the largest is 1: nothing underflows).

    SE(w̄)² = σ̂²(w)/n for one proposal. A pool whose proposals drew ``counts`` = (n_1, …, n_J)
    consecutive samples each is stratified: w̄ = Σ_j (n_j/n) w̄_j, so SE(w̄)² = Σ_j n_j σ̂_j²/n²
    with σ̂_j the spread within proposal j's samples (the spread between the w̄_j is not noise).
    """
    w = np.exp(a - a.max())
    w_mean = w.mean()
    n = a.shape[0]
    strata = np.split(w, np.cumsum(counts)[:-1]) if counts else [w]
    if min(len(part) for part in strata) > 1:
        variance = sum(len(part) * part.var(ddof=1) for part in strata) / n**2
        se = lam * math.sqrt(variance) / w_mean
    else:
        se = math.nan
    return -lam * (a.max() + math.log(w_mean)), se, w


def _estimates(
    a: np.ndarray,
    C: np.ndarray,
    left: np.ndarray,
    lam: float,
    judged: tuple[np.ndarray, np.ndarray] | None = None,
    counts: tuple[int, ...] = (),
) -> tuple:
    """The certificate's estimates from one start state's samples of the proposal: the log
    weights a (−S_u/λ for one proposal), realised costs C, left the box; ``judged`` = (costs,
    left) of the judged policy's own samples when it is not the proposal; ``counts`` the samples
    of each pooled proposal, in order (:func:`_optimal_value`)."""
    n = a.shape[0]
    value, value_se, w = _optimal_value(a, lam, counts)
    w_mean = w.mean()
    ess = w.sum() ** 2 / np.dot(w, w)
    paired = judged is None
    weighted_left = np.dot(w, left) / w.sum()
    if judged is not None:
        C, left = judged
    if n > 1 and C.shape[0] > 1:  # the judged policy's samples: n, or its share of a pool
        cost_se = C.std(ddof=1) / math.sqrt(C.shape[0])
        gap_se = (
            (C + lam * w / w_mean).std(ddof=1) / math.sqrt(n)
            if paired
            else math.hypot(cost_se, value_se)
        )
    else:
        cost_se = gap_se = math.nan
    cost = C.mean()
    return (
        value,
        value_se,
        cost,
        cost_se,
        cost - value,
        gap_se,
        ess,
        pareto_k(a),
        left.mean(),
        weighted_left,
    )


def sample_certificate(
    problem: Problem,
    policy,
    x0,
    n_samples: int = 2000,
    dt: float | None = None,
    seed: int | None = None,
    progress: bool | None = None,
    min_effective_sample_size: float = MIN_EFFECTIVE_SAMPLE_SIZE,
    max_pareto_k: float = MAX_PARETO_K,
    proposal="auto",
    boundary: str | None = None,
    richardson: bool = False,
    max_time: float | None = None,
    grid_proposal: Callable | None = None,
    step_check: bool = True,
) -> Certificate:
    """:func:`gridlbc.certify`, with ``proposal="auto"``'s grid solution from ``grid_proposal``
    (a function of the problem returning a policy and its name, or None and why not:
    :func:`gridlbc.certify` passes the solve it makes); without it, ``"auto"`` is the judged
    policy alone. The arguments and the result are :func:`gridlbc.certify`'s.

    With ``richardson``, two certificates at Δt and 2Δt (independent draws) give the
    extrapolated value and the certificate's diagnostics are the worse of
    the two runs' (the smaller effective sample size, the larger k̂ and unexited share): a
    heavy tail at 2Δt spoils the extrapolation as much as one at Δt. A third at 4Δt checks
    the extrapolation (:attr:`Certificate.extrapolation_gap`)."""
    check_problem_and_policy(problem, policy)
    n = check_sample_count(n_samples)
    if problem.average_cost:
        raise ValueError(
            "certify estimates the optimal cost-to-go of a task that ends; an average-cost "
            "problem has none (its value is relative): simulate the policy for a long max_time "
            "and compare the cost per unit time with solution.average_cost"
        )
    # the inputs checked once, before a grid proposal is solved
    starts = problem.wrap(problem.check_states(x0, "x0"))
    horizon = rollout_horizon(problem, max_time, dt)
    one_sample = n < 2 and isinstance(proposal, str)  # "auto" with one sample: nothing to share
    pilot = partial(
        pilot_share, problem, starts, horizon, dt, boundary, seed, min(n, PILOT_SAMPLES)
    )
    work = n * step_count(horizon, dt)  # the sample-steps of the draws at dt, per start state
    samplers, names = _proposal_policies(
        problem, policy, None if one_sample else proposal, grid_proposal, pilot, work
    )
    if n < len(samplers):
        raise ValueError(
            f"n_samples = {n} is fewer than the {len(samplers)} proposals that share it: give at "
            "least one sample per proposal"
        )
    once = partial(
        _certify_once,
        problem,
        policy,
        starts,
        np.ndim(x0) == 1,
        samplers,
        names,
        n=n,
        T=horizon,
        progress=progress,
        min_effective_sample_size=min_effective_sample_size,
        max_pareto_k=max_pareto_k,
        boundary=boundary,
    )
    if crossings_unchecked(problem):
        warn_user(
            "certify: the exit set is not a gridlbc.regions shape, so a path is stopped only "
            "where a step lands in it, and one that crosses into it and back within a step goes "
            "on: v* is biased by O(√dt), which neither its standard error nor the first-order "
            "extrapolation of richardson=True removes. Give the exit set as a shape (Box, Ball, "
            "their unions: crossings between the steps are then found by a Brownian bridge), or "
            "halve dt to see how far the value moves",
            CertificateWarning,
        )
    if not richardson:
        certificate = once(dt=dt, seed=seed)
        check_unvisited(problem, samplers, certificate)
        if step_check:
            certificate = _check_step(problem, certificate, once, len(samplers), horizon)
        return certificate
    steps = step_count(horizon, dt)
    if steps < 8:
        raise ValueError(
            f"richardson=True compares the step with twice and four times it, and {steps} steps "
            "leave the coarsest fewer than 2: give a dt of at most an eighth of the horizon "
            "(of max_time without one)"
        )
    fine = once(dt=dt, seed=seed)
    check_unvisited(problem, samplers, fine)
    coarse, coarser = (
        once(
            dt=m * fine.dt,
            seed=None if seed is None else seed + j,
            run=f"the run at {m} dt, {why}",
        )
        for j, m, why in (
            (1, 2, "which richardson=True extrapolates from"),
            (2, 4, "which only checks richardson=True's extrapolation"),
        )
    )
    runs = (fine, coarse, coarser)
    h = [c.dt for c in runs]  # the steps taken (T over a whole number of them)
    v1, v2, v4 = (np.asarray(c.optimal_value) for c in runs)
    s1, s2, s4 = (np.asarray(c.optimal_value_se) for c in runs)

    def weights(a: int, b: int) -> tuple[float, float]:
        """(w_a, w_b) with w_a v_a + w_b v_b free of a bias c Δt (runs a, b)."""
        return h[b] / (h[b] - h[a]), -h[a] / (h[b] - h[a])

    (w1, w2), (u2, u4) = weights(0, 1), weights(1, 2)
    extrapolated, se = w1 * v1 + w2 * v2, np.hypot(w1 * s1, w2 * s2)
    gap = w1 * v1 + (w2 - u2) * v2 - u4 * v4  # from (Δt, 2Δt) less from (2Δt, 4Δt)
    gap_se = np.sqrt((w1 * s1) ** 2 + ((w2 - u2) * s2) ** 2 + (u4 * s4) ** 2)
    # a bias c₁Δt + c₂Δt² leaves 2c₂Δt² in the extrapolation and 6c₂Δt² in the gap
    residual = np.abs(gap) / 3
    floor = EXTRAPOLATION_FLOOR * np.fmax(np.abs(extrapolated), problem.temperature)
    flagged = (np.abs(gap) > 3 * gap_se) & (residual > np.fmax(se, floor))
    table = [np.atleast_1d(c) for c in (v1, v2, v4, extrapolated, residual, se)]
    for i in np.flatnonzero(np.atleast_1d(flagged)):
        at_dt, at_2dt, at_4dt, best, off, error = (column[i] for column in table)
        warn_user(
            f"certify: at x0 = {state_text(fine.start_states[i])} the time step's bias is not "
            f"yet of first order: v* = {at_dt:.4g}, {at_2dt:.4g} and {at_4dt:.4g} at dt, 2 dt "
            "and 4 dt, and the extrapolations from the first two and from the last two differ "
            f"beyond their sampling. The extrapolated value {best:.4g} (SE {error:.2g}) is then "
            f"off by about {off:.2g}: certify with a smaller dt (the step is long against the "
            "dynamics somewhere the paths go: by an exit set, or where the policy is steep)",
            CertificateWarning,
        )
    bias, bias_se = _step_bias(fine, coarse)
    fields = {  # the worse diagnostics of the two runs, and the extrapolation
        "effective_sample_size": np.fmin(fine.effective_sample_size, coarse.effective_sample_size),
        "pareto_k": np.fmax(fine.pareto_k, coarse.pareto_k),
        "unexited_fraction": np.fmax(fine.unexited_fraction, coarse.unexited_fraction),
        "extrapolated_value": extrapolated,
        "extrapolated_value_se": se,
        "extrapolation_gap": gap,
        "step_bias": bias,
        "step_bias_se": bias_se,
    }
    shaped = {name: float(a) if v1.ndim == 0 else a for name, a in fields.items()}
    return dataclasses.replace(fine, **shaped)  # type: ignore[arg-type]


def _step_bias(fine: Certificate, coarse: Certificate) -> tuple[np.ndarray, np.ndarray]:
    """The first-order bias c Δt of ``fine``'s v̂* and its SE, from ``coarse``'s at a longer step
    (independent draws): v̂*(h₁) − v̂*(h₂) = c (h₁ − h₂) (:attr:`Certificate.step_bias`)."""
    scale = fine.dt / (coarse.dt - fine.dt)
    difference = np.asarray(coarse.optimal_value) - np.asarray(fine.optimal_value)
    spread = np.hypot(fine.optimal_value_se, coarse.optimal_value_se)
    return scale * difference, scale * spread


def _check_step(
    problem: Problem, certificate: Certificate, once, proposals: int, horizon: float
) -> Certificate:
    """``certificate`` with its :attr:`~Certificate.step_bias` read from a run at
    :data:`STEP_CHECK_FACTOR` times its step with :data:`STEP_CHECK_SHARE` of its samples
    (seed + 1; that run's own warnings are not raised: the certificate's speak), and a
    :class:`CertificateWarning` where the bias exceeds 3 of its SEs, v*'s SE and
    :data:`EXTRAPOLATION_FLOOR` of max(abs(v*), λ) at a state whose two runs are both trusted.
    The step's O(Δt) bias is not in v*'s SE, and a gap crossed within a step, or a default step
    long against the dynamics, made a certificate silently a few percent off (stranger round
    45: +1 % at Δt = 0.01, +13 % at the horizon's T/300; the swing-up's truth at Δt = 0.002,
    1.6 % below the SDE's optimum: docs page :doc:`validating`)."""
    if certificate.n_samples < 4 or round(horizon / certificate.dt) < STEP_CHECK_FACTOR:
        return certificate
    n = max(int(STEP_CHECK_SHARE * certificate.n_samples), proposals)
    seed = None if certificate.seed is None else certificate.seed + 1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridlbcWarning)
        check = once(dt=STEP_CHECK_FACTOR * certificate.dt, seed=seed, n=n, run="the check")
    bias, bias_se = _step_bias(certificate, check)
    v, se = np.asarray(certificate.optimal_value), np.asarray(certificate.optimal_value_se)
    floor = EXTRAPOLATION_FLOOR * np.fmax(np.abs(v), problem.temperature)
    trusted = np.asarray(certificate.trusted) & np.asarray(check.trusted)
    flagged = trusted & (np.abs(bias) > 3 * bias_se) & (np.abs(bias) > np.fmax(se, floor))
    table = [np.atleast_1d(c) for c in (v, check.optimal_value, bias, bias_se, se)]
    for i in np.flatnonzero(np.atleast_1d(flagged)):
        at_dt, at_long, off, off_se, error = (column[i] for column in table)
        warn_user(
            f"certify: at x0 = {state_text(certificate.start_states[i])} v* = {at_dt:.4g} at "
            f"dt = {certificate.dt:.3g} and {at_long:.4g} at {STEP_CHECK_FACTOR} dt (a check "
            f"with {n} samples), apart beyond their sampling: read as first order in dt, the "
            f"time step's own bias at dt is {off:+.2g} ± {off_se:.2g}, more than v*'s standard "
            f"error {error:.2g}, which leaves it out. Certify with richardson=True, which "
            "extrapolates it away and checks the extrapolation, or with a smaller dt (docs page "
            "'validating')",
            CertificateWarning,
        )
    shaped = {
        name: float(a) if v.ndim == 0 else a
        for name, a in (("step_bias", bias), ("step_bias_se", bias_se))
    }
    return dataclasses.replace(certificate, **shaped)  # type: ignore[arg-type]


def crossings_unchecked(problem: Problem) -> bool:
    """Whether the certificate's paths can cross the exit set's boundary between two steps
    unseen: an exit set given as a callable (not a :mod:`gridlbc.regions` shape, whose
    crossings a Brownian bridge finds, :func:`gridlbc.simulate.euler_maruyama`) where the noise
    moves the paths across its boundary. A path that crosses and comes back within a step of
    size Δt is then missed with a probability that shrinks only as √Δt (Broadie, Glasserman &
    Kou, Math. Finance 1997): a bias of that order, which the first-order extrapolation of
    ``richardson=True`` does not remove (extrapolating at order ½ instead amplified other
    biases of the step and made right answers wrong: stranger round 36's toll strip the steps
    cross, docs page :doc:`validating`, "An interval").

    Which axes cross the boundary is read on the grid: those along which the exit set's nodes
    meet the others, at the nodes on either side, with the noise's variance (B R⁻¹ Bᵀ)_kk
    there. A boundary that only an axis without noise crosses (a point mass's position) is
    crossed by paths of bounded speed, whose excursions within a step are O(Δt). Without a
    grid, any callable exit set."""
    if problem.exit is None or has_geometry(problem.exit):
        return False
    grid = problem.grid
    if grid is None:
        return True
    inside = grid.reshape(problem.exit_mask())
    spread = problem.R_inv
    for k in range(grid.ndim):
        lower = np.argwhere(np.diff(inside, axis=k))  # the node below each change along axis k
        if len(lower) == 0:
            continue
        upper = lower + np.eye(grid.ndim, dtype=int)[k]
        nodes = grid.node_coordinates(np.ravel_multi_index(np.vstack([lower, upper]).T, grid.shape))
        B = np.asarray(problem.system.input_matrix(nodes), dtype=float)
        if np.any(np.einsum("nj,jl,nl->n", B[:, k, :], spread, B[:, k, :]) > 0):
            return True
    return False


def _certify_once(
    problem: Problem,
    policy,
    starts: np.ndarray,
    single: bool,
    samplers: list,
    names: list[str],
    n: int,
    T: float,
    dt: float | None,
    seed: int | None,
    progress: bool | None,
    min_effective_sample_size: float,
    max_pareto_k: float,
    boundary: str | None,
    run: str = "",
) -> Certificate:
    """One certificate at one step, from the checked and wrapped ``starts`` (``single``: one
    state given as ``(d,)``) over ``T``, its samples drawn by ``samplers``
    (:func:`sample_certificate` without ``richardson``). ``run`` names it in its warnings where
    it is one of several (the runs at 2Δt and 4Δt of ``richardson=True``, whose v* and k̂ are
    not the ones returned)."""
    who = f"certify ({run})" if run else "certify"
    boundary = resolve_boundary(problem, boundary)
    K = step_count(T, dt)
    k = starts.shape[0]
    own = next((j for j, sampler in enumerate(samplers) if sampler is policy), None)
    runs = len(samplers) + (own is None)
    bar = ProgressBar.chosen(
        runs * K,
        progress,
        f"certify {k}×{n} samples",
        work_per_item=k * n,
        work_unit="sample-steps",
    )
    rng = np.random.default_rng(seed)
    lam = problem.temperature
    counts = [len(c) for c in np.array_split(np.arange(n), len(samplers))]
    scored = samplers if len(samplers) > 1 else ()

    def roll(run: int, sampler, samples: int, scored=()):
        """The ``run``-th roll-out (for the progress bar): ``samples`` paths per start state."""
        return euler_maruyama(
            problem,
            sampler,
            np.repeat(starts, samples, axis=0),
            K,
            rng,
            True,
            lambda step, x_new, u: bar.update(run * K + step + 1),
            boundary,
            T,
            scored=scored,
        )

    draws = [(roll(j, s, n_j, scored), n_j) for j, (s, n_j) in enumerate(zip(samplers, counts))]
    a, C, left, final, cut, components = _mixture(draws, np.array(counts) / n, k, lam)
    paired = len(samplers) == 1 and own == 0
    judged: list = [None] * k
    if not paired:
        # the judged policy's own samples: independent of the proposals', or its share of the pool
        path = roll(len(samplers), policy, n) if own is None else draws[own][0]
        C_own = (path.running_cost + path.terminal_cost).reshape(k, -1)
        left_own = path.left_box.reshape(k, -1)
        judged = [(C_own[i], left_own[i]) for i in range(k)]
    strata = tuple(counts) if len(counts) > 1 else ()
    columns = np.array(
        [_estimates(a[i], C[i], left[i], lam, judged[i], strata) for i in range(k)]
    ).T
    estimates = dict(zip(_ESTIMATES, columns))
    ess, value = estimates["effective_sample_size"], estimates["optimal_value"]
    k_hat = estimates["pareto_k"]
    for i in np.flatnonzero(~_trusted(ess, np.zeros(k), min_effective_sample_size, math.inf)):
        warn_user(
            f"{who}: effective sample size {ess[i]:.1f} of {n} at x0 = {state_text(starts[i])} is "
            f"below {min_effective_sample_size:g}: v* = {value[i]:.4g} and its standard "
            "error are not trustworthy (a few samples carry all the weight exp(−S/λ)). Use a "
            "proposal closer to optimal (a finer or fitted grid solution), more samples, or note "
            f"that the temperature λ = {lam:g} is small relative to the costs, which sharpens "
            "the weights.",
            CertificateWarning,
        )
    for i in np.flatnonzero((ess >= min_effective_sample_size) & (k_hat > max_pareto_k)):
        warn_user(
            f"{who}: the weights exp(−S/λ) at x0 = {state_text(starts[i])} have a heavy tail (PSIS "
            f"k̂ = {k_hat[i]:.2f} > {max_pareto_k:g}): v* = {value[i]:.4g} is likely too high and "
            "its standard error too small, because the samples that carry the weight are rarely "
            "drawn. More samples do not fix this; a proposal closer to optimal does, e.g. the "
            "policy of a grid solution of this problem.",
            CertificateWarning,
        )
    if not problem.stationary:
        cut[:] = False
    unexited = cut.mean(axis=1)
    for i in np.flatnonzero(unexited > MAX_UNEXITED):
        carried = _weight_share(a[i], cut[i])  # what v* reads of them; J reads each sample alike
        told = "v* and J are underestimated"
        if carried <= MAX_UNEXITED:
            told = (
                f"J is underestimated; they carry {carried:.1e} of the weight exp(−S/λ), so "
                "v* is not"
            )
        warn_user(
            f"{who}: {unexited[i]:.1%} of the samples from x0 = {state_text(starts[i])} had not reached "
            f"the exit set by max_time = {T:g}: their costs are cut short, so {told}. Raise "
            "max_time, or use a proposal that reaches the exit sooner.",
            CertificateWarning,
        )
    return Certificate(
        starts,
        **{name: float(c[0]) if single else c for name, c in estimates.items()},
        final_states=final[0] if single else final,
        n_samples=n,
        dt=T / K,
        temperature=lam,
        min_effective_sample_size=float(min_effective_sample_size),
        max_pareto_k=float(max_pareto_k),
        seed=seed,
        separate_proposal=not paired,
        proposals=tuple(names),
        boundary=boundary,
        unexited_fraction=float(unexited[0]) if single else unexited,
        proposal_values=None if components is None else components[0][0 if single else ...],
        proposal_values_se=None if components is None else components[1][0 if single else ...],
    )


def check_unvisited(problem: Problem, samplers: list, certificate: Certificate) -> None:
    """Warn (:class:`gridlbc.CertificateWarning`) where a grid solution that drew samples does not
    resolve a feature of the costs narrower than its cells, and v̂* agrees with that solution.

    Importance sampling sees only what its samples visit. A grid solution's policy steers by the
    costs its nodes see: a goal or a well between the nodes is not sought, and where the other
    samplers do not go there either, v̂* is the value of the problem without the feature, with a
    small SE, a large ESS and a light tail, far from the optimum and trusted (stranger round
    35's terminal dip between the nodes: docs page :doc:`validating`, "What the samples never
    visit"). The grid solution's error
    estimate measures what such features change: S, its response to the costs' excess between
    the nodes (:class:`gridlbc.accuracy.subcell.Response`, docs page :doc:`accuracy`). Where S
    at x₀ exceeds three of v̂*'s standard errors and :data:`UNVISITED_FLOOR` of max(abs(v̂*), λ),
    and v̂* lies within S/2 of that solution's own value, the samples most likely missed the
    feature, and v̂* may be off by up to S. Read only
    for samplers that are grid solutions of the same task (the policy of a
    :class:`~gridlbc.Solution`, or the automatic one, :class:`gridlbc.certify.GridPolicy`) whose
    estimate ran the raised solve (a feature was found)."""
    starts = certificate.start_states
    value = np.atleast_1d(np.asarray(certificate.optimal_value, dtype=float))
    se = np.atleast_1d(np.asarray(certificate.optimal_value_se, dtype=float))
    for sampler in samplers:
        solution = getattr(sampler, "solution", getattr(sampler, "__self__", None))
        response = getattr(getattr(solution, "embedded", None), "excess", None)
        if solution is None or response is None or response.raised is None:
            continue
        if not _same_problem(solution.problem, problem, but="grid"):
            continue
        change = response(starts, 0.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an underflowed value was the solve's to warn of
            own = np.reshape(solution.value(starts, 0.0), -1)
        scale = UNVISITED_FLOOR * np.fmax(np.abs(value), problem.temperature)
        with np.errstate(invalid="ignore"):
            blind = (change > np.fmax(3 * se, scale)) & (np.abs(value - own) < 0.5 * change)
        for i in np.flatnonzero(blind):
            warn_user(
                f"certify: at x0 = {state_text(starts[i])} the costs have a feature narrower "
                "than a cell of a grid solution that drew samples: it changes that grid's value "
                f"by up to {change[i]:.3g} there (its error estimate's response to the costs "
                f"between the nodes), and v* = {value[i]:.4g} lies within half of that of the "
                f"solution's own {own[i]:.4g}. The samples probably never visited the feature, "
                "and v* is then off by up to that much with nothing in its standard error, "
                "effective sample size or k̂ to show it. Certify with a proposal that visits it "
                "(a solution on a grid that resolves the feature: proposal=)",
                CertificateWarning,
            )


def _proposal_policies(
    problem: Problem,
    policy,
    proposal,
    grid_proposal: Callable | None = None,
    pilot: Callable | None = None,
    work: int = 0,
) -> tuple[list, list[str]]:
    """The proposals' policies and their names: ``[policy]`` for None; for ``"auto"`` the judged
    policy pooled with a grid solution of the problem (``grid_proposal(problem, pilot, work)``,
    which may judge its candidates by ``pilot``, :func:`pilot_share`, within a multiple of the
    certificate's sample-steps ``work``) unless none is given or the policy is one already and
    a good proposal (its pilot's effective share at least :data:`PILOT_SHARE`); one per
    entry of a list or tuple of proposals; else the proposal's policy alone."""
    if proposal is None:
        return [policy], ["the policy"]
    if isinstance(proposal, str):
        if proposal != "auto":
            raise ValueError(
                f'proposal must be "auto", None, a solution, a callable or a list of them, got '
                f"{proposal!r}"
            )
        owner = getattr(policy, "__self__", None)
        if hasattr(owner, "desirability") and _same_problem(
            getattr(owner, "problem", None), problem
        ):
            own = "the policy (a grid solution of this problem)"
            if grid_proposal is None or pilot is None or problem.stationary:
                return [policy], [own]
            if pilot(policy) >= PILOT_SHARE:
                return [policy], [own]
            grid_policy, name = grid_proposal(problem, pilot, work)
            if grid_policy is None:
                return [policy], [own]
            return [policy, grid_policy], [own, name]
        if grid_proposal is None:
            return [policy], ["the policy (no grid solution to pool with)"]
        grid_policy, name = grid_proposal(problem, pilot, work)
        if grid_policy is None:
            return [policy], [f"the policy ({name})"]
        return [policy, grid_policy], ["the policy", name]
    if isinstance(proposal, (list, tuple)):
        if not proposal:
            raise ValueError("proposal is an empty sequence: give one proposal or several")
        names = [f"proposal {i + 1}" for i in range(len(proposal))]
        return [_proposal_policy(p) for p in proposal], names
    return [_proposal_policy(proposal)], ["the proposal"]


PILOT_SHARE = 0.5
"""With ``proposal="auto"``, a grid solution whose pilot paths' effective share
(:func:`pilot_share`) is below this is a poor proposal: a judged policy that is a grid
solution of the problem is then pooled with the automatic one, and the automatic one is solved
again with half its time step (:func:`gridlbc.certify`, docs page :doc:`validating`)."""

PILOT_SAMPLES = 128
"""Paths per start state with which :func:`pilot_share` judges a candidate proposal (a few
percent of a certificate's draws)."""


def pilot_share(
    problem: Problem,
    starts: np.ndarray,
    horizon: float,
    dt: float | None,
    boundary: str | None,
    seed: int | None,
    samples: int,
    sampler,
) -> float:
    """The smallest effective share of ``sampler``'s weights over the start states: (Σw)²/Σw²
    of ``samples`` paths per state over ``horizon`` at the certificate's step ``dt``, divided
    by their number (1 for the optimal policy, whose weights are all equal), as a proposal alone.
    Drawn from a generator of their own (the seed with a second word), so that what a pilot
    decides is independent of the certificate's draws, which stay exact for any proposal
    chosen (:func:`gridlbc.certify` judges its automatic proposal so, docs page
    :doc:`validating`).

    Parameters
    ----------
    problem : Problem
        The problem certified.
    starts : ndarray (k, d)
        The certificate's start states, checked and wrapped.
    horizon : float
        How long the paths run (:func:`gridlbc.simulate.rollout_horizon`).
    dt : float or None
        The certificate's step (None: :data:`gridlbc.simulate.DEFAULT_STEPS` steps).
    boundary : {"free", "reflect"} or None
        At closed edges of the box, as the certificate's.
    seed : int or None
        The certificate's seed.
    samples : int
        Paths per start state (:data:`PILOT_SAMPLES`, or the certificate's count if fewer).
    sampler : callable
        The candidate proposal, ``sampler(x, t)`` → ``(N, m)``.

    Returns
    -------
    float
        The smallest effective share over the start states, in (0, 1] (0 where a weight is
        not finite).
    """
    rng = np.random.default_rng(None if seed is None else [seed, 1])
    k = starts.shape[0]
    paths = euler_maruyama(
        problem,
        sampler,
        np.repeat(starts, samples, axis=0),
        step_count(horizon, dt),
        rng,
        boundary=resolve_boundary(problem, boundary),
        horizon=horizon,
    )
    a = -(paths.running_cost + paths.terminal_cost + paths.ito) / problem.temperature
    a = a.reshape(k, samples)
    if not np.all(np.isfinite(a)):
        return 0.0
    return float(np.min(effective_sample_sizes(a))) / samples


def effective_sample_sizes(log_weights: np.ndarray) -> np.ndarray:
    """(Σw)²/Σw² per row of importance weights given by their logarithms (the weights relative to
    each row's largest, so nothing overflows); NaN where a weight is NaN.

    Parameters
    ----------
    log_weights : ndarray (N, n)
        log w, one row per start state.

    Returns
    -------
    ndarray (N,)
    """
    w = np.exp(log_weights - np.max(log_weights, axis=1, keepdims=True))
    return np.sum(w, axis=1) ** 2 / np.sum(w**2, axis=1)


def _same_problem(other, problem: Problem, but: str | None = None) -> bool:
    """Whether ``other`` is ``problem`` or a copy of it (every field the same object, but the
    field named ``but``: ``"grid"`` for the same task on another grid)."""
    return isinstance(other, Problem) and all(
        getattr(other, f.name) is getattr(problem, f.name)
        for f in dataclasses.fields(Problem)
        if f.name != but
    )


def _weight_share(log_weights: np.ndarray, which: np.ndarray) -> float:
    """The share Σ_which w / Σ w of the weights w = exp(``log_weights``) (one state's samples)
    that the samples ``which`` carry: how much of v* = −λ log mean(w) they make (stranger round
    45: paths cut short at ``max_time`` whose costs had already made their weights e⁻¹⁶ of the
    others' were said to bias v*)."""
    finite = np.isfinite(log_weights)
    if not (finite & which).any():
        return 0.0
    w = np.exp(log_weights[finite] - log_weights[finite].max())
    return float(w[which[finite]].sum() / w.sum())


def _mixture(draws, shares: np.ndarray, k: int, lam: float):
    """Pool the samples of the proposals u_1…u_J (``draws``: per proposal its SamplePaths and
    samples per start state) into log weights for one start state each (rows).

    One proposal: a = −S_u/λ. Several, drawn n_j = c_j n each: the balance heuristic of multiple
    importance sampling (Veach & Guibas 1995; Owen, "Monte Carlo theory, methods and examples",
    §9.13) treats the pool as draws of the mixture Σ_j c_j Q_j, whose weight on a path is

        a = −(g + ∫q dt)/λ − log Σ_j c_j dQ_j/dP
          = −S_u/λ + log dQ_u/dP − log Σ_j c_j dQ_j/dP        (u the proposal that drew it),

    exact for the chain like the single-proposal weight (every ratio is the Euler–Maruyama
    transition densities', :func:`gridlbc.simulate.euler_maruyama`), and never larger than
    −(g + ∫q)/λ − log c_j − log dQ_j/dP for any j: the pool is as good as its best member up to
    the factor 1/c_j. Also returned, per proposal, v̂* and its SE from its own samples alone
    (arrays (k, J), None for one proposal), to show how far each would have gone alone.

    Returns a, C, left (k, n); the final states (k, n, d); which samples had not exited (k, n)
    (none without an exit set); and the per-proposal (values, SEs) or None.
    """
    parts: list[list[np.ndarray]] = [[], [], [], [], []]
    alone = []
    for j, (path, n_j) in enumerate(draws):
        C = path.running_cost + path.terminal_cost
        a = -(C + path.ito) / lam
        if path.log_likelihoods is not None:
            alone.append([_optimal_value(row, lam)[:2] for row in a.reshape(k, n_j)])
            pooled = np.log(shares) + path.log_likelihoods
            top = pooled.max(axis=1, keepdims=True)
            mixture = top[:, 0] + np.log(np.exp(pooled - top).sum(axis=1))
            a = a + path.log_likelihoods[:, j] - mixture
        exited = np.ones(C.shape, bool) if path.exit_times is None else ~np.isnan(path.exit_times)
        for part, values in zip(parts, (a, C, path.left_box, path.final_states, ~exited)):
            part.append(values.reshape(k, n_j, *values.shape[1:]))
    a, C, left, final, unexited = (np.concatenate(part, axis=1) for part in parts)
    components = None
    if alone:
        values = np.array(alone)  # (J, k, 2)
        components = (values[..., 0].T, values[..., 1].T)
    return a, C, left, final, unexited, components


def _proposal_policy(proposal):
    """``proposal.policy`` where it has one (a Solution, a combination), else ``proposal``."""
    method = getattr(proposal, "policy", None)
    if callable(method):
        return method
    if callable(proposal):
        return proposal
    raise TypeError(
        "proposal must have a .policy(x, t) method (a Solution, a combination) or be callable as "
        f"policy(x, t) -> (N, m), got {type(proposal).__name__}"
    )
