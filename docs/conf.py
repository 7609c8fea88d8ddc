"""Sphinx configuration: python -m sphinx -W -b html docs docs/_build/html (nothing fetched).

Formulas are typeset by MathJax 3 in the reader's browser from a copy inside the built site, so
a page opened offline shows them rendered: the copy comes from the PyPI package
``sphinx-mathjax-offline`` (in the docs and test extras), whose files are added to the site's
``_static`` folder below, and the SVG output is chosen because it needs no web fonts.
"""

import importlib.util
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # document this checkout, installed or not
os.environ.setdefault("MPLBACKEND", "Agg")

import gridlbc

project = "gridlbc"
author = "the gridlbc authors"
copyright = "2026, the gridlbc authors"
release = version = gridlbc.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

exclude_patterns = ["_build", "gallery"]
templates_path = []
nitpicky = False
default_role = "py:obj"
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # numpydoc's Parameters sections say the types
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
numpydoc_show_class_members = False  # autodoc lists them once, with their docstrings
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",  # every plot_*.py runs at build time
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "reference_url": {},  # no links resolved over the network
    "show_memory": False,
    "capture_repr": (),  # print() is what a page shows, not the last expression's repr
    "matplotlib_animations": False,
}

html_theme = "pydata_sphinx_theme"
html_title = "gridlbc"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
}


def _bundled_mathjax() -> str:
    """The folder holding ``mathjax/`` in the sphinx-mathjax-offline package (MathJax 3.2)."""
    spec = importlib.util.find_spec("sphinx-mathjax-offline")
    if spec is None or spec.origin is None:
        raise RuntimeError(
            'the docs need a local MathJax: pip install ".[docs]" (sphinx-mathjax-offline)'
        )
    static = Path(spec.origin).parent / "static"
    if not (static / "mathjax" / "tex-svg.js").is_file():
        raise RuntimeError(
            f"no mathjax/tex-svg.js under {static}: reinstall sphinx-mathjax-offline"
        )
    return str(static)


# Copied into _static/ at build time; mathjax_path is relative to _static/.
html_static_path = [_bundled_mathjax()]
mathjax_path = "mathjax/tex-svg.js"
html_show_sourcelink = False
# No left sidebar: the pages are few (all in the header), and wide formulas get the room.
html_sidebars = {"**": []}
