"""The warnings gridlbc issues, under one base class.

Every warning the library raises about its own results derives from :class:`GridlbcWarning`, so a
user (or a test suite) can silence, log or turn into errors all of them at once::

    warnings.simplefilter("error", gridlbc.GridlbcWarning)

Each message says what limits the result and what to change (docs page ``limitations``).
"""

from __future__ import annotations


class GridlbcWarning(UserWarning):
    """Base class of the warnings about gridlbc's own results."""


class ResolutionWarning(GridlbcWarning, RuntimeWarning):
    """The grid and scheme cannot resolve the solution (its values are not to be trusted there);
    the message says what limits it and what to change."""


class UnderflowWarning(GridlbcWarning, RuntimeWarning):
    """Desirability underflowed to zero at some query states: value +inf, policy undefined (NaN).
    Also where a first exit's exit set cannot be reached at all, and z is zero exactly."""


class CertificateWarning(GridlbcWarning):
    """The certified optimum rests on too few effective samples to be trusted."""


class ProjectionWarning(GridlbcWarning):
    """The component costs represent the target poorly (paper Fig. 4)."""


class TrajectoryWarning(GridlbcWarning, RuntimeWarning):
    """An expansion was built around a trajectory whose optimisation did not converge."""


class ConvergenceError(RuntimeError):
    """An iterative linear solve or eigen-solve did not reach its residual; the message says what
    to change (a direct solver, a larger residual, a smaller step)."""


def warn_user(message: str, category: type[Warning]) -> None:
    """``warnings.warn(message, category)`` attributed to the first frame outside the gridlbc
    package: the user's own call, however deep inside the library the result was judged (what
    Python 3.12's ``skip_file_prefixes`` does), so the warning names the line to change; the
    frames of :mod:`contextlib` between the library's (a function decorated with a context
    manager) are passed over too. Where every frame is the library's (the command line), the
    outermost one."""
    import contextlib
    import os
    import sys
    import warnings

    package = os.path.dirname(os.path.abspath(__file__)) + os.sep

    def ours(filename: str) -> bool:
        return filename.startswith(package) or filename == contextlib.__file__

    frame, level = sys._getframe(1), 2
    while frame.f_back is not None and ours(frame.f_code.co_filename):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, category, stacklevel=level)


def state_text(x) -> str:
    """A state ``(d,)`` as a message names it, each coordinate to 4 significant digits: in
    whatever unit the problem is written (a box of ±5 mm in metres), not to a fixed number of
    decimals, which would read "[0., 0.001]" there (stranger round 30)."""
    import numpy as np

    return np.array2string(
        np.asarray(x, dtype=float), separator=", ", formatter={"float_kind": lambda v: f"{v:.4g}"}
    )
