"""The ``gridlbc`` command.

Each subcommand is a function ``_cmd_<name>(args)`` registered in :func:`build_parser`; user
mistakes (``ValueError``, ``TypeError``, ``FileNotFoundError``) end with a one-line message on
stderr and exit status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import warnings
from pathlib import Path


def _cmd_demo(args) -> int:
    from .studies.demo import run_demo

    run_demo(Path(args.out), grid_size=args.grid, progress=not args.quiet)
    return 0


def _cmd_verify(args) -> int:
    """Exit status 0 when every check passes, 1 when one fails (the table says which)."""
    from .studies.verify import run_verification

    report = run_verification(
        grid_size=args.grid,
        samples=args.samples,
        seed=args.seed,
        quick=args.quick,
        progress=not args.quiet,
    )
    print(report.table())
    if args.convergence:
        from .studies.convergence import pendulum_study, pointmass_study

        spacings, sizes = (
            ((1 / 4, 1 / 8, 1 / 16), (32, 64, 128))
            if args.quick
            else ((1 / 4, 1 / 8, 1 / 16, 1 / 32), (64, 128, 256))
        )
        for name, table in (
            ("PointMass vs Riccati", pointmass_study(spacings)),
            ("Pendulum: z-space vs value-space HJB", pendulum_study(sizes)),
        ):
            print(f"\n{name} ({table.points} points, v < min v + {table.band:g})")
            print(table.format())
    if args.json:
        report.to_json(Path(args.json))
        print(f"wrote {args.json}")
    print(
        f"{'all checks passed' if report.passed else 'SOME CHECKS FAILED'} "
        f"({report.wall_time:.0f} s)"
    )
    return 0 if report.passed else 1


def _vector(text: str, flag: str) -> list[float]:
    """Comma-separated numbers (multiples of pi allowed) from a flag's value."""
    from .config import number

    return [number(item.strip(), flag) for item in text.split(",")]


def _states(values: list[str], grid, flag: str):
    """The states given by a repeatable flag (``--at=x1,x2``), checked against ``grid``."""
    import numpy as np

    return grid.check_states(np.array([_vector(x, flag) for x in values]), flag)


def _description_from_flags(data: dict, args) -> dict:
    """The TOML description ``data`` with the command-line flags of ``solve`` laid over it."""
    data = dict(data)
    if args.system is not None:
        data["system"] = {"name": args.system}
    if args.param:
        system = dict(data.get("system", {}))
        parameters = dict(system.get("parameters", {}))
        for item in args.param:
            key, sep, value = item.partition("=")
            if not sep or not key:
                raise ValueError(f"--param expects KEY=VALUE, got {item!r}")
            parameters[key.strip()] = _vector(value, f"--param {key}")[0]
        data["system"] = {**system, "parameters": parameters}
    if args.grid is not None and args.axis:
        raise ValueError("give either --grid (node counts, default box) or --axis, not both")
    if args.grid is not None:
        counts = args.grid.split(",")
        if not all(c.strip().isdigit() for c in counts):
            raise ValueError(f"--grid expects node counts such as 101 or 101,81, got {args.grid!r}")
        data["grid"] = {"n": [int(c) for c in counts]}
    if args.axis:
        axes = []
        for item in args.axis:
            parts = [p.strip() for p in item.split(",")]
            periodic = parts[-1] == "periodic"
            parts = parts[:-1] if periodic else parts
            if len(parts) != 3 or not parts[2].isdigit():
                raise ValueError(
                    f"--axis expects LO,HI,N[,periodic] (e.g. --axis=-pi,pi,101,"
                    f"periodic), got {item!r}"
                )
            axes.append({"lo": parts[0], "hi": parts[1], "n": int(parts[2]), "periodic": periodic})
        data["grid"] = {"axes": axes}
    for key in ("horizon", "temperature"):
        if getattr(args, key) is not None:
            data[key] = _vector(getattr(args, key), f"--{key}")[0]
    if args.control_cost is not None:
        values = _vector(args.control_cost, "--control-cost")
        data["control_cost"] = values[0] if len(values) == 1 else values
    for cost in ("terminal", "state"):
        table = dict(data.get(f"{cost}_cost") or {})
        for part in ("center", "weights"):
            value = getattr(args, f"{cost}_{part}")
            if value is not None:
                table[part] = _vector(value, f"--{cost}-{part}")
        if table:
            data[f"{cost}_cost"] = table
    solver = dict(data.get("solver", {}))
    for key in ("method", "dt", "store_every", "dtype", "fitting"):
        if getattr(args, key) is not None:
            solver[key] = getattr(args, key)
    if solver:
        data["solver"] = solver
    return data


def _base_description(args) -> dict:
    """The description of ``--config`` (if given) with the problem flags laid over it."""
    from .config import read_description

    return _description_from_flags(read_description(args.config) if args.config else {}, args)


def _config(data: dict, args):
    """The problem and settings of a description; a missing key says which flag gives it."""
    from .config import problem_from_dict

    try:
        return problem_from_dict(data)
    except (TypeError, ValueError) as exc:
        message = str(exc)
        for key, flags in (
            ("'system'", "--system"),
            ("'grid'", "--grid or --axis"),
            ("'horizon'", "--horizon"),
            ("'terminal_cost'", "--terminal-center and --terminal-weights"),
        ):
            if message == f"missing key {key}":
                message += f": give {flags} or a --config file"
        from_file = args.config and not message.startswith("--")
        raise type(exc)(f"{args.config}: {message}" if from_file else message) from None


def _cmd_solve(args) -> int:
    from .io import save
    from .settings import SolverSettings
    from .solver import solve

    config = _config(_base_description(args), args)
    problem = config.problem
    states = None
    if args.at:
        states = _states(args.at, problem.require_grid("--at"), "--at")
    if args.max_seconds is not None and args.tol is None:
        raise ValueError("--max-seconds is the budget of a solve to a tolerance: give --tol too")
    if not args.quiet:
        print(f"solving {problem.describe()}", flush=True)
    settings = config.settings
    to_tolerance = {} if args.tol is None else {"tol": args.tol, "states": states}
    if args.max_seconds is not None:
        to_tolerance["max_seconds"] = args.max_seconds
    if isinstance(settings, SolverSettings):
        progress = False if args.quiet else settings.progress is not False
        solution = solve(problem, settings=settings, progress=progress, **to_tolerance)
    else:  # a stationary problem: one linear solve, its options by name
        solution = solve(problem, **to_tolerance, **dataclasses.asdict(settings))
    for r in solution.refinement if args.tol is not None else ():
        print(
            f"  round: {'×'.join(map(str, r.shape))}"
            + ("" if problem.stationary else f", dt = {r.dt:.4g}")
            + f", estimated error {r.error:.2%} of |v|, {r.wall_time:.1f} s"
        )
    d = solution.diagnostics
    path = save(solution, args.out)
    if problem.stationary:
        how = solution.operator.method + (
            f" ({d.iterations[0]} iterations)" if d.iterations else ""
        )
    else:
        how = f"{d.method}, {d.steps} steps of dt = {d.dt:.4g}"
    print(
        f"wrote {path}: {how} in {d.wall_time:.1f} s"
        + (f", {d.underflow_nodes} nodes underflowed" if d.underflow_nodes else "")
    )
    if args.tol is not None:
        last = solution.refinement[-1]
        print(
            f"tolerance {args.tol:g} "
            f"{'met' if last.met(args.tol) else 'NOT met (the warning says why)'}: "
            f"estimated error {last.error:.2%} of |v| "
            + ("at the --at states" if states is not None else "where it matters")
        )
    if states is not None:
        v, error = solution.value(states, 0.0), solution.error_estimate(states, 0.0)
        header = "v(x)" if problem.stationary else "v(x, 0)"
        print(f"{'state':>24}  {header:>12}  {'estimated |error|':>18}")
        for x, vx, ex in zip(states, v, error, strict=True):
            print(f"{','.join(f'{c:g}' for c in x):>24}  {vx:12.6g}  {ex:18.3g}")
    return 0


def _sweep_axes(args) -> list[tuple[str, list]]:
    """The swept quantities: (column name, values), in the order of the flags' help."""
    axes: list[tuple[str, list]] = []
    for item in args.param_values or ():
        key, sep, values = item.partition("=")
        if not sep or not key.strip():
            raise ValueError(f"--param-values expects KEY=V1,V2,..., got {item!r}")
        axes.append((key.strip(), _vector(values, f"--param-values {key.strip()}")))
    for flag in ("temperatures", "horizons"):
        if getattr(args, flag) is not None:
            axes.append((flag[:-1], _vector(getattr(args, flag), f"--{flag}")))
    if args.goal:
        axes.append(("goal", [_vector(goal, "--goal") for goal in args.goal]))
    if not axes:
        raise ValueError(
            "nothing to sweep: give --param-values, --temperatures, --horizons "
            "and/or --goal (repeatable)"
        )
    return axes


def _sweep_member(base: dict, names, values) -> dict:
    """The description of one member: ``base`` with the swept values put in."""
    import copy

    data = copy.deepcopy(base)
    for name, value in zip(names, values):
        if name in ("temperature", "horizon"):
            data[name] = value
        elif name == "goal":
            data["terminal_cost"] = {**data.get("terminal_cost", {}), "center": value}
        else:
            system = data.setdefault("system", {})
            system["parameters"] = {**system.get("parameters", {}), name: value}
    return data


def _cmd_sweep(args) -> int:
    """Exit status 0 when every member is solved (or reused), 1 when one failed."""
    import itertools

    from .sweep import import_distributed, sweep

    try:
        import_distributed()
    except ImportError as exc:
        print(f"gridlbc sweep: error: {exc}", file=sys.stderr)
        return 2
    base = _base_description(args)
    axes = _sweep_axes(args)
    names = [name for name, _ in axes]
    combos = list(itertools.product(*(values for _, values in axes)))
    configs = []
    for i, combo in enumerate(combos):
        try:
            configs.append(_config(_sweep_member(base, names, combo), args))
        except (TypeError, ValueError) as exc:
            what = ", ".join(f"{n}={v}" for n, v in zip(names, combo))
            raise type(exc)(f"member {i} ({what}): {exc}") from None
    states = None
    if args.at:
        states = _states(args.at, configs[0].problem.grid, "--at")
    members = sweep(
        [c.problem for c in configs],
        args.out,
        states=states,
        client=args.scheduler,
        workers=args.workers,
        progress=not args.quiet,
        settings=configs[0].settings,
    )
    header = (
        ["#", *names]
        + [f"v({','.join(f'{c:g}' for c in x)})" for x in ([] if states is None else states)]
        + ["solve s", "status"]
    )
    rows = []
    for m, combo in zip(members, combos):
        swept = [",".join(f"{c:g}" for c in v) if isinstance(v, list) else f"{v:g}" for v in combo]
        values = [] if m.values is None else [f"{v:.6g}" for v in m.values]
        if m.path is None:  # failed: no file
            values = ["-"] * (0 if states is None else len(states))
            status = f"failed: {m.error}"
        else:
            status = ("reused " if m.reused else "solved ") + m.path.name
        wall = "-" if m.diagnostics is None else f"{m.diagnostics.wall_time:.2f}"
        rows.append([str(m.index), *swept, *values, wall, status])
    widths = [max(len(h), *(len(r[k]) for r in rows)) for k, h in enumerate(header[:-1])]
    for row in [header, *rows]:
        print("  ".join(c.rjust(w) for c, w in zip(row, widths)) + "  " + row[-1])
    failed = sum(m.error is not None for m in members)
    reused = sum(m.reused for m in members)
    print(
        f"{len(members)} members: {len(members) - failed - reused} solved, {reused} reused, "
        f"{failed} failed; files in {args.out}"
    )
    return 1 if failed else 0


def _cmd_combine(args) -> int:
    import numpy as np

    from .combine import combine
    from .costs import Quadratic
    from .io import load
    from .project import projection

    solutions = [load(p) for p in args.solutions]
    grid = solutions[0].grid
    weights: list[float] | np.ndarray | None = None
    if args.weights is not None and args.project is not None:
        raise ValueError("give either --weights or --project TARGET, not both")
    if args.weights is not None:
        weights = _vector(args.weights, "--weights")
    if args.project is not None:
        costs = [s.problem.terminal_cost for s in solutions]
        target_weights: list[float] | np.ndarray
        if args.project_weights is not None:
            target_weights = _vector(args.project_weights, "--project-weights")
        elif isinstance(costs[0], Quadratic):
            target_weights = costs[0].weights
        else:
            raise ValueError(
                "--project needs --project-weights: the first solution's terminal "
                "cost is not a quadratic to copy W from"
            )
        target = Quadratic(_vector(args.project, "--project"), target_weights)
        target = target.with_periods(grid.periods)
        result = projection(target, costs, grid, temperature=solutions[0].temperature)
        weights = result.weights
        print(
            f"projected weights {np.round(weights, 6).tolist()} (sum {result.weight_sum:.4g}, "
            f"residual {result.residual:.3g}, {result.method})"
        )
        for message in result.messages:
            print(f"warning: {message}", file=sys.stderr)
    combined = combine(solutions, weights)
    if weights is None:
        print(f"coordination: weights {combined.weights.tolist()}")
    if args.at:
        states = _states(args.at, grid, "--at")
    elif args.table:
        states = grid.nodes()
    else:
        return 0
    t = args.time
    value = combined.value(states, t)
    policy = combined.policy(states, t)
    alpha = combined.blend_weights(states, t)
    names = [a.name or f"x{k}" for k, a in enumerate(grid.axes)]
    header = (
        names
        + ["value"]
        + [f"u{k}" for k in range(policy.shape[1])]
        + [f"alpha{i}" for i in range(alpha.shape[1])]
    )
    rows = np.column_stack([states, value, policy, alpha])
    if args.table:
        np.savetxt(args.table, rows, delimiter=",", header=",".join(header), comments="")
        print(f"wrote {args.table}: {len(rows)} states at t = {t:g}")
    if args.at:
        print(" ".join(f"{h:>11}" for h in header))
        for row in rows:
            print(" ".join(f"{v:11.5g}" for v in row))
    return 0


def _cmd_certify(args) -> int:
    """The certified optimum from each --state with the saved solution's policy as proposal,
    beside the solution's own prediction v(x₀, 0)."""
    import warnings

    import numpy as np

    from .certify import certify
    from .errors import CertificateWarning
    from .io import load

    solution = load(args.solution)
    grid = solution.grid
    if not args.state:
        raise ValueError("give at least one start state: --state=X1,X2,... (repeatable)")
    states = _states(args.state, grid, "--state")
    if solution.problem.horizon is None and (args.dt is None or args.max_time is None):
        raise ValueError(
            "a first exit without a horizon needs --dt, the Euler–Maruyama step (for the dynamics' "
            "fastest time scale; check it by halving), and --max-time, when paths that have not "
            "reached the exit set are stopped (well beyond the typical time to reach it)"
        )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CertificateWarning)
        cert = certify(
            solution.problem,
            solution.policy,
            states,
            n_samples=args.samples,
            dt=args.dt,
            seed=args.seed,
            progress=None if not args.quiet else False,
            boundary=args.boundary,
            max_time=args.max_time,
            richardson=args.richardson,
        )
    predicted = solution.value(states, 0.0)
    # with --richardson the SDE's optimum (extrapolated), else the chain's at dt
    optimum, optimum_se = (
        np.asarray(value, dtype=float)
        for value in (
            (cert.extrapolated_value, cert.extrapolated_value_se)
            if args.richardson
            else (cert.optimal_value, cert.optimal_value_se)
        )
    )
    print(f"proposal: the policy of {args.solution} ({solution.problem.describe()})")
    print(cert.summary())
    print(
        " ".join(
            f"{h:>12}"
            for h in ("predicted v", "certified v*", "± SE", "error", "policy cost", "gap", "ESS")
        )
    )
    # one row per start state: with (k, d) states every estimate is a (k,) array
    table = np.column_stack(
        [
            predicted,
            optimum,
            optimum_se,
            predicted - optimum,
            cert.policy_cost,
            cert.gap,
            cert.effective_sample_size,
        ]
    )
    for row in table:
        print(" ".join(f"{x:12.5g}" for x in row))
    for w in caught:
        print(f"warning: {w.message}", file=sys.stderr)
    return 0


def _cmd_figures(args) -> int:
    from .studies.figures import make_all

    written = make_all(Path(args.out), quick=args.quick, only=args.only, progress=not args.quiet)
    print(f"wrote {len(written)} files to {args.out}")
    return 0


def _cmd_interactive(args) -> int:
    from .interactive import write_page
    from .io import load

    options = {"dtype": args.dtype, "n_times": args.times}
    if args.max_mb is not None:
        options["max_bytes"] = int(args.max_mb * 1e6)
    if args.nodes is not None:
        nodes = [c.strip() for c in args.nodes.split(",")]
        if not all(c.isdigit() for c in nodes):
            raise ValueError(f"--nodes expects node counts such as 61 or 61,41, got {args.nodes!r}")
        options["nodes"] = [int(c) for c in nodes]
    if args.weights is not None:
        options["weights"] = _vector(args.weights, "--weights")
    if args.state is not None:
        options["state"] = _vector(args.state, "--state")
    if args.solutions:
        report = write_page([load(p) for p in args.solutions], args.out, **options)
    else:
        from .studies.demo import interactive_demo

        if not args.quiet:
            print(
                f"solving the built-in pendulum demo (three goals) on {args.demo_grid} θ nodes ...",
                flush=True,
            )
        report = interactive_demo(args.out, args.demo_grid, progress=not args.quiet, **options)
    print(report.summary())
    return 0


def _add_problem_arguments(parser):
    """The flags that describe a problem and its solver settings (``solve`` and ``sweep``)."""
    parser.add_argument("--config", metavar="TOML", help="problem description file")
    parser.add_argument(
        "--system", help="SingleIntegrator, PointMass, Pendulum, Acrobot or package.module.Class"
    )
    parser.add_argument(
        "--param",
        action="append",
        metavar="KEY=VALUE",
        help="system constructor parameter (repeatable), e.g. damping=0.1",
    )
    parser.add_argument(
        "--grid", metavar="N[,N...]", help="nodes per axis on the system's default box"
    )
    parser.add_argument(
        "--axis",
        action="append",
        metavar="LO,HI,N[,periodic]",
        help="one axis per state coordinate, in order (repeatable)",
    )
    parser.add_argument("--horizon", metavar="T", help="horizon T in seconds")
    parser.add_argument("--temperature", metavar="LAMBDA", help="temperature λ (default 1)")
    parser.add_argument("--control-cost", metavar="R", help="R: a number or one per control")
    for cost, what in (("terminal", "terminal cost g"), ("state", "state cost q")):
        parser.add_argument(
            f"--{cost}-center", metavar="C", help=f"centre c of the {what}, comma-separated"
        )
        parser.add_argument(f"--{cost}-weights", metavar="W", help=f"diagonal of W of the {what}")
    parser.add_argument("--method", help="splitting (default) or implicit")
    parser.add_argument("--dt", type=float, help="time step (default from the Courant number)")
    parser.add_argument("--store-every", type=int, help="keep every k-th time slice")
    parser.add_argument("--dtype", help="float64 (default) or float32 storage")
    parser.add_argument(
        "--fitting",
        choices=["auto", "terminal", "none"],
        help="splitting only: fit the scheme to the terminal cost ('auto', the "
        "default, = 'terminal': far less numerical diffusion where v is steep) "
        "or not ('none': the plain operator, independent of the terminal cost, "
        "so separately solved files combine exactly); see docs/schemes.rst",
    )


def _add_workflow_parsers(sub):
    solve = sub.add_parser(
        "solve",
        help="solve a problem from flags or a TOML file and save the Solution",
        description="Solve the linear Bellman PDE of a problem given by a TOML description "
        "(--config, see gridlbc.config) and/or flags (flags win) and save it with gridlbc.save. "
        "Negative numbers need '=': --axis=-pi,pi,101,periodic; multiples of pi are allowed.",
    )
    _add_problem_arguments(solve)
    solve.add_argument(
        "--tol",
        type=float,
        metavar="TOL",
        help="solve again, refining dt and the grid, until the estimated relative error of v "
        "meets TOL (at the --at states if given, else where it matters); docs/accuracy.rst",
    )
    solve.add_argument(
        "--at",
        action="append",
        metavar="STATE",
        help="print v(x, 0) and its error estimate at this state (comma-separated, "
        "repeatable); with --tol, where the tolerance must hold",
    )
    solve.add_argument(
        "--max-seconds",
        type=float,
        metavar="S",
        help="with --tol: a wall-clock budget; the last round is saved with a warning of the "
        "estimate reached",
    )
    solve.add_argument("--out", required=True, help="where to save the Solution (.npz)")
    solve.add_argument("--quiet", action="store_true", help="no progress output")
    solve.set_defaults(func=_cmd_solve)

    sweep = sub.add_parser(
        "sweep",
        help="solve a grid of problems in parallel on Dask and print their values",
        description="Solve every combination of the swept values (--param-values, "
        "--temperatures, --horizons, --goal) around a base problem given as for solve, in "
        'parallel on Dask distributed (pip install "gridlbc[dask]"): a local cluster of '
        "--workers processes, or the cluster at --scheduler. Each member is saved in --out "
        "under a hash of its problem and settings; a rerun reuses finished members. Prints a "
        "table of v(x, 0) at the --at states; exit status 1 if a member failed.",
    )
    _add_problem_arguments(sweep)
    sweep.add_argument(
        "--param-values",
        action="append",
        metavar="KEY=V1,V2,...",
        help="values of a system parameter (repeatable), e.g. damping=0,0.1,0.2",
    )
    sweep.add_argument("--temperatures", metavar="L1,L2,...", help="temperatures λ")
    sweep.add_argument("--horizons", metavar="T1,T2,...", help="horizons T")
    sweep.add_argument(
        "--goal",
        action="append",
        metavar="C",
        help="a terminal-cost centre (repeatable: one member per goal)",
    )
    sweep.add_argument(
        "--at",
        action="append",
        metavar="STATE",
        help="report v(x, 0) at this state (comma-separated, repeatable)",
    )
    sweep.add_argument("--out", required=True, help="folder for the Solution files")
    sweep.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a Dask scheduler, e.g. tcp://host:8786 (default: a local cluster)",
    )
    sweep.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help="processes of the local cluster (default: the available cores)",
    )
    sweep.add_argument("--quiet", action="store_true", help="no progress output")
    sweep.set_defaults(func=_cmd_sweep)

    combine = sub.add_parser(
        "combine",
        help="combine saved solutions and evaluate value, policy and blend weights",
        description="Linear Bellman combination z = Σ w_i z_i of saved solutions (same problem, "
        "different terminal costs). Weights: all ones (coordination), --weights, or --project "
        "TARGET (the centre of a quadratic target cost; weights from gridlbc.project). States: "
        "--at=-1,0 (repeatable) prints a table; --table PATH writes CSV (all grid nodes "
        "without --at).",
    )
    combine.add_argument("solutions", nargs="+", help="solution files written by gridlbc solve")
    combine.add_argument("--weights", metavar="W1,W2,...", help="fixed weights w_i")
    combine.add_argument("--project", metavar="CENTER", help="target cost centre, e.g. 0.2,0")
    combine.add_argument(
        "--project-weights",
        metavar="W",
        help="diagonal of the target's W (default: the first solution's)",
    )
    combine.add_argument(
        "--at",
        action="append",
        metavar="STATE",
        help="evaluate at this state (comma-separated, repeatable)",
    )
    combine.add_argument("--time", type=float, default=0.0, help="time t (default 0)")
    combine.add_argument("--table", metavar="CSV", help="write the evaluations as CSV")
    combine.set_defaults(func=_cmd_combine)

    certify = sub.add_parser(
        "certify",
        help="the true optimal cost from start states, with a saved solution's policy "
        "as the importance-sampling proposal",
        description="Certify a saved solution: roll out its policy on the problem's SDE and "
        "estimate the true optimal cost v*(x0) = −λ log E[exp(−S/λ)] (Feynman–Kac and Girsanov; "
        "exact for any proposal up to the time step), the policy's own cost and the gap, beside "
        "the solution's prediction v(x0, 0). A small effective sample size (ESS) or a heavy "
        "weight tail (PSIS k̂ > 0.7) means the estimate is not to be trusted (a warning says "
        "what to do). The time step's own bias is read by a run at 4 dt and warned of where it "
        "matters; --richardson extrapolates it away.",
    )
    certify.add_argument("solution", help="a solution file written by gridlbc solve")
    certify.add_argument(
        "--state",
        action="append",
        metavar="X",
        help="start state, comma-separated, multiples of pi allowed "
        "(repeatable; negative numbers need '=': --state=-pi,0)",
    )
    certify.add_argument(
        "--samples", type=int, default=2000, help="samples per start state (default: 2000)"
    )
    certify.add_argument(
        "--dt",
        type=float,
        help="Euler–Maruyama step (default: T/300; required for a first exit without a horizon)",
    )
    certify.add_argument(
        "--max-time",
        type=float,
        metavar="S",
        help="a first exit without a horizon: the paths that have not reached the exit set by "
        "then are stopped and reported (well beyond the typical time to reach it)",
    )
    certify.add_argument("--seed", type=int, help="random seed")
    certify.add_argument(
        "--boundary",
        choices=("free", "reflect"),
        default=None,
        help="closed box edges: 'reflect' folds paths back as the solver's state constraint "
        "does (the default where the grid has a closed axis: the certificate then concerns "
        "the problem the solution solved), 'free' lets them leave the box (the problem on R^d)",
    )
    certify.add_argument(
        "--richardson",
        action="store_true",
        help="also certify at 2 dt and 4 dt and extrapolate the step's O(dt) bias away: the "
        "certified column is then the SDE's optimum, not the chain's at dt (policy cost and gap "
        "stay the chain's)",
    )
    certify.add_argument("--quiet", action="store_true", help="no progress output")
    certify.set_defaults(func=_cmd_certify)

    interactive = sub.add_parser(
        "interactive",
        help="write a self-contained web page that recombines solutions live",
        description="Write one HTML file (nothing loaded from the network) that recombines saved "
        "solutions in the browser: drag weights, pick a goal (weights by projection), click a "
        "state to roll out the combined controller on the value and policy maps. Without files "
        "it solves a built-in pendulum swing-up with three goals on 101² (well under a "
        "minute). Supported: 2-D Pendulum and PointMass solutions. Solutions larger than "
        "--max-mb are decimated (a subset of the stored slices, denser towards T, and a "
        "coarser grid, both evaluated from the solution itself); the page then computes "
        "exactly what gridlbc.combine computes on the decimated solutions, and the output says "
        "how far those are from the originals. PAGE.html?weights=1,0.5&state=2.8,0&time=0 "
        "writes {value, policy, alpha} as JSON into the element #probe (goal=c1,c2 instead of "
        "weights: weights by projection).",
    )
    interactive.add_argument("solutions", nargs="*", help="solution files (gridlbc solve)")
    interactive.add_argument("--out", required=True, help="the page to write (.html)")
    interactive.add_argument(
        "--weights", metavar="W1,W2,...", help="initial weights (default: all ones)"
    )
    interactive.add_argument("--state", metavar="X", help="initial rollout start state")
    interactive.add_argument(
        "--max-mb",
        type=float,
        help="embed the solutions whole up to this many MB of slices, "
        "else decimate to fit (default: 16; the built-in demo: 4)",
    )
    interactive.add_argument(
        "--nodes", metavar="N[,N]", help="decimate to this many nodes per axis"
    )
    interactive.add_argument(
        "--times",
        type=int,
        metavar="K",
        help="decimate to at most K stored time slices, denser towards "
        "T (default 41 when decimating)",
    )
    interactive.add_argument(
        "--dtype",
        choices=["float32", "float64"],
        default="float32",
        help="precision of decimated slices (default float32: half the "
        "bytes; float64 keeps z below 1e-45 of each slice's maximum)",
    )
    interactive.add_argument(
        "--demo-grid",
        type=int,
        default=101,
        help="nodes per axis of the built-in demo's solve (default: 101)",
    )
    interactive.add_argument("--quiet", action="store_true", help="no progress output")
    interactive.set_defaults(func=_cmd_interactive)

    from .studies.figures import FIGURES

    figures = sub.add_parser(
        "figures",
        help="regenerate the figure gallery",
        description="Write every figure of the gallery (gridlbc.studies.figures) to a folder. The full "
        "sizes take several minutes; --quick runs small grids in about a minute.",
    )
    figures.add_argument("--out", default="figures", help="folder (default: figures)")
    figures.add_argument("--quick", action="store_true", help="small grids and sample counts")
    figures.add_argument(
        "--only",
        action="append",
        choices=list(FIGURES),
        metavar="NAME",
        help=f"only this figure (repeatable): {', '.join(FIGURES)}",
    )
    figures.add_argument("--quiet", action="store_true", help="no progress output")
    figures.set_defaults(func=_cmd_figures)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="gridlbc",
        description="Linearly solvable optimal control on grids and linear Bellman combination.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    demo = sub.add_parser(
        "demo",
        help="solve the pendulum swing-up, combine two goals, verify and write figures",
        description="Solve a pendulum swing-up on a grid, combine solutions for two goals, check "
        "superposition, check each predicted cost against the certified optimum (importance "
        "sampling, gridlbc.certify), and write figures.",
    )
    demo.add_argument("--out", default="figures", help="folder for the figures (default: figures)")
    demo.add_argument(
        "--grid", type=int, default=201, help="nodes per axis of the pendulum grid (default: 201)"
    )
    demo.add_argument("--quiet", action="store_true", help="no progress output")
    demo.set_defaults(func=_cmd_demo)

    verify = sub.add_parser(
        "verify",
        help="check superposition, optimality, interpolation and coordination; print a table",
        description="Check the linear Bellman combination claims against exact answers "
        "(direct solves, Riccati, Monte Carlo) and print a table. Exit status 1 if a check fails.",
    )
    verify.add_argument(
        "--grid", type=int, default=256, help="θ nodes of the pendulum swing-up grid (default: 256)"
    )
    verify.add_argument(
        "--samples",
        type=int,
        default=8000,
        help="Monte-Carlo samples of the swing-up (default: 8000)",
    )
    verify.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    verify.add_argument("--json", metavar="PATH", help="also write the results as JSON")
    verify.add_argument(
        "--quick",
        action="store_true",
        help="smoke-test sizes (bounds not expected to hold; use with small --grid and --samples)",
    )
    verify.add_argument("--quiet", action="store_true", help="no progress output")
    verify.add_argument(
        "--convergence",
        action="store_true",
        help="also run the convergence study: both z-space schemes and the "
        "value-space HJB solver under grid refinement (a few minutes)",
    )
    verify.set_defaults(func=_cmd_verify)
    _add_workflow_parsers(sub)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    told = warnings.formatwarning
    warnings.formatwarning = _warning_line
    try:
        return int(args.func(args) or 0)
    except (ValueError, TypeError, FileNotFoundError, MemoryError) as exc:
        print(f"gridlbc {args.command}: error: {exc}", file=sys.stderr)
        return 2
    finally:
        warnings.formatwarning = told


def _warning_line(message, category, filename, lineno, line=None) -> str:
    """A warning as the command line tells it: its kind and its words, without the file and
    line of the code that raised it (the library's own, not the user's)."""
    return f"{category.__name__}: {message}\n"


if __name__ == "__main__":
    sys.exit(main())
