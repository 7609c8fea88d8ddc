"""
Interpolating goals by projection
=================================

To reach a goal no component was solved for, project its desired terminal reward
h̄ = exp(−ḡ/λ) onto the span of the components' rewards h_i = exp(−g_i/λ): the weights w solve
A w = b with A_ij = ⟨h_i, h_j⟩ and b_i = ⟨h_i, h̄⟩. Combining with those weights gives the
optimal controller for the projected terminal cost. When the components are too narrow or too
far apart, the projection represents the target poorly (weights far from summing to one, or
negative; a large residual) and :func:`gridlbc.project` warns. This is the paper's Figure 4.
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Quadratic

grid = Grid([Axis(-2, 3, 501)])
x = grid.nodes()
lam = 1.0
fig, axes = plt.subplots(1, 2, figsize=(9, 3.4), constrained_layout=True, sharey=True)
for ax, width, title in [
    (axes[0], 1.0, "wide rewards: a good fit"),
    (axes[1], 20.0, "narrow rewards: a poor fit"),
]:
    # the goal x = 0.5 halfway between components solved for x = 0 and x = 1
    target = Quadratic([0.5], [width])
    components = [Quadratic([0.0], [width]), Quadratic([1.0], [width])]
    result = gridlbc.projection(target, components, grid, temperature=lam)  # the full report
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        gridlbc.project(target, components, grid, temperature=lam)  # just w, warning if poor
    h = np.array([np.exp(-c(x) / lam) for c in components])
    ax.plot(x[:, 0], np.exp(-target(x) / lam), "k", lw=2, label="target h̄")
    for i, hi in enumerate(h):
        ax.plot(x[:, 0], hi, "--", label=f"h_{i + 1}")
    ax.plot(x[:, 0], result.weights @ h, "C3", label="Σ w_i h_i")
    ax.set(
        title=f"{title}\nw = {np.round(result.weights, 3)}, residual {result.residual:.2f}",
        xlabel="x",
    )
    print(f"{title}: w = {result.weights}, residual {result.residual:.3f}")
    for w in caught:
        print(f"    {type(w.message).__name__}: {w.message}")
axes[0].legend()
