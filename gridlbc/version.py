"""The library's version, recorded in saved solutions and sweep manifests (kept equal to
``pyproject.toml``'s)."""

__version__ = "0.1.0"
