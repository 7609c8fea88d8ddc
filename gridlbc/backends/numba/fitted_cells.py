"""The cell integrals of the fitted diffusion (:mod:`gridlbc.schemes.splitting.fitted_diffusion`):
one cell's constants and mass, a line's bounds and curvature, and the scan's parameters."""

from __future__ import annotations

import math

import numpy as np

from .options import jit_inline
from .special import erfcx

FIT_WINDOW = 20.0  # cells whose integrand stays below e^{−20} of the largest are skipped
FIT_IMAGES = 16  # the fitted diffusion scans at most this many line lengths to each side
FIT_TABLE_RANGE = 600.0  # lines whose ℓ spans at most this take the integrand from tables
FIT_SLACK = 30.0  # the sums are rescaled only when a cell peaks this far above their scale


@jit_inline
def cell_constants(A, kappa):
    """(A_c, √A_c, 1/(2A_c), √π/(2√A_c)) of a cell whose log-integrand is −A_c s² + B s + C,
    A_c = A − κ/2 > 0: the Gaussian's A = h²/(2σ²) less the cell's curvature κ (≤ A)."""
    Ac = A - 0.5 * kappa
    root = math.sqrt(Ac)
    return Ac, root, 0.5 / Ac, 0.5 * math.sqrt(math.pi) / root


@jit_inline
def cell_mass(root, mu, top, E, F0, F1, prefactor):
    """∫₀¹ e^{f(s) − E} ds for the concave f(s) = −A s² + B s + C (A > 0) with its vertex at
    μ = B/(2A), its largest value on [0, 1] ``top`` and the integrand at the ends F0 =
    e^{f(0) − E}, F1 = e^{f(1) − E} (E ≥ ``top``, so nothing overflows); ``root`` = √A and
    ``prefactor`` = √π/(2√A) (:func:`cell_constants`).

    With the ends lo = −√A μ, hi = √A (1 − μ) in the Gaussian's units, and
    erfc(x) e^{f(μ)} = erfcx(x) e^{f(μ) − x²}, it is √π/(2√A) times

        F0 erfcx(lo) − F1 erfcx(hi)                  (μ ≤ 0, the integrand falls),
        F1 erfcx(−hi) − F0 erfcx(−lo)                (μ ≥ 1, it rises),
        2 e^{f(μ) − E} − F1 erfcx(hi) − F0 erfcx(−lo) (its peak inside the cell, f(μ) = top),

    every erfcx taken at a non-negative argument, so it is bounded and never underflows."""
    lo, hi = -root * mu, root * (1.0 - mu)
    if lo >= 0.0:
        mass = F0 * erfcx(lo) - F1 * erfcx(hi)
    elif hi <= 0.0:
        mass = F1 * erfcx(-hi) - F0 * erfcx(-lo)
    else:
        peak = 1.0 if top == E else math.exp(top - E)  # the cell that set E: no exp
        mass = 2.0 * peak - F1 * erfcx(hi) - F0 * erfcx(-lo)
    return max(prefactor * mass, 0.0)


@jit_inline
def line_bounds(ell, line, n, stride, periodic, curvature):
    """For the line starting at ``line``: ``curvature[i]`` = ℓ_{i−1} − 2ℓ_i + ℓ_{i+1} at its node
    i (wrapped on a periodic line; at the ends of a closed one, the neighbour's), and returns
    (rise, bulge, top, low): the largest |ℓ_{i+1} − ℓ_i| between neighbours, and the most the
    curved interpolant of the fitted diffusion rises above the nodes, max(0, −min κ)/8,
    which together bound how far the fitted diffusion scans; and the line's largest and
    smallest ℓ."""
    rise = 0.0
    lowest = 0.0
    top, low = -np.inf, np.inf
    for i in range(n):
        top, low = max(top, ell[line + i * stride]), min(low, ell[line + i * stride])
        left = i - 1 if i > 0 else (n - 1 if periodic else 1)
        right = i + 1 if i < n - 1 else (0 if periodic else n - 2)
        if not periodic and (i == 0 or i == n - 1):
            inner = 1 if i == 0 else n - 2  # the neighbour's curvature
            left, right, centre = inner - 1, inner + 1, inner
        else:
            centre = i
        kappa = (
            ell[line + left * stride]
            - 2.0 * ell[line + centre * stride]
            + ell[line + right * stride]
        )
        curvature[i] = kappa
        lowest = min(lowest, kappa)
        if periodic or i < n - 1:
            j = i + 1 if i + 1 < n else 0
            rise = max(rise, abs(ell[line + j * stride] - ell[line + i * stride]))
    return rise, -lowest / 8.0, top, low


@jit_inline
def cell_curvature(curvature, cell, n, A):
    """κ of cell ``cell`` of a line (nodes cell and cell + 1, wrapped: a periodic line's seam is
    cell n − 1): the mean of its nodes' second differences, capped at A."""
    return min(0.5 * (curvature[cell] + curvature[cell + 1 if cell + 1 < n else 0]), A)
