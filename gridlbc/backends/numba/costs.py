"""The wrap-aware quadratic form of :class:`gridlbc.costs.Quadratic` and
:class:`gridlbc.costs.Tracking`, in one pass over the states.

A cost is read at every step of every simulated path (rollouts, certificates, the error
estimate's paths), a few thousand states at a time; in numpy the difference, its wrap and the
form make several temporaries per call.
"""

from __future__ import annotations

import numpy as np

from .options import jit


@jit
def quadratic_kernel(x, center, weights, periods, out):
    """out[s] = max(Σ_ij d_i W_ij d_j, 0) with d = x[s] − c, c = ``center[s]`` (or ``center[0]``
    for every state where ``center`` has one row), d_k taken to its nearest image in
    [−P_k/2, P_k/2) on the axes with a finite period P_k (``periods``, inf elsewhere)."""
    n, d = x.shape
    one_center = center.shape[0] == 1
    diff = np.empty(d)
    for s in range(n):
        c = 0 if one_center else s
        for k in range(d):
            y = x[s, k] - center[c, k]
            period = periods[k]
            if period < np.inf:
                y = (y + 0.5 * period) % period - 0.5 * period
            diff[k] = y
        total = 0.0
        for i in range(d):
            row = 0.0
            for j in range(d):
                row += weights[i, j] * diff[j]
            total += diff[i] * row
        out[s] = total if total > 0.0 else 0.0
