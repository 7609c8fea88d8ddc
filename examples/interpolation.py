"""An intermediate goal on the pendulum: LBC vs naive blend vs direct solve (Fig. 6 idea).

Writes the figure with gridlbc.studies.figures.interpolation (see its docstring for the experiment).

    python examples/interpolation.py [--out figures] [--quick]
"""

import argparse

from gridlbc.studies.figures import make_all

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="small grid, for a look in seconds")
args = parser.parse_args()
make_all(args.out, quick=args.quick, only=["interpolation"])
