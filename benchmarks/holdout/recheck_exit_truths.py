"""Recheck of the hold-out corpus's first-exit truths after the bridge's depth was unbounded.

RESULTS (2026-12-07, one thread, library at e72b907 (after 68d78fd), ``--run`` then ``--run
dock hot_band --levels 6`` then ``--table``; about 3 minutes in all): NO first-exit truth moved.

- 13 members have an exit set; 8 carry an ``exact`` function (no certificate, unaffected:
  notch_exit, toll_blind, notch_exit_horizon, tiny_ball_cold, two_doors, three_doors,
  cold_flow_exit, exit_strip_between). 5 are certified, 17 states, all rechecked, none skipped
  (≤ 31 s a member): two with a shaped exit set (hot_band: Box |θ| < 0.5, a slab; dock: Ball
  radius 0.1 in (x, v)), three with a callable one (exit_late, exit_late_cold, cart_exit_late:
  no bridge, the control).
- Every member picked the stored proposal and sample count (n 1000).
- dock (PointMass, λ = 0.05, noise on v only): z = −0.2, +0.1, +0.4 (−0.02 %, +0.01 %,
  +0.03 %); at the old depth z = −0.3, −0.2, +0.3. The bridge's own effect (same seed, depth 30
  against 6) is +0.0001, +0.0007, +0.0001 (≤ 0.03 %, within a SE): a step's velocity noise,
  √(λΔt) = 0.01 at Δt = 0.002, is a tenth of the ball's radius, so six halvings already sufficed.
- hot_band: the same value to 1e-13 at either depth (the slab's faces are planes: no halving).
- exit_late, exit_late_cold, cart_exit_late: bit for bit the stored values.
- No truth moved by 3 combined SE (largest |z| 0.4); truths.json needs no change for the bridge.
- Rerun after a step's straight segment was tested against the shapes too (the next session,
  ``--run dock hot_band``): the same values to the last digit printed (dock z −0.2, +0.1, +0.4;
  hot_band identical): no path of theirs crosses a part of E within a step unseen.

Why: the certificate stops a path between two Euler–Maruyama steps with a Brownian-bridge
crossing probability when the exit set is a shape of :mod:`gridlbc.regions`. Until main commit
68d78fd that rule halved a step at most 6 times (``BRIDGE_LEVELS = 6``); on a boundary curved on
the scale of a step's noise (small balls, corners, noise on one axis only) it over-counted
crossings and certified v* too low. It now halves until a crossing is implausible (the guard
``BRIDGE_LEVELS = 30``). The stored truths (``truths.json``) were certified with the old rule.

What: every member of ``corpus.py`` whose problem has an exit set (with or without a horizon).
Members with an ``exact`` function carry no certificate (unaffected, listed only). Each certified
member is re-certified by ``truths.truth`` itself (the same proposals, pilot choice, sample count,
steps ``cert_dt`` and ``cert_dt/2``, seed 25 and the defaults of ``truths.py``), with the current
library; nothing is written to ``truths.json``. The exit sets that are not shapes (callables:
no bridge) are rechecked as a control. A truth that moved by more than 3 combined SE,
z = (new − old)/√(se_new² + se_old²), is certified once more at the old depth
(``sys.modules["gridlbc.simulate"].BRIDGE_LEVELS = 6``), which should give the stored value back
within noise if the bridge is what moved it.

    cd /work/wt-rt && PYTHONPATH=/work/wt-rt NUMBA_NUM_THREADS=1 \\
        python benchmarks/holdout/recheck_exit_truths.py --list
    ... recheck_exit_truths.py --run [NAME ...] [--levels 6]   # one record per (member, levels)
    ... recheck_exit_truths.py --table
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import truths as T  # noqa: E402
from corpus import BY_NAME, MEMBERS  # noqa: E402

from gridlbc.regions import has_geometry  # noqa: E402

OUT = HERE / "strangers_roundexit_results" / "recheck.json"  # gitignored
STORED = json.loads((HERE / "truths.json").read_text())["members"]


def exit_members():
    """[(member, shape or None, certified?)] for every member whose problem has an exit set."""
    rows = []
    for m in MEMBERS:
        p = m.certified_problem()
        if p.exit is None:
            continue
        shape = repr(p.exit) if has_geometry(p.exit) else None
        rows.append((m, shape, m.exact is None))
    return rows


def run(names, levels):
    """Re-certify ``names`` as ``truths.py --only`` does, the bridge at ``levels`` (None: the
    library's)."""
    S = sys.modules["gridlbc.simulate"]  # gridlbc.simulate the attribute is the function
    default = S.BRIDGE_LEVELS
    data = json.loads(OUT.read_text()) if OUT.exists() else {}
    for name in names:
        member = BY_NAME[name]
        S.BRIDGE_LEVELS = default if levels is None else levels
        try:
            start = time.perf_counter()
            record = T.truth(member, 400, 0.005, 1000, 6000, 25)
        finally:
            S.BRIDGE_LEVELS = default
        record["levels"] = default if levels is None else levels
        key = f"{name}@{record['levels']}"
        data[key] = record
        OUT.parent.mkdir(exist_ok=True)
        OUT.write_text(json.dumps(data, indent=1) + "\n")
        print(f"{key}: {record['proposal']}, n {record['n_samples']}, "
              f"{time.perf_counter() - start:.0f} s", flush=True)  # fmt: skip


def table():
    data = json.loads(OUT.read_text())
    default = sys.modules["gridlbc.simulate"].BRIDGE_LEVELS
    print(
        "member | state | stored v ± se (bias) | new v ± se (ESS) | z | rel | old-depth v ± se, z"
    )
    for key, rec in data.items():
        name, levels = key.rsplit("@", 1)
        if int(levels) != default:
            continue
        old = STORED[name]
        check = data.get(f"{name}@6")
        same = rec["proposal"] == old["proposal"] and rec["n_samples"] == old["n_samples"]
        print(f"{name}: {rec['proposal']} n {rec['n_samples']}"
              f"{'' if same else ' (stored: ' + old['proposal'] + ' n ' + str(old['n_samples']) + ')'}")  # fmt: skip
        for i, (s, o) in enumerate(zip(rec["states"], old["states"])):
            z = (s["v"] - o["v"]) / math.hypot(s["se"], o["se"])
            line = (
                f"  {tuple(round(c, 3) for c in o['x'])} | {o['v']:.4f} ± {o['se']:.4f} "
                f"({100 * o['step_bias']:+.2f} %) | {s['v']:.4f} ± {s['se']:.4f} "
                f"({s['ess']:.0f}) | {z:+.1f} | {100 * (s['v'] - o['v']) / abs(o['v']):+.2f} %"
            )
            if check is not None:
                c = check["states"][i]
                zc = (c["v"] - o["v"]) / math.hypot(c["se"], o["se"])
                line += f" | {c['v']:.4f} ± {c['se']:.4f}, {zc:+.1f}"
            print(line)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--run", nargs="*")
    parser.add_argument("--levels", type=int, default=None)
    parser.add_argument("--table", action="store_true")
    args = parser.parse_args(argv)
    if args.list:
        for m, shape, certified in exit_members():
            how = "certified" if certified else "exact (no certificate)"
            print(f"{m.name}: {shape or 'callable (no bridge)'}; {how}; {len(m.states)} states")
    if args.run is not None:
        names = args.run or [m.name for m, _, certified in exit_members() if certified]
        run(names, args.levels)
    if args.table:
        table()
    return 0


if __name__ == "__main__":
    sys.exit(main())
