"""First-exit solves with and without defect correction against certified truths.

For the corpus's first-exit members (``holdout/truths.json``, the certificate extrapolated to a
vanishing SDE step) and the problems of ``first_exit_holdout.py`` (their certified values as
quoted on the docs page first_exit, "Hold-outs"): the prediction, the error, the embedded
estimate, whether the solve warned, whether the correction was kept, and its time (estimate
included, the faster of two runs), for
``defect_correction=0`` (the default) and the steps given.

    python benchmarks/defect_correction.py [--steps 2]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE / "holdout"))

import first_exit_holdout  # noqa: E402
from corpus import MEMBERS  # noqa: E402

import gridlbc  # noqa: E402

QUOTED = {  # first_exit_holdout.py's certified values (docs/first_exit.rst, 2026-12-04)
    "bays (point mass)": ([1.2509, 0.9226], [0.0051, 0.0045]),
    "upright (pendulum)": ([12.6664, 3.6848], [0.0662, 0.0410]),
    "door (λ = 0.2)": ([2.8530, 5.4523], [0.0028, 0.0028]),
    "chain 3-D": ([2.4592, 2.5275], [0.0040, 0.0049]),
}


def cases():
    """(name, problem, states, certified, SE) of every first-exit problem with a truth."""
    truths = json.loads((HERE / "holdout" / "truths.json").read_text())["members"]
    for m in MEMBERS:
        if m.name in ("hot_band", "dock"):
            t = truths[m.name]["states"]
            v = [s.get("v_extrapolated", s["v"]) for s in t]
            se = [s.get("se_extrapolated", s["se"]) for s in t]
            yield m.name, m.build(), np.asarray(m.states, float), v, se
    for name, (build, states) in first_exit_holdout.PROBLEMS.items():
        yield name, build(), np.asarray(states, float), *QUOTED[name]


def run(problem, states, steps):
    """The solve's values, estimates, whether it warned, whether the correction was kept, and
    its time (the faster of two runs)."""
    times = []
    for _ in range(2):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", gridlbc.ResolutionWarning)
            start = time.perf_counter()
            solution = gridlbc.solve(problem, defect_correction=steps)
            times.append(time.perf_counter() - start)
    seconds = min(times)
    warned = any(issubclass(w.category, gridlbc.ResolutionWarning) for w in caught)
    kept = "+dc" in solution.operator.method
    return solution.value(states), solution.error_estimate(states), warned, kept, seconds


def main(steps: int) -> None:
    print(
        f"{'problem':20}{'state':>16}{'dc':>4}{'predicted':>10}{'certified':>17}{'error':>8}"
        f"{'estimate':>9}{'est≥act/2':>10}{'warned':>7}{'kept':>5}{'time s':>7}",
        flush=True,
    )
    for name, problem, states, certified, se in cases():
        for k in (0, steps):
            v, e, warned, kept, seconds = run(problem, states, k)
            for i, x in enumerate(states):
                actual = max(abs(v[i] - certified[i]) - 2 * se[i], 0.0)
                state = "(" + ", ".join(f"{c:.3g}" for c in x) + ")"
                print(
                    f"{name:20}{state:>16}{k:>4}{v[i]:>10.4f}{certified[i]:>10.4f} ± "
                    f"{se[i]:<5.3f}{100 * (v[i] - certified[i]) / abs(certified[i]):>+7.1f}%"
                    f"{e[i]:>9.3f}{'yes' if e[i] >= actual / 2 else 'NO':>10}"
                    f"{'yes' if warned else 'no':>7}{'yes' if kept else '-':>5}{seconds:>7.2f}",
                    flush=True,
                )


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=2, help="defect-correction steps")
    main(parser.parse_args().steps)
