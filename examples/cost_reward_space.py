"""Cost space vs reward space: v, z and u* of the pendulum swing-up (paper Fig. 2).

Writes the figure with gridlbc.studies.figures.cost_reward_space (see its docstring for the experiment).

    python examples/cost_reward_space.py [--out figures] [--quick]
"""

import argparse

from gridlbc.studies.figures import make_all

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="small grid, for a look in seconds")
args = parser.parse_args()
make_all(args.out, quick=args.quick, only=["cost_reward_space"])
