"""The Pareto tail diagnostic k̂ of importance weights (Pareto-smoothed importance sampling).

An importance-sampling estimate of a mean, here z*(x₀) = E_u[w] with w = exp(−S_u/λ) (see
:mod:`gridlbc.certificate`), is reliable when the weights' distribution has a light enough right tail.
Vehtari, Simpson, Gelman, Yao & Gabry ("Pareto smoothed importance sampling", JMLR 25(72), 2024)
measure the tail by fitting a generalized Pareto distribution (GPD)

    P(w − u > y | w > u) = (1 + ξ y / σ)^(−1/ξ)

to the M largest weights' exceedances over u, the (M + 1)-th largest weight, with

    M = ⌈min(n / 5, 3 √n)⌉

for n independent draws. Its shape k̂ = ξ̂ says how many moments the weights have (those of order
< 1/ξ): the paper's guidance is k̂ < 0.5 reliable (finite variance), 0.5 ≤ k̂ < 0.7 usable with a
slower convergence, k̂ ≥ 0.7 unreliable: the mean's error then shrinks so slowly that no practical
sample count helps, and an ESS or a delta-method standard error computed from the same draws is
over-optimistic because the draws that would show the tail are missing.

The fit is Zhang & Stephens' empirical-Bayes estimator ("A new and efficient estimation method for
the generalized Pareto distribution", Technometrics 51(3), 2009), as PSIS uses it. With the
exceedances sorted, x₁ ≤ … ≤ x_M, and the GPD written in θ = −ξ/σ (so 1 − θx > 0):

- candidate θ_j = 1/x_M + (1 − √(m / (j − ½))) / (3 x_q), j = 1 … m, with m = 30 + ⌊√M⌋ and x_q
  the first quartile x_{⌊M/4 + ½⌋};
- for each, the profile: ξ(θ) = mean log(1 − θ x), profile log-likelihood
  ℓ(θ) = M (log(−θ/ξ(θ)) − ξ(θ) − 1);
- θ̂ = Σ_j π_j θ_j with π_j ∝ exp(ℓ(θ_j)) (normalised; negligible π_j dropped), ξ̂ = ξ(θ̂);
- PSIS's weakly informative prior pulls ξ̂ towards ½ with the weight of 10 observations:
  k̂ = (M ξ̂ + 10 · ½) / (M + 10).

The fit is invariant to the weights' scale, so log-weights are shifted by their maximum first and
nothing overflows.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["pareto_k"]

MIN_TAIL = 5
"""Fewest exceedances the GPD fit uses; with fewer, :func:`pareto_k` returns NaN (as PSIS does)."""

PRIOR_WEIGHT = 10.0
"""Observations' worth of the prior that pulls k̂ towards :data:`PRIOR_SHAPE` (PSIS)."""

PRIOR_SHAPE = 0.5
"""The prior's centre for k̂ (PSIS)."""


def tail_length(n: int) -> int:
    """M = ⌈min(n/5, 3√n)⌉: how many of n independent weights form the fitted tail (PSIS).

    Parameters
    ----------
    n : int
        Number of weights.
    """
    return math.ceil(min(n / 5.0, 3.0 * math.sqrt(n)))


def gpd_shape(exceedances) -> float:
    """Zhang & Stephens' estimate of the generalized Pareto shape ξ, with PSIS's prior.

    Parameters
    ----------
    exceedances : array_like (M,)
        Positive exceedances over a threshold, in any order (M ≥ :data:`MIN_TAIL`).

    Returns
    -------
    float
        k̂ = (M ξ̂ + 10 · ½)/(M + 10), see the module docstring; NaN where no candidate θ has a
        profile likelihood that is a number.
    """
    x = np.sort(np.asarray(exceedances, dtype=float).ravel())
    M = x.size
    if M < MIN_TAIL:
        raise ValueError(f"the GPD fit needs at least {MIN_TAIL} exceedances, got {M}")
    m = 30 + int(math.sqrt(M))
    quartile = x[int(M / 4 + 0.5) - 1]
    theta = 1.0 / x[-1] + (1.0 - np.sqrt(m / (np.arange(1, m + 1) - 0.5))) / (3.0 * quartile)
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = np.log1p(-theta[:, None] * x).mean(axis=1)
        loglik = M * (np.log(-theta / xi) - xi - 1.0)
    # a candidate θ whose profile likelihood is not a number has no weight: where most of the
    # exceedances tie at the largest (paths of one cost, stranger round 45) θ x reaches 1
    finite = np.isfinite(loglik)
    if not finite.any():
        return math.nan
    theta, loglik = theta[finite], loglik[finite]
    # π_j = 1 / Σ_i exp(ℓ_i − ℓ_j): normalised without forming exp(ℓ)
    with np.errstate(over="ignore"):  # a far likelier θ_i: exp → inf, and π_j → 0, its limit
        pi = 1.0 / np.exp(loglik[None, :] - loglik[:, None]).sum(axis=1)
    keep = pi >= 10 * np.finfo(float).eps
    pi, theta = pi[keep], theta[keep]
    theta_hat = float(np.dot(pi, theta) / pi.sum())
    xi_hat = float(np.log1p(-theta_hat * x).mean())
    return (M * xi_hat + PRIOR_WEIGHT * PRIOR_SHAPE) / (M + PRIOR_WEIGHT)


def pareto_k(log_weights) -> float:
    """The PSIS tail diagnostic k̂ of importance weights given by their logarithms.

    Fits a generalized Pareto distribution to the exceedances of the M = ⌈min(n/5, 3√n)⌉ largest
    weights over the (M + 1)-th largest (Vehtari et al., JMLR 2024, §3; Zhang & Stephens 2009),
    for n independent weights; see the module docstring for the estimator. k̂ < 0.5: the weights
    have a finite variance and the importance-sampling estimate converges at the usual rate;
    0.5–0.7: finite mean, slower; > 0.7: unreliable whatever the sample count.

    Parameters
    ----------
    log_weights : array_like (n,)
        log w of independent importance weights (any common shift; ``-inf`` for a zero weight).

    Returns
    -------
    float
        k̂, or NaN where fewer than :data:`MIN_TAIL` weights exceed the threshold (n below about
        25, or the largest weights tied).
    """
    lw = np.asarray(log_weights, dtype=float).ravel()
    if lw.size == 0 or np.any(np.isnan(lw)) or np.any(lw == np.inf):
        raise ValueError("log_weights must be finite or -inf, and not empty")
    n = lw.size
    lw = lw - lw.max()
    order = np.sort(lw)
    # the (M+1)-th largest is the threshold; below the smallest normal number exp underflows
    M = min(tail_length(n), n - 1)
    cutoff = max(order[n - M - 1], math.log(np.finfo(float).tiny))
    tail = order[order > cutoff]
    if tail.size < MIN_TAIL:
        return math.nan
    return gpd_shape(np.exp(tail) - math.exp(cutoff))
