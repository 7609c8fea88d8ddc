"""How to solve the first-exit system (diag(q/λ) − L)_II z_I = b: sparse LU against Krylov methods
and algebraic multigrid, on 2-D, 3-D and 4-D problems (docs/first_exit.rst, "Linear solvers").

Each row assembles one first-exit problem (a noisy integrator chain with a disc-shaped exit set
and the boundary fitted) and solves its interior system with:

- ``splu``: scipy's SuperLU (what ``linear_solver="direct"`` uses);
- ``gmres+ilu``: restarted GMRES with an incomplete LU preconditioner (``"gmres"``);
- ``bicgstab``: BiCGSTAB on the row-scaled system (unit diagonal: Jacobi is already applied);
- ``pyamg-air``: pyamg's AIR multigrid for non-symmetric M-matrices, as a GMRES preconditioner
  (only where pyamg is installed: ``pip install pyamg``).

It prints the seconds (setup + solve, shortest of ``repeats``) and the relative residual reached,
and each method's time relative to ``splu`` in the same run; a method that took more than
:data:`TIME_LIMIT` is not run on the larger cases.

``--average`` instead solves the average-cost problem of the same chains (no exit set; q as
above) with ``gridlbc.solve(..., error_estimate=False)`` by Noda's inverse iteration with a
sparse LU per shift (``linear_solver="direct"``) and on BiCGSTAB (``"bicgstab"``, with
the ILU-GMRES fallback of ``"auto"``), and prints each one's seconds, eigen-residual
‖(M − μI)e‖ / (‖M‖∞‖e‖), Krylov iterations (per shift) and the difference of the two c.

    python benchmarks/stationary_solvers.py [--average]
"""

from __future__ import annotations

import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import gridlbc as g
from gridlbc.regions import Ball
from gridlbc.schemes.generator import exit_generator

CASES = {
    "2-D 201²": (2, 201),
    "2-D 401²": (2, 401),
    "3-D 31³": (3, 31),
    "3-D 41³": (3, 41),
    "4-D 15⁴": (4, 15),
    "4-D 19⁴": (4, 19),
}

TIME_LIMIT = 60.0
"""A method that took longer than this on a case is not run on the larger cases."""


def system(d: int, n: int):
    """The interior system of a d-dimensional noisy chain ẍ-like problem: x_{k} driven by
    x_{k+1}, the last by the control, with noise on every axis (control costs 1 … d)."""
    A = np.diag(np.ones(d - 1), 1) * 0.5
    chain = g.systems.LinearSystem(A, np.eye(d))
    grid = g.Grid([g.Axis(-2, 2, n) for _ in range(d)])
    problem = g.Problem(
        chain,
        grid,
        None,
        state_cost=lambda x: 1.0 + 0.25 * np.sum(x**2, axis=1),
        control_cost=np.arange(1.0, d + 1),
        temperature=0.5,
        exit=Ball(np.r_[1.0, np.zeros(d - 1)], 0.6),
    )
    E = problem.exit_mask()
    gen = exit_generator(problem, "fitted", E)
    q = problem.state_cost_values()
    interior = np.flatnonzero(~E)
    A_full = (sp.diags(np.where(E, 0, q) / problem.temperature) - gen.matrix).tocsr()[interior]
    b = gen.boundary_rates[interior] @ np.ones(gen.boundary_rates.shape[1])
    A = A_full[:, interior].tocsr()
    inverse = sp.diags(1.0 / A.diagonal())  # rows scaled as gridlbc.stationary does
    return (inverse @ A).tocsr(), inverse @ b


def _splu(A, b):
    return spla.splu(A.tocsc()).solve(b)


def _krylov(method, preconditioner):
    def solve(A, b):
        M = preconditioner(A)
        z, info = method(A, b, rtol=1e-10, atol=0.0, M=M, maxiter=2000)
        return z if info == 0 else np.full_like(b, np.nan)

    return solve


def _ilu(A):
    ilu = spla.spilu(A.tocsc(), drop_tol=1e-4, fill_factor=10)
    return spla.LinearOperator(A.shape, ilu.solve)


def _jacobi(A):
    inv = 1.0 / A.diagonal()
    return spla.LinearOperator(A.shape, lambda v: inv * v)


def _air(A):
    import pyamg

    return pyamg.air_solver(A.tocsr()).aspreconditioner()


METHODS = {
    "splu": _splu,
    "gmres+ilu": _krylov(lambda *a, **k: spla.gmres(*a, restart=50, **k), _ilu),
    "bicgstab": _krylov(spla.bicgstab, _jacobi),
    "pyamg-air": _krylov(lambda *a, **k: spla.gmres(*a, restart=50, **k), _air),
}


def main(repeats: int = 1) -> None:
    try:
        import pyamg  # noqa: F401
    except ImportError:
        METHODS.pop("pyamg-air")
    header = f"{'problem':<12}{'unknowns':>10}" + "".join(f"{m:>22}" for m in METHODS)
    print(header, flush=True)
    too_slow: set[str] = set()
    for name, (d, n) in CASES.items():
        A, b = system(d, n)
        cells = []
        base = None
        for method, solve in METHODS.items():
            if method in too_slow:
                cells.append(f"{'(too slow)':>22}")
                continue
            walls, z = [], None
            for _ in range(repeats):
                started = time.perf_counter()
                z = solve(A, b)
                walls.append(time.perf_counter() - started)
            wall = min(walls)
            if wall > TIME_LIMIT:
                too_slow.add(method)
            residual = np.linalg.norm(A @ z - b) / np.linalg.norm(b)
            base = wall if method == "splu" else base
            ratio = f" ×{wall / base:.2f}" if base else ""
            cells.append(f"{wall:>9.3f}s {residual:.0e}{ratio:>6}")
        print(f"{name:<12}{A.shape[0]:>10}" + "".join(f"{c:>22}" for c in cells), flush=True)


AVERAGE_CASES = {
    "2-D 201²": (2, 201, False),
    "2-D 401²": (2, 401, False),
    "2-D 201², noise on x₂": (2, 201, True),
    "3-D 21³": (3, 21, False),
    "3-D 31³": (3, 31, False),
    "3-D 41³": (3, 41, False),
    "3-D 31³, noise on x₃": (3, 31, True),
    "4-D 15⁴": (4, 15, False),
    "4-D 21⁴": (4, 21, False),
}
"""name: (dimension, nodes per axis, noise on the last axis only)."""


def average_problem(d: int, n: int, last_only: bool):
    """The chain of :func:`system` without an exit: an average-cost problem (with noise, and
    control, on the last axis only where ``last_only``: a mechanical chain)."""
    A = np.diag(np.ones(d - 1), 1) * 0.5
    B = np.eye(d)[:, -1:] if last_only else np.eye(d)
    return g.Problem(
        g.systems.LinearSystem(A, B),
        g.Grid([g.Axis(-2, 2, n) for _ in range(d)]),
        "average",
        state_cost=lambda x: 1.0 + 0.25 * np.sum(x**2, axis=1),
        control_cost=np.arange(1.0, B.shape[1] + 1),
        temperature=0.5,
    )


def average_main() -> None:
    from gridlbc.schemes.generator import generator_matrix
    from gridlbc.stationary import eigen_residual

    print(
        f"{'problem':<24}{'unknowns':>9}{'LU+Noda':>12}{'residual':>10}{'Noda+BiCGSTAB':>15}"
        f"{'residual':>10}{'×LU':>7}  {'|Δc|':>8}  iterations per shift",
        flush=True,
    )
    too_slow = False
    for name, (d, n, last_only) in AVERAGE_CASES.items():
        problem = average_problem(d, n, last_only)
        M = generator_matrix(problem, "fitted") - sp.diags(problem.state_cost_values() / 0.5)
        out = {}
        for method in ("direct", "bicgstab"):
            if method == "direct" and (too_slow or d >= 4):  # 4-D LU: 258 s on 15⁴ (first exit)
                continue
            started = time.perf_counter()
            s = g.solve(problem, linear_solver=method, error_estimate=False)
            wall = time.perf_counter() - started
            too_slow |= method == "direct" and wall > TIME_LIMIT
            mu = -s.average_cost / problem.temperature
            out[method] = (wall, eigen_residual(M, mu, s.slices[0]), s)
        it = out["bicgstab"][2].diagnostics.iterations
        if "direct" in out:
            lu = f"{out['direct'][0]:>11.2f}s{out['direct'][1]:>10.0e}"
            ratio = f"{out['bicgstab'][0] / out['direct'][0]:>7.2f}"
            dc = abs(out["bicgstab"][2].average_cost - out["direct"][2].average_cost)
            dc_text = f"{dc:>8.0e}"
        else:
            skipped = "(too slow)" if too_slow and d < 4 else "(not run)"
            lu, ratio, dc_text = f"{skipped:>12}{'':>10}", f"{'':>7}", f"{'':>8}"
        print(
            f"{name:<24}{M.shape[0]:>9}{lu}{out['bicgstab'][0]:>14.2f}s"
            f"{out['bicgstab'][1]:>10.0e}{ratio}  {dc_text}  {sum(it)} {it}",
            flush=True,
        )


if __name__ == "__main__":
    average_main() if "--average" in sys.argv[1:] else main()
