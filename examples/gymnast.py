"""The gymnast (acrobot) swing-up from the paper's test state: still frames and a GIF.

Writes the figure with gridlbc.studies.figures.gymnast (see its docstring for the experiment).

    python examples/gymnast.py [--out figures] [--quick]
"""

import argparse

from gridlbc.studies.figures import make_all

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="small grid, for a look in seconds")
args = parser.parse_args()
make_all(args.out, quick=args.quick, only=["gymnast"])
