"""Projecting a target terminal reward onto component rewards (paper Figs. 3 and 4).

Writes the figure with gridlbc.studies.figures.projection (see its docstring for the experiment).

    python examples/projection.py [--out figures] [--quick]
"""

import argparse

from gridlbc.studies.figures import make_all

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="small grid, for a look in seconds")
args = parser.parse_args()
make_all(args.out, quick=args.quick, only=["projection"])
