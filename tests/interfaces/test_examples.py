"""Every script in examples/ runs (small sizes), so the tutorial and the docs that name them
never point at a broken script."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SLOW = {"gymnast", "interpolation"}  # cold numba cache / many rollouts: over ~20 s
NEEDS = {"gym_pendulum": "gymnasium"}  # optional extras an example imports
MISSING = {name for name, module in NEEDS.items() if importlib.util.find_spec(module) is None}


def _marks(name):
    marks = [pytest.mark.slow] if name in SLOW else []
    if name in MISSING:
        marks.append(
            pytest.mark.skip(reason=f"needs {NEEDS[name]} (pip install '.[{NEEDS[name]}]')")
        )
    return marks


@pytest.mark.parametrize(
    "name", [pytest.param(p.stem, marks=_marks(p.stem)) for p in sorted(EXAMPLES.glob("*.py"))]
)
def test_example_runs(tmp_path, name):
    args = [sys.executable, str(EXAMPLES / f"{name}.py"), "--quick"]
    if name != "tutorial":
        args += ["--out", str(tmp_path)]
    result = subprocess.run(
        args, capture_output=True, text=True, timeout=900, cwd=tmp_path, check=False
    )
    assert result.returncode == 0, result.stderr[-2000:]
    if name == "tutorial":
        assert "α(x0) =" in result.stdout
    else:
        written = [p for p in tmp_path.iterdir() if p.suffix in (".png", ".gif")]
        assert written and all(p.stat().st_size > 1000 for p in written)
