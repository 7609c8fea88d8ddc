"""The documentation cannot rot: every public name has an API entry, and the site builds with
warnings as errors (examples executed)."""

import importlib
import importlib.util
import re
import subprocess
import sys
import zlib
from pathlib import Path

import pytest

import gridlbc

DOCS = Path(__file__).resolve().parents[2] / "docs"
# Subpackages whose public names are documented beside gridlbc.__all__, when they exist.
SUBPACKAGES = ("systems", "costs", "reference", "trajectory")
DIRECTIVE = re.compile(r"^\.\.\s+(?:auto\w+|py:\w+)::\s+([\w.]+)", re.MULTILINE)


def public_names() -> set[str]:
    """Dotted names of gridlbc.__all__ and of each subpackage's __all__ (a module without one
    needs its own entry)."""
    names = set()
    modules = {
        n
        for n in gridlbc.__all__
        if hasattr(getattr(gridlbc, n), "__path__")
        or type(getattr(gridlbc, n)).__name__ == "module"
    }
    for name in gridlbc.__all__:
        names.add(f"gridlbc.{name}")
    for sub in set(SUBPACKAGES) | modules:
        if importlib.util.find_spec(f"gridlbc.{sub}") is None:
            continue
        module = importlib.import_module(f"gridlbc.{sub}")
        names.add(f"gridlbc.{sub}")
        names.update(f"gridlbc.{sub}.{n}" for n in getattr(module, "__all__", ()))
    return names


def documented_names() -> set[str]:
    found = set()
    for page in DOCS.glob("*.rst"):
        found.update(DIRECTIVE.findall(page.read_text(encoding="utf-8")))
    return found


def _aliases(name: str) -> set[str]:
    """A subpackage name re-exported at the top level (gridlbc.costs.Quadratic is
    gridlbc.Quadratic) counts as documented by the top-level entry."""
    module, _, attr = name.rpartition(".")
    obj = getattr(importlib.import_module(module), attr, None) if module != "gridlbc" else None
    return {
        f"gridlbc.{top}"
        for top in gridlbc.__all__
        if obj is not None and getattr(gridlbc, top) is obj
    }


def test_every_public_name_has_an_api_entry():
    documented = documented_names()
    missing = sorted(
        n for n in public_names() if n not in documented and not (_aliases(n) & documented)
    )
    assert not missing, f"add these to docs/api.rst: {missing}"


def test_api_entries_name_existing_objects():
    # The reverse: an entry for a renamed or removed name would fail the build (autodoc warns
    # under -W), but say which one here, quickly.
    stale = []
    for name in documented_names():
        module, _, attr = name.rpartition(".")
        try:
            obj = importlib.import_module(name)
        except ImportError:
            try:
                obj = getattr(importlib.import_module(module), attr)
            except (ImportError, AttributeError):
                obj = None
        if obj is None:
            stale.append(name)
    assert not stale, f"docs/api.rst names objects that do not exist: {stale}"


def _inventory(path: Path) -> set[str]:
    """Object names in a Sphinx objects.inv (four header lines, then zlib-compressed text)."""
    raw = path.read_bytes()
    body = zlib.decompress(raw.split(b"\n", 4)[4]).decode()
    return {line.split(" ", 1)[0] for line in body.splitlines() if line}


def test_docs_build_with_warnings_as_errors(tmp_path):
    pytest.importorskip("sphinx", reason='the docs build needs pip install ".[docs]"')
    for module in ("numpydoc", "sphinx_gallery", "pydata_sphinx_theme", "gymnasium"):
        pytest.importorskip(module, reason=f'the docs build needs {module}: pip install ".[docs]"')
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "sphinx",
            "-W",
            "--keep-going",
            "-q",
            "-b",
            "html",
            "-d",
            str(tmp_path / "doctrees"),
            str(DOCS),
            str(tmp_path / "html"),
        ],
        capture_output=True,
        text=True,
        timeout=900,
        check=False,
    )
    assert result.returncode == 0, (result.stdout + result.stderr)[-4000:]
    inventory = _inventory(tmp_path / "html" / "objects.inv")
    missing = sorted(
        n for n in public_names() if n not in inventory and not (_aliases(n) & inventory)
    )
    assert not missing, f"built without an entry for {missing}"
    gallery = tmp_path / "html" / "auto_examples"
    assert sorted(p.stem for p in gallery.glob("plot_*.html")) == sorted(
        p.stem for p in (DOCS / "gallery").glob("plot_*.py")
    )
