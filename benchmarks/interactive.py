"""How large the interactive page is and how fast it reacts, in headless Chromium.

Writes the built-in page of ``gridlbc interactive`` (pendulum swing-up, three goals, solved on
``--grid`` θ nodes), opens it with ``?bench=N`` (the page recomputes its two 320×240 heat maps
and the rollout N times for new weights and N times for a new time, and writes the medians of
``performance.now()`` intervals into ``#timing``) and prints a table. The baseline, measured in
the same run: ``gridlbc.combine``'s value and policy (numpy, one core) at the same 76 800 states
and the same embedded data.

    python benchmarks/interactive.py [--grid 101] [--repeats 9] [--out /tmp/gridlbc_page.html]
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc.interactive import RASTER
from gridlbc.studies.demo import INTERACTIVE_WEIGHTS, interactive_demo

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def page_timing(page: Path, repeats: int) -> dict:
    with tempfile.TemporaryDirectory() as profile:
        dom = subprocess.run(
            [
                "chromium",
                *FLAGS,
                f"--user-data-dir={profile}",
                "--dump-dom",
                f"{page.resolve().as_uri()}?bench={repeats}",
            ],
            capture_output=True,
            text=True,
            timeout=300,
            check=True,
        ).stdout
    return json.loads(re.search(r'<pre id="timing">([^<]*)</pre>', dom).group(1))


def numpy_baseline(components, repeats: int) -> float:
    """Median seconds of gridlbc.combine's value + policy on the page's raster."""
    grid = components[0].grid
    width, height = RASTER
    x = grid.lo[0] + (np.arange(width) + 0.5) / width * (grid.hi[0] - grid.lo[0])
    y = grid.hi[1] - (np.arange(height) + 0.5) / height * (grid.hi[1] - grid.lo[1])
    X = np.stack(np.meshgrid(x, y), -1).reshape(-1, 2)
    combined = gridlbc.combine(components, INTERACTIVE_WEIGHTS)
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        combined.value(X, 0.0)
        combined.policy(X, 0.0)
        times.append(time.perf_counter() - started)
    return float(np.median(times))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=101, help="θ nodes of the demo's solve")
    parser.add_argument("--repeats", type=int, default=9, help="recomputes timed in the page")
    parser.add_argument("--out", default=str(Path(tempfile.gettempdir()) / "gridlbc_page.html"))
    args = parser.parse_args(argv)
    if shutil.which("chromium") is None:
        raise SystemExit("needs Debian's chromium (apt-get install chromium)")
    report = interactive_demo(args.out, args.grid, progress=False)
    print(report.summary())
    timing = page_timing(report.path, args.repeats)
    baseline = numpy_baseline(report.embedding.components, args.repeats)
    w, t = timing["weights_change_ms"], timing["time_change_ms"]
    weights_row = (
        f"{w['total']:.0f} ms (recombine {w['combine']:.0f}, rollout "
        f"{w['rollout']:.1f}, draw {w['draw']:.0f})"
    )
    rows = [
        ("page size", f"{report.size / 1e6:.2f} MB"),
        ("decode the embedded slices", f"{timing['decode_ms']:.0f} ms"),
        ("first render (fields, maps, rollout)", f"{timing['first_render_ms']:.0f} ms"),
        ("new weights: recombine 2 maps + rollout + draw", weights_row),
        (
            "new time: fields + recombine + rollout + draw",
            f"{t['total']:.0f} ms (fields {t['fields']:.0f})",
        ),
        (
            "baseline: gridlbc.combine value + policy, numpy",
            f"{1e3 * baseline:.0f} ms ({RASTER[0]}×{RASTER[1]} states)",
        ),
    ]
    width = max(len(r[0]) for r in rows)
    for name, value in rows:
        print(f"{name:<{width}}  {value}")


if __name__ == "__main__":
    main()
