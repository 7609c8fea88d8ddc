"""
Validating an optimality claim with the certificate
===================================================

A grid solver's v(x₀, 0) = −λ log z(x₀, 0) claims to be the optimal cost. The certificate checks
the claim without trusting the solver: run any policy u on the SDE and accumulate
S_u = g(x_T) + ∫(q + ½uᵀRu) dt + ∫uᵀR dε; then v*(x₀) = −λ log E_u[exp(−S_u/λ)] exactly
(Feynman–Kac and Girsanov), whatever u is. The better u, the smaller the error bar. The same
samples give the policy's own cost J(u) ≥ v*.
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import Pendulum

x0 = np.array([2.8, 0.0])
rows = []
for n in (48, 96):
    grid = Grid([Axis(-np.pi, np.pi, n, periodic=True), Axis(-10, 10, n + 1)])
    problem = Problem(Pendulum(), grid, horizon=3.0, terminal_cost=Quadratic([0, 0], [10, 0.5]))
    for fitting in (None, "terminal"):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", gridlbc.ResolutionWarning)
            solution = gridlbc.solve(problem, fitting=fitting)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", gridlbc.CertificateWarning)  # shown below instead
            # The swing-up needs a fine SDE step: the certificate is exact up to the
            # Euler–Maruyama chain's O(Δt) bias, a few percent here at Δt = 0.01.
            certificate = gridlbc.certify(
                problem, solution.policy, x0, n_samples=300, dt=0.002, seed=0, progress=False
            )
        rows.append((n, fitting or "plain", solution.value(x0, 0.0), certificate))
        print(f"{n}², {fitting or 'plain'}: predicted v(x0, 0) = {rows[-1][2]:.2f}")
        for w in caught:  # the plain operator says when it cannot resolve the problem
            print("    the solver warned:", str(w.message).split(":")[0])
        print("   ", certificate.summary().splitlines()[0])

# %%
# A poor proposal still gives an unbiased estimate in z, but few samples carry its weight: the
# effective sample size says so (``certificate.trusted`` is False below 30), and the fix is a
# better proposal (a finer or fitted grid), not more trust.
#
# The predictions against the certified optimum (± 2 SE) and the policies' own costs. Where the
# prediction sits inside the certified band, the claim holds at this sample size; a policy cost
# above the band is the policy's suboptimality, J(u) − v* = λ KL(P_u ‖ P*). Here the plain
# predictions sit far below the band (optimistic, as the solver warned) and their policies cost
# several units more than the optimum; the fitted predictions are within about 2 % of v*, and
# their policies' gaps are within two standard errors of zero.
fig, ax = plt.subplots(figsize=(6.5, 3.8), constrained_layout=True)
for k, (_n, _kind, predicted, c) in enumerate(rows):
    if not c.trusted:
        ax.annotate(
            "untrusted",
            (k, c.optimal_value),
            textcoords="offset points",
            xytext=(6, -12),
            fontsize=8,
        )
    ax.errorbar(
        k,
        c.optimal_value,
        yerr=2 * c.optimal_value_se,
        fmt="o",
        color="k",
        label="certified v* ± 2 SE" if k == 0 else None,
    )
    ax.plot(k, predicted, "s", color="C0", label="predicted v(x₀, 0)" if k == 0 else None)
    ax.plot(k, c.policy_cost, "^", color="C3", label="policy cost J(u)" if k == 0 else None)
ax.set_xticks(range(len(rows)), [f"{n}²\n{kind}" for n, kind, *_ in rows])
ax.set(ylabel="cost from x₀ = (2.8, 0)", title="Pendulum swing-up: claims against the truth")
ax.legend()
