"""Certified errors: where the embedded levels do not converge, the error at a few states measured
against certified optima (docs page :doc:`accuracy`, "Certified states where the estimate cannot
decide"; :func:`gridlbc.certify`, docs page :doc:`validating`).
"""

from __future__ import annotations

import warnings

import numpy as np

from ..certificate import sample_certificate
from ..errors import GridlbcWarning
from .estimate import given_floor, quiet_reads, relative_error
from .matter import judged_states

CERTIFIED_STATES = 16
""":func:`solve_to_tolerance` certifies the user's states
(:func:`~gridlbc.accuracy.certified_error`) where the embedded levels do not converge, if there are
at most this many."""


CERTIFICATE_SAMPLES = 1000
"""Samples per state of the certificates that :func:`~gridlbc.accuracy.certified_error` draws first
(four times as many where the first ones cannot decide)."""


CERTIFICATE_LEVEL = 0.95
"""The confidence level of each state's certified interval
(:func:`~gridlbc.accuracy.certified_error`)."""


CERTIFICATE_STEPS = 300
"""The certificates' first Euler–Maruyama step is T / this
(:func:`~gridlbc.accuracy.certified_error`)."""


def certificate_work(n_states: int) -> int:
    """The sample-steps of the first certificates at ``n_states`` states: samples × (the steps at
    Δt_c and at 2Δt_c) × states (:func:`~gridlbc.accuracy.certified_error`)."""
    return CERTIFICATE_SAMPLES * (CERTIFICATE_STEPS + CERTIFICATE_STEPS // 2) * n_states


def certifiable(solution, states) -> bool:
    """Whether :func:`solve_to_tolerance` certifies the user's ``states``
    (:func:`~gridlbc.accuracy.certified_error`) after a round whose estimate missed: where the
    embedded levels do not converge at first order (the estimate is then rough in either direction:
    far above the error on 4-D grids of a few dozen nodes per axis), the user gave at
    most :data:`CERTIFIED_STATES` states, and the round cost at least as much as the certificates
    would: its node-steps (nodes × steps) against their sample-steps
    (:func:`~gridlbc.accuracy.certified.certificate_work`), each an interpolation or a stencil of
    about the same cost. Where a round is cheaper, the next one is the cheaper way to learn more (on
    a 32² grid the certificates took a hundred times as long as the round)."""
    embedded = solution.embedded
    if states is None or embedded is None or embedded.converging:
        return False
    n = len(judged_states(solution, states))
    work = solution.grid.size * solution.diagnostics.steps
    return n <= CERTIFIED_STATES and work >= certificate_work(n)


@quiet_reads()
def certified_error(solution, X: np.ndarray, tol: float) -> float:
    """The relative error of v at the states ``X`` measured against certified optima::

        ê_c = max over x of  max(v(x) − lo(x), hi(x) − v(x)) / |v(x)|,

    with [lo, hi] the :data:`CERTIFICATE_LEVEL` interval of :func:`gridlbc.certify` at x for the
    SDE's optimum: importance sampling with the solution's own policy as proposal (exact for any
    proposal, docs page :doc:`validating`), extrapolated to a vanishing Euler–Maruyama step from
    Δt_c and 2Δt_c (``richardson=True``), Δt_c = T/300 at first. It measures the error itself,
    so it holds where the embedded estimate cannot say (levels that do not converge: grids too
    coarse to judge this one). The certificates are drawn again, at most twice each, with half
    the step where the step's contribution exceeds ``tol``/4 (the extrapolation leaves
    O(Δt_c²), small beside it), and with four times the samples where the interval is too wide
    to decide ``tol`` (v lies within ``tol`` of its centre, not of both ends).

    Parameters
    ----------
    solution : Solution
        A grid solution of a problem with a horizon.
    X : ndarray (N, d)
        The states.
    tol : float
        The relative tolerance the certificates must decide.

    Returns
    -------
    float
        ê_c; NaN where a certificate is not :attr:`~gridlbc.Certificate.trusted` at every
        state (too few effective samples or a heavy weight tail: the solve's policy is too poor a
        proposal to certify with), and without certificates where the estimate's response to the
        costs' excess between the nodes, S
        (:meth:`~gridlbc.accuracy.EmbeddedEstimate.excess_response`), exceeds ``tol`` at a state: a
        goal or a well narrower than a cell that the solve misses, its policy steers around as well,
        and certificates that it proposes agree with the solve without a sign of it, with a
        large ESS (the corpus's ``goal_off8``, a goal an eighth of a cell wide: docs page
        :doc:`accuracy`, "Solving to a tolerance").
    """
    v = np.asarray(solution.value(X, 0.0), dtype=float).reshape(-1)
    floor = given_floor(solution, X)  # relative to abs(v) at the user's states
    if solution.embedded is not None:
        unseen = solution.embedded.excess_response(X, 0.0)
        if np.any(relative_error(unseen, v, floor) > tol):
            return np.nan
    n, dt = CERTIFICATE_SAMPLES, solution.problem.horizon / CERTIFICATE_STEPS
    halvings = more = 0
    while True:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GridlbcWarning)
            c = sample_certificate(
                solution.problem,
                solution.policy,
                X,
                n,
                dt=dt,
                seed=0,
                progress=False,
                proposal=None,
                richardson=True,
            )
        if not np.all(c.trusted):
            return np.nan
        lo, hi = (np.asarray(end, dtype=float).reshape(-1) for end in c.interval(CERTIFICATE_LEVEL))
        error = float(np.max(relative_error(np.maximum(v - lo, hi - v), v, floor)))
        step = relative_error(
            np.abs(np.asarray(c.step_contribution, dtype=float).reshape(-1)), v, floor
        )
        centre = relative_error(np.abs(v - 0.5 * (lo + hi)), v, floor)
        if step.max() > tol / 4 and halvings < 2:
            dt, halvings = dt / 2, halvings + 1
        elif error > tol and centre.max() <= tol and more < 2:
            n, more = 4 * n, more + 1
        else:
            return error
