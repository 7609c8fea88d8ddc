"""Projection pitfalls: weights that aim a combination at a target terminal cost, when the
component costs represent it well and when they do not (negative weights, Σw far from one).

    python examples/projection.py [--out figures] [--quick]
"""

import argparse
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Quadratic

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="(accepted for uniformity; fast anyway)")
args = parser.parse_args()

lam = 1.0
x = np.linspace(-1.5, 2.5, 401)[:, None]
cases = {  # component centres, weight W of g = W (x − c)², target centre
    "represented well": ((-0.5, 0.5), 0.5, 0.2),
    "target outside the components": ((-0.5, 0.5), 0.5, 1.2),
    "components too narrow": ((0.0, 1.0), 25.0, 0.5),
}
fig, axes = plt.subplots(1, 3, figsize=(15, 4), constrained_layout=True)
for ax, (title, (centres, W, c_target)) in zip(axes, cases.items()):
    components = [Quadratic([c], [W]) for c in centres]
    target = Quadratic([c_target], [W])
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        w = gridlbc.project(target, components, temperature=lam)  # analytic Gaussian integrals
    print(f"{title}: w = {np.round(w, 3)}, Σw = {w.sum():.2f}")
    for message in said:
        print("   ProjectionWarning:", message.message)
    ax.plot(x, np.exp(-target(x) / lam), "k--", label="target h̄")
    ax.plot(x, sum(wi * np.exp(-c(x) / lam) for wi, c in zip(w, components)), "C3", label="Σ wᵢ hᵢ")
    ax.set(title=f"{title}: w = {np.round(w, 2)}", xlabel="x", ylabel="h = exp(−g/λ)")
    ax.legend(fontsize=8)
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "projection_example.png", dpi=110)
print("wrote", out / "projection_example.png")
