"""Recheck of the Crank–Nicolson truths of stranger rounds 21–24 with a monotone scheme.

RESULTS (2026-12-06, one thread, ``--run`` then ``--table``; about 20 minutes; stored solves of
each round's results folder, read only): 173 entries, 644 (problem, state, t) pairs rechecked —
round 21: 20 entries / 60 pairs ("1-D"); round 22: 50 / 172 (46 "1-D", 4 "cn" strips with an
exit and a horizon); round 23: 61 / 244 (``rot1d`` and ``sep_truth``); round 24: 42 / 168
("1-D", ``sep_truth``); round 21t: none (certified truths). Largest cell Péclet number 0.157
(monotone everywhere); largest Richardson step correction 1.55 % of max(|v*|, λ), node ± ≤ 1.6 %.

- Truths moved by > 1 %: ONE pair, also > 5 %: round 24 ``ledger3_cold`` (−4, 950, 0.05), t = 0,
  λ = 0.03: Crank–Nicolson 33.722 (its 8001-node value 16.765, ± 16.96: ringing), backward Euler
  19.993 (± 0.004 nodes, 0.007 step; z/max ≥ 1e-110 there, no underflow), the library's solve
  20.050, ê 0.326: error −40.5 % (under-read) → +0.29 % (covered). Round 24 had flagged it
  UNTRUSTED as an underflow ("cn1d's clamp"); it was CN's ringing, and it is now a trusted pair:
  round 24's counts become 564 trusted pairs, ê ≥ ½|err| at 555 / 564, none silent, the one
  under-read unchanged (flat_hot_at1.95).
- Every other pair moved by < 0.01 % (rounds 21–23: max 0.00 %; round 24 0.01 %): no verdict
  (> 10 %, silent, covered, under-read, false-alarm entry) changes in rounds 21, 22, 23, or at any
  other pair of round 24. The "none is silent" of rounds 22–24 in docs/benchmarks.rst holds.
- Still unresolvable by z in double precision: flat_cold (−1.9, 1.9) at t = 1.8 and 1.95
  (λ = 0.01, z/max at the 1e-300 clamp in BE as in CN: v* = λ·690.8 per axis), already UNTRUSTED
  in round 24; flat_cold_at1.95 (1.25, −1.25) has z/max ≈ 1e-258 (representable; BE and CN
  agree to 0.01 %: +134 %, warned, covered, as recorded).

Why: round 25 found that round 21's ``cn1d`` (Crank–Nicolson after four backward-Euler half
steps, z renormalised each step) rings to negative z at small λ, where z spans hundreds of
orders over the box; the log then clamps to λ·690 and v* comes out 2–4× too high. Rounds 21–24
took their separable truths ("1-D" in rounds 21–24, "cn" in round 22) from that scheme.

What: every (problem, state, t) pair of rounds 21, 22, 23 and 24 whose stored truth came from
Crank–Nicolson (round 21's ``cn1d`` through ``one_d``, round 22's ``sep_truth`` and
``exit_cn1d``, round 23's ``rot1d`` and its uses of ``sep_truth``, round 24's
``sep_specs_truth``) is recomputed with the same truth function of its round, the same 1-D
setup (box, coefficients, 8001 / 16001 nodes, the node difference as ±) but each 1-D solve by
backward Euler (fully implicit, z renormalised by its max each step, z held at e^{−g_E/λ − log s}
on an exit set) with Richardson in the step: 2·BE(Δt/2) − BE(Δt), Δt = τ/steps of the original.
Backward Euler with central differences is monotone while the cell Péclet number |a|h/(2D) ≤ 1
(recorded; the largest over all rechecked axes is printed). A state whose z falls below 1e-250
of its max is flagged (underflow: v is then the clamp, not a value). Round 21t (tol runs) uses
the certified corpus truths (``truths.json``), no Crank–Nicolson: nothing to recheck.

Nonperiodic axes march with a Thomas solve in numba (the factorisation of the M-matrix I − ΔtL
reused; every substitution adds terms of one sign, so tiny z keep their relative precision);
periodic axes with SuperLU.

Verdicts as round 20's ``table`` (which rounds 21–24 use): error (v − v*)/max(|v*|, λ), silent
= |err| > 10 % with no GridlbcWarning, covered = ê ≥ ½|v − v*|, under-read = |err| > 2 % and not
covered, false alarm (per entry) = warned with every pair < 3 %.

    cd /work/wt-cn && PYTHONPATH=/work/wt-cn NUMBA_NUM_THREADS=1 \\
        python benchmarks/holdout/recheck_cn_truths.py --run [ROUND ...] | --table [--all]
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numba import njit

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import strangers_round20 as r20  # noqa: E402
import strangers_round21 as r21  # noqa: E402
import strangers_round22 as r22  # noqa: E402
import strangers_round23 as r23  # noqa: E402
import strangers_round24 as r24  # noqa: E402

OUT = HERE / "strangers_roundcn_results"  # gitignored (strangers_round*_results/)
STORED = {
    21: Path("/work/main/benchmarks/holdout/strangers_round21_results"),
    22: Path("/work/main/benchmarks/holdout/strangers_round22_results"),
    23: Path("/work/main/benchmarks/holdout/strangers_round23_results"),
    24: Path("/work/main/benchmarks/holdout/strangers_round24_results"),
}
TABLES = {21: r21.P21, 22: r22.P22, 23: r23.P23, 24: r24.P24}
CN_TAGS = ("1-D", "cn")  # every Crank–Nicolson truth of rounds 21–24 (round 24's "1-Dt" is BE)
UNDER = -250.0  # log10 z/max below this: flagged (near underflow)
CLAMP = -299.0  # at the 1e-300 clamp: v is λ·690.8 per axis, not a value


# ---------------- backward Euler ---------------------------------------------------------------
@njit(cache=True)
def _march(sub, diag, sup, z, steps, fixed, gl, logs):
    """``steps`` BE steps of the tridiagonal system (sub, diag, sup) = I − ΔtL (rows of
    ``fixed`` the identity, their value e^{−gl − logs}); z renormalised by its max each step."""
    n = len(z)
    cp = np.empty(n)
    den = np.empty(n)
    den[0] = diag[0]
    cp[0] = sup[0] / den[0]
    for i in range(1, n):
        den[i] = diag[i] - sub[i] * cp[i - 1]
        cp[i] = sup[i] / den[i] if i < n - 1 else 0.0
    d = np.empty(n)
    for _ in range(steps):
        for i in range(n):
            if fixed[i]:
                z[i] = math.exp(-gl[i] - logs)
        d[0] = z[0] / den[0]
        for i in range(1, n):
            d[i] = (z[i] - sub[i] * d[i - 1]) / den[i]
        z[n - 1] = d[n - 1]
        for i in range(n - 2, -1, -1):
            z[i] = d[i] - cp[i] * z[i + 1]
        m = 0.0
        for i in range(n):
            if z[i] > m:
                m = z[i]
        for i in range(n):
            z[i] /= m
        logs += math.log(m)
    return logs


def _be(x, h, a, D, q, lam, g, tau, steps, periodic, fixed=None, gfix=None):
    """v on the nodes after ``steps`` BE steps over τ, and log10 z/max (underflow flag)."""
    n = len(x)
    main = -2 * D / h**2 - q / lam
    up = D / h**2 + a / (2 * h)
    dn = D / h**2 - a / (2 * h)
    if fixed is None:
        fixed = np.zeros(n, bool)
        gfix = np.zeros(n)
    g = np.where(fixed, gfix, g)
    shift = g.min()
    z, logs = np.exp(-(g - shift) / lam), -shift / lam
    gl = (gfix - 0 * x) / lam
    dt = tau / steps
    if periodic:
        L = r21._operator(x, h, a, D, q, lam, True)
        A = spla.splu((sp.identity(n, format="csc") - dt * L).tocsc())
        for _ in range(steps):
            z = A.solve(z)
            m = z.max()
            z, logs = z / m, logs + math.log(m)
    else:
        sub = np.zeros(n)
        sup = np.zeros(n)
        diag = 1 - dt * main
        sub[1:] = -dt * dn[1:]
        sup[:-1] = -dt * up[:-1]
        sup[0] = -dt * (up[0] + dn[0])  # ghost z_{-1} = z_1: reflecting wall
        sub[-1] = -dt * (up[-1] + dn[-1])
        diag = np.where(fixed, 1.0, diag)
        sub = np.where(fixed, 0.0, sub)
        sup = np.where(fixed, 0.0, sup)
        z = np.where(fixed, np.exp(-gl - logs), z)
        logs = _march(sub, diag, sup, z, steps, fixed, gl, logs)
    lz = np.log(np.maximum(z, 1e-300))
    return -lam * (lz + logs), lz / math.log(10)


CACHE = {}  # identical 1-D solves (same axis, horizon, nodes) recur across entries


def _key(*parts):
    h = hashlib.sha1()
    for p in parts:
        h.update(
            np.ascontiguousarray(p).tobytes() if isinstance(p, np.ndarray) else repr(p).encode()
        )
    return h.hexdigest()


LOG = []  # per 1-D solve: (n, interpolants of v_be(Δt), v_be(Δt/2), log10 z); read by truth()
PECLET = [0.0]


def _record(x, lo, hi, periodic, n, v1, v2, lz):
    if periodic:
        xx, P = np.append(x, hi), hi - lo

        def at(v):
            vv = np.append(v, v[0])
            return lambda y: np.interp(lo + np.mod(np.asarray(y) - lo, P), xx, vv)
    else:

        def at(v):
            return lambda y: np.interp(np.asarray(y), x, v)

    f1, f2, fz = at(v1), at(v2), at(lz)

    def value(y):
        LOG.append((n, f1(y), f2(y), fz(y)))
        return 2 * f2(y) - f1(y)

    return value


def be_cn1d(lo, hi, tau, lam, a, D, q, g, periodic=False, n=8001, steps=4000):
    """Drop-in for round 21's ``cn1d``: backward Euler, Richardson over ``steps`` and 2·steps."""
    if periodic:
        x = lo + (hi - lo) * np.arange(n) / n
        h = (hi - lo) / n
    else:
        x = np.linspace(lo, hi, n)
        h = x[1] - x[0]
    av, Dv, qv = (np.broadcast_to(np.asarray(f(x), float), x.shape).copy() for f in (a, D, q))
    gv = np.asarray(g(x), float) + 0 * x
    with np.errstate(divide="ignore", invalid="ignore"):
        PECLET[0] = max(PECLET[0], float(np.nanmax(np.abs(av) * h / (2 * Dv))))
    if tau <= 0:
        return _record(x, lo, hi, periodic, n, gv, gv, 0 * x)
    key = _key(lo, hi, tau, lam, periodic, n, steps, av, Dv, qv, gv)
    if key not in CACHE:
        v1, _ = _be(x, h, av, Dv, qv, lam, gv, tau, steps, periodic)
        v2, lz = _be(x, h, av, Dv, qv, lam, gv, tau, 2 * steps, periodic)
        CACHE[key] = (v1, v2, lz)
    return _record(x, lo, hi, periodic, n, *CACHE[key])


def be_exit_cn1d(lo, hi, tau, lam, q, g, exit_mask, exit_cost, n, steps):
    """Drop-in for round 22's ``exit_cn1d`` (D = λ/2, no drift, z held on E): BE, Richardson."""
    x = np.linspace(lo, hi, n)
    h = x[1] - x[0]
    qv = np.asarray(q(x), float) + 0 * x
    E = np.asarray(exit_mask(x), bool)
    gE = np.asarray(exit_cost(x), float) + 0 * x
    gv = np.asarray(g(x), float) + 0 * x
    Dv, av = lam / 2 + 0 * x, 0 * x
    if tau <= 0:
        gg = np.where(E, gE, gv)
        return _record(x, lo, hi, False, n, gg, gg, 0 * x)
    key = _key(lo, hi, tau, lam, "exit", n, steps, qv, gv, E, gE)
    if key not in CACHE:
        v1, _ = _be(x, h, av, Dv, qv, lam, gv, tau, steps, False, E, gE)
        v2, lz = _be(x, h, av, Dv, qv, lam, gv, tau, 2 * steps, False, E, gE)
        CACHE[key] = (v1, v2, lz)
    return _record(x, lo, hi, False, n, *CACHE[key])


def patch():
    for mod in (r21, r22, r23):
        mod.cn1d = be_cn1d
    r22.exit_cn1d = be_exit_cn1d


# ---------------- run --------------------------------------------------------------------------
def entries(rounds):
    for rd in rounds:
        for name, (build, X, truth, tag, t) in TABLES[rd].items():
            if tag not in CN_TAGS:
                continue
            if not (STORED[rd] / f"{name}_truth.json").exists():
                continue
            yield rd, name, build, np.asarray(X, float), truth, tag, t


def run(rounds):
    patch()
    OUT.mkdir(exist_ok=True)
    for rd, name, _build, X, truth, tag, t in entries(rounds):
        f = OUT / f"r{rd}_{name}.json"
        if f.exists():
            continue
        start = time.perf_counter()
        LOG.clear()
        PECLET[0] = 0.0
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            vs, unc, _extra = truth(X)
        # the 16001-node solves: step correction Σ|BE(Δt/2) − BE(Δt)| and the smallest log10 z
        nmax = max(r[0] for r in LOG)
        fine = [r for r in LOG if r[0] == nmax]
        corr = np.sum([np.abs(r[2] - r[1]) for r in fine], axis=0)
        lz = np.min([r[3] for r in fine], axis=0)
        out = dict(
            round=rd,
            name=name,
            tag=tag,
            t=t,
            X=X.tolist(),
            vstar=np.asarray(vs, float).tolist(),
            unc_nodes=np.asarray(unc, float).tolist(),
            step_corr=np.asarray(corr, float).reshape(-1).tolist(),
            log10z_min=np.asarray(lz, float).reshape(-1).tolist(),
            peclet=PECLET[0],
            seconds=time.perf_counter() - start,
        )
        f.write_text(json.dumps(out))
        print(f"r{rd} {name:30s} {out['seconds']:6.1f} s  Pe {PECLET[0]:.3f}", flush=True)


# ---------------- table ------------------------------------------------------------------------
def verdicts(v, vs, e, sc, warned):
    err = (v - vs) / sc
    cov = e is not None and e >= 0.5 * abs(v - vs)
    return dict(
        err=err,
        off10=abs(err) > 0.10,
        silent=abs(err) > 0.10 and not warned,
        covered=bool(cov),
        under=abs(err) > 0.02 and not cov,
    )


def table(show_all):
    lams = {}
    rows, per_entry = [], {}
    for rd, name, build, X, _truth, _tag, t in entries(TABLES):
        f = OUT / f"r{rd}_{name}.json"
        if not f.exists():
            continue
        new = json.loads(f.read_text())
        old = json.loads((STORED[rd] / f"{name}_truth.json").read_text())
        fs = STORED[rd] / f"{name}_solve.json"
        if not fs.exists():
            continue
        sol = json.loads(fs.read_text())
        if build not in lams:
            lams[build] = r20._lam(build)
        lam = lams[build]
        for i in range(len(X)):
            v, e = sol["v"][i], (sol.get("est") or [None] * len(X))[i]
            vo, vn = old["vstar"][i], new["vstar"][i]
            a = verdicts(v, vo, e, max(abs(vo), lam), sol["warned"])
            b = verdicts(v, vn, e, max(abs(vn), lam), sol["warned"])
            rows.append(
                dict(
                    rd=rd,
                    name=name,
                    i=i,
                    x=X[i],
                    t=t,
                    lam=lam,
                    v=v,
                    e=e,
                    vo=vo,
                    vn=vn,
                    move=(vn - vo) / max(abs(vn), lam),
                    corr=new["step_corr"][i] / max(abs(vn), lam),
                    unc=new["unc_nodes"][i] / max(abs(vn), lam),
                    lz=new["log10z_min"][i],
                    warned=sol["warned"],
                    a=a,
                    b=b,
                    pe=new["peclet"],
                    untrusted=rd == 24 and (name, i) in r24.UNTRUSTED,
                )
            )
            per_entry.setdefault((rd, name), []).append(
                (sol["warned"], abs(a["err"]), abs(b["err"]))
            )
    print(
        f"{'rd':>2s} {'problem':28s} {'state':26s} {'t':>5s} {'λ':>6s} {'v* old':>10s} {'v* new':>10s}"
        f" {'move':>7s} {'±step':>6s} {'±node':>6s} {'v':>10s} {'ê':>9s} {'err old':>8s}"
        f" {'err new':>8s} w  verdict old → new"
    )

    def tagv(d):
        return ("S" if d["silent"] else ("X" if d["off10"] else "-")) + (
            "c" if d["covered"] else ("U" if d["under"] else "u")
        )

    changed = []
    for r in rows:
        a, b = r["a"], r["b"]
        ch = any(a[k] != b[k] for k in ("off10", "silent", "covered", "under"))
        if ch:
            changed.append(r)
        if show_all or ch or abs(r["move"]) > 0.01 or r["lz"] < UNDER:
            e = r["e"] if r["e"] is not None else float("nan")
            print(
                f"{r['rd']:2d} {r['name']:28s} {np.round(r['x'], 3).tolist()!s:26s} {r['t']:5.2f}"
                f" {r['lam']:6.3g} {r['vo']:10.4f} {r['vn']:10.4f} {100 * r['move']:+6.2f}%"
                f" {100 * r['corr']:5.2f}% {100 * r['unc']:5.2f}% {r['v']:10.4f} {e:9.4f}"
                f" {100 * a['err']:+7.2f}% {100 * b['err']:+7.2f}% {'Y' if r['warned'] else 'n'}"
                f"  {tagv(a)} → {tagv(b)}{'  CHANGED' if ch else ''}"
                f"{'  (log10 z/max ' + format(r['lz'], '.0f') + ')' if r['lz'] < UNDER else ''}"
                f"{': clamped, no value' if r['lz'] <= CLAMP else ''}"
                f"{'  (untrusted in round 24)' if r['untrusted'] else ''}"
            )
    print("\nverdict codes: S silent (>10 %, no warning), X >10 % warned, - ≤10 %; c covered,")
    print("U under-read (>2 %, ê < ½err), u not covered but ≤ 2 %\n")
    for rd in sorted(TABLES):
        rr = [r for r in rows if r["rd"] == rd]
        if not rr:
            print(f"round {rd}: no Crank–Nicolson truth rechecked")
            continue
        mv = np.array([abs(r["move"]) for r in rr])
        ok = [r for r in rr if r["lz"] >= UNDER]
        ut = sum(r["untrusted"] for r in rr)
        print(
            f"round {rd}: {len({r['name'] for r in rr})} entries, {len(rr)} pairs;"
            f" moved > 1 %: {int((mv > 0.01).sum())}, > 5 %: {int((mv > 0.05).sum())}"
            f" (max {100 * mv.max():.2f} %); z < 1e-250 {len(rr) - len(ok)}, clamped {sum(r['lz'] <= CLAMP for r in rr)}"
            f" (round 24's UNTRUSTED: {ut});"
            f" silent {sum(r['a']['silent'] for r in rr)} → {sum(r['b']['silent'] for r in rr)},"
            f" >10 % {sum(r['a']['off10'] for r in rr)} → {sum(r['b']['off10'] for r in rr)},"
            f" covered {sum(r['a']['covered'] for r in rr)} → {sum(r['b']['covered'] for r in rr)},"
            f" under-reads {sum(r['a']['under'] for r in rr)} → {sum(r['b']['under'] for r in rr)};"
            f" verdicts changed at {sum(r in changed for r in rr)} pairs;"
            f" max step corr {100 * max(r['corr'] for r in rr):.2f} %,"
            f" max node ± {100 * max(r['unc'] for r in rr):.2f} %, max Péclet"
            f" {max(r['pe'] for r in rr):.3f}"
        )
    fa = [
        (
            k,
            sum(1 for w, _, _ in v if w) > 0 and max(x for _, x, _ in v) < 0.03,
            sum(1 for w, _, _ in v if w) > 0 and max(y for _, _, y in v) < 0.03,
        )
        for k, v in per_entry.items()
    ]
    print("false-alarm status changed:", [(k, a, b) for k, a, b in fa if a != b] or "none")


def main(argv):
    if "--table" in argv:
        table("--all" in argv)
        return
    if "--run" in argv:
        rounds = [int(a) for a in argv if a.isdigit()] or sorted(TABLES)
        run(rounds)


if __name__ == "__main__":
    main(sys.argv[1:])
