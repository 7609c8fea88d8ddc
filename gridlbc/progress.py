"""A one-line progress bar on stderr for long runs: solves, certificates and sweeps."""

from __future__ import annotations

import math
import sys
import time

DELAY = 2.0
"""Seconds after which a run given ``progress=None`` (the default of :func:`gridlbc.solve` and
:func:`gridlbc.certify`) starts its progress bar: quiet for short runs, a bar for long ones."""


class ProgressBar:
    """``label [#####    ] done/total items{note} elapsed ETA [rate]`` on one line of stderr.

    Parameters
    ----------
    total : int
        Items to do (time steps, sweep members).
    enabled : bool
        False: :meth:`update` prints nothing.
    label : str
        What runs, at the start of the line.
    items : str
        The items' name (``"steps"``).
    work_per_item : int
        If positive, the line ends with the rate of ``work_per_item`` × items per second, in
        millions of ``work_unit`` (e.g. nodes per step: M node-steps/s).
    work_unit : str
        Name of that rate's unit.
    delay : float
        Print only once the run has taken this many seconds (quiet for short runs).
    """

    def __init__(
        self,
        total: int,
        enabled: bool,
        label: str,
        *,
        items: str = "steps",
        work_per_item: int = 0,
        work_unit: str = "node-steps",
        delay: float = 0.0,
    ):
        self.total, self.enabled, self.label, self.items = total, enabled, label, items
        self.work_per_item, self.work_unit, self.delay = work_per_item, work_unit, delay
        self.start = time.perf_counter()
        self.last = -math.inf

    @classmethod
    def chosen(cls, total: int, progress: bool | None, label: str, **options) -> ProgressBar:
        """A bar as the user's ``progress`` asks: True always, False never, None once the run
        has taken :data:`DELAY` seconds."""
        return cls(
            total, progress is not False, label, delay=DELAY if progress is None else 0.0, **options
        )

    def update(self, done: int, note: str = ""):
        """Show ``done`` of ``total`` items, ``note`` right after the count (at most twice a
        second, and always the last update)."""
        if not self.enabled:
            return
        now = time.perf_counter()
        elapsed = now - self.start
        if (now - self.last < 0.5 and done != self.total) or elapsed < self.delay:
            return
        self.last = now
        fraction = done / self.total if self.total else 1.0
        bar = "#" * int(25 * fraction)
        eta = elapsed * (1 - fraction) / fraction if done else math.nan
        line = (
            f"\r{self.label} [{bar:<25}] {done}/{self.total} {self.items}{note} "
            f"{elapsed:6.1f}s ETA {eta:6.1f}s"
        )
        if self.work_per_item:
            rate = done * self.work_per_item / elapsed / 1e6 if elapsed > 0 else math.nan
            line += f" {rate:7.1f} M {self.work_unit}/s"
        sys.stderr.write(line)
        if done == self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()
