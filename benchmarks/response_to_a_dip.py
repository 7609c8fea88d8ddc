"""How much of a dip at one node a scheme's solve carries to t = 0: the fitted scheme against the
plain one, on the grid of 11 nodes per axis that an embedded grid of 21 has (docs/accuracy.rst,
"Costs between the nodes": why the response S is measured with the plain scheme).

ẋ = u on [−2, 2]^d, λ = 0.1, T = 1, g = 0.1 |x|² with a dip of 2.5 λ at the node x = 0. Read as
a grid function, the dip's desirability is a hat of the spacing h = 0.4 around the node, and
the exact response of v at t = 0 is

    −λ log(1 + (e^{2.5} − 1) ∫ N(x − y; λT) hat(y) dy / ∫ N(x − y; λT) e^{−0.1|y|²/λ} dy)

(a product of 1-D integrals, by quadrature). The table gives each scheme's response, its
v with the dip minus its v without, as a ratio to the exact one, at three states.

    python benchmarks/response_to_a_dip.py
"""

from __future__ import annotations

import warnings

import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem
from gridlbc.systems import LinearSystem

LAM, T, DIP, H = 0.1, 1.0, 0.25, 0.4


def problem(d: int, dip: bool) -> Problem:
    """The d-dimensional problem, with or without the dip at x = 0."""

    def cost(x):
        smooth = 0.1 * np.sum(x**2, axis=1)
        return smooth - DIP * np.all(np.abs(x) < 1e-9, axis=1) if dip else smooth

    grid = Grid([Axis(-2.0, 2.0, 11) for _ in range(d)])
    return Problem(LinearSystem(np.zeros((d, d)), np.eye(d)), grid, T, cost, temperature=LAM)


def exact_response(x: np.ndarray) -> np.ndarray:
    """The response of v(x, 0) to the dip's hat, exactly (module docstring)."""
    y = np.linspace(-3.0, 3.0, 6001)
    dy = y[1] - y[0]

    def smoothed(xi, f):
        kernel = np.exp(-((xi - y) ** 2) / (2 * LAM * T)) / np.sqrt(2 * np.pi * LAM * T)
        return np.sum(kernel * f) * dy

    hat = np.maximum(0.0, 1.0 - np.abs(y) / H)
    out = []
    for row in x:
        base = np.prod([smoothed(xi, np.exp(-0.1 * y**2 / LAM)) for xi in row])
        bump = np.prod([smoothed(xi, hat) for xi in row]) * (np.exp(DIP / LAM) - 1.0)
        out.append(-LAM * np.log1p(bump / base))
    return np.array(out)


def main() -> None:
    print(f"{'d':>2}{'scheme':>10}{'dt':>6}   response / exact at x = 0, (0.2, …), (0.4, 0, …)")
    for d in (1, 2, 4):
        x = np.array([[0.0] * d, [0.2] * d, [0.4] + [0.0] * (d - 1)])
        exact = exact_response(x)
        for fitting, name in ((None, "plain"), ("terminal", "fitted")):
            for dt in (0.2, 0.05):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", gridlbc.GridlbcWarning)
                    v = [
                        gridlbc.solve(problem(d, dip), dt, fitting=fitting, error_estimate=False)
                        for dip in (True, False)
                    ]
                ratio = (v[0].value(x) - v[1].value(x)) / exact
                print(f"{d:>2}{name:>10}{dt:>6}   " + "  ".join(f"{r:5.2f}" for r in ratio))


if __name__ == "__main__":
    main()
