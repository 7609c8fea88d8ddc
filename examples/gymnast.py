"""The gymnast (acrobot) swing-up from the paper's test state (−105°, −15°) at rest: solve the
4-D grid problem, roll the policy out without noise and draw the swing.

    python examples/gymnast.py [--out figures] [--quick]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import gridlbc
from gridlbc.studies.gymnast import angle_distance, animate_swingup, plot_swingup
from gridlbc.studies.problems import GYMNAST_START, gymnast_problem

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="a 13⁴ grid, for a look in seconds")
args = parser.parse_args()

# Acrobot in canonical momenta, T = 3, λ = 1, g = xᵀdiag(10, 10, ½, ½)x, hip stops at ±π.
n = 13 if args.quick else 51
problem = gymnast_problem(n)
solution = gridlbc.solve(problem, dt=0.05, dtype="float32", fitting="terminal", progress=True)
print(f"predicted v(x0, 0) = {solution.value(GYMNAST_START, 0.0):.2f}")

run = gridlbc.simulate(problem, solution.policy, GYMNAST_START, dt=0.002, noise=False)
print(
    f"noise-free cost {run.costs[0]:.2f}, final distance from the handstand "
    f"{angle_distance(run.final_states)[0]:.2f} rad"
)

out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig = plot_swingup(run.times, {f"{n}⁴ grid": (run.states[0], run.controls[0])})
fig.savefig(out / "gymnast_example.png", dpi=110)
animate_swingup(run.times, run.states[0], out / "gymnast_example.gif", title=f"gymnast {n}⁴")
print("wrote", out / "gymnast_example.png", out / "gymnast_example.gif")
