"""The fitted diffusion along one axis, compiled: the lines in parallel, each node by
:func:`gridlbc.backends.numba.fitted_node.diffuse_fitted_node`."""

from __future__ import annotations

import math

import numpy as np

from .fitted_cells import FIT_IMAGES, FIT_TABLE_RANGE, cell_constants, cell_curvature, line_bounds
from .fitted_node import diffuse_fitted_node
from .options import jit_parallel, prange


@jit_parallel
def diffuse_fitted_kernel(y, ell, ell_max, sigma2, h, n, stride, periodic, log_out, out):
    """out[r, p] = ∫ G_σ(x_p − x) φ̄(x) ȳ_r(x) dx along one axis, for y = z/φ and ell = log φ at
    the nodes: ȳ_r the piecewise-linear interpolant of y_r, φ̄ = exp(ℓ̄) with ℓ̄ on each cell the
    quadratic through its two nodes with the mean of their second differences κ
    (:func:`line_bounds`), capped at A below so that every cell's integrand stays concave in
    the exponent (exact for quadratic ℓ), G_σ the Gaussian of variance σ² = ``sigma2`` (one value, or
    one per node), continued across the ends by wrapping (periodic) or mirroring (closed). The
    curvature removes the bias of a linear ℓ̄, which overestimates v = −λℓ by h²v''/8 mid-cell.

    Each side of x_p is scanned cell by cell once, integrating every cell whose peak of the
    log-integrand −(x_p − x)²/(2σ²) + ℓ̄(x) is within 20 (``FIT_WINDOW``) of the largest peak
    seen so far, so no cell within 20 of the final largest peak is missed. The sums are kept
    relative to a scale e^E, E raised to a cell's peak (and the sums rescaled) only when that
    peak passes E + 30 (``FIT_SLACK``): nothing overflows, and few nodes pay an exp for it. A
    cell c cells away peaks at most at −A c² + ℓ (A = h²/(2σ²), ℓ its near node's, plus the
    line's bulge), and beyond c > L/(2A), L the line's rise (:func:`line_bounds`), no later
    cell can peak higher than that: the scan stops there once it falls below the window, or
    once −A c² + ``ell_max`` (plus the bulge) does (after at most ``FIT_IMAGES`` line lengths).

    With one σ² for all nodes, each cell's constants (:func:`cell_constants`) are computed once
    per line, not once per node that integrates the cell; the lines are taken in blocks, each
    with its own table of them. The integrand at a node k, c cells from x_p, over e^E is then
    e^{ℓ_k − L} · e^{−A c²} · e^{L − E} (L the line's largest ℓ): the first factor tabulated
    once per line, the second once per call, the third updated with E, so that it costs two
    products instead of an exp. Only where the line's ℓ spans at most 600
    (``FIT_TABLE_RANGE``): every factor of a cell within the window is then far from
    underflow and overflow (elsewhere, at small temperatures, each is an exp as before).

    A discrete maximum principle: where the reference's own result ψ(x_p) = ∫ G_σ φ̄ exceeds
    e^L, L the line's largest ℓ, every row at p is scaled by e^L/ψ(x_p) (a factor of φ alone,
    so the step stays linear and non-negative in y). The exact heat kernel never does that
    where φ's peaks are resolved (a Gaussian peak of variance s between two nodes lifts them
    only if h > 2√s); on a grid too coarse for ℓ, ℓ̄'s quadratics bulge above their nodes, and
    without the cap each step would lift the largest value again, a growth of z that can send v
    below zero (docs/schemes.rst).

    With ``log_out`` the rows of ``y`` are taken to be ones and out[0, p] is the logarithm of
    the integral, log ∫ G_σ φ̄ (capped at L): the reference advanced alone, in the log domain
    (nothing underflows however steep ℓ is)."""
    n_lines = y.shape[1] // n
    n_blocks = min(n_lines, 256)
    uniform = sigma2.size == 1
    reach = FIT_IMAGES * n
    shared = uniform and sigma2[0] > 0.0  # one Gaussian for every node
    A_shared = h * h / (2.0 * sigma2[0]) if shared else 0.0
    norm_shared = h / math.sqrt(2.0 * math.pi * sigma2[0]) if shared else 0.0
    gaussian = np.zeros(reach + 2)  # e^{−A c²} for the one σ², shared by all lines
    if shared:
        for c in range(reach + 2):
            gaussian[c] = math.exp(-A_shared * c * c)
    for block in prange(n_blocks):
        cells = np.empty((5, n))  # per cell k (nodes k, k + 1): κ, A_c, √A_c, 1/(2A_c), prefactor
        nodes = np.empty(n)  # e^{ℓ_k − L} per node k of the line
        curvature = np.empty(n)  # κ per node of the line
        A, norm = A_shared, norm_shared
        free = top = 0.0
        tables = False
        for line_id in range(block * n_lines // n_blocks, (block + 1) * n_lines // n_blocks):
            line = (line_id // stride) * n * stride + line_id % stride  # no division per node
            rise, bulge, top, low = line_bounds(ell, line, n, stride, periodic, curvature)
            if shared:
                free = rise / (2.0 * A)
                for k in range(n if periodic else n - 1):
                    kappa = cell_curvature(curvature, k, n, A)
                    cells[0, k] = kappa
                    cells[1, k], cells[2, k], cells[3, k], cells[4, k] = cell_constants(A, kappa)
                tables = top - low <= FIT_TABLE_RANGE
                if tables:
                    for k in range(n):
                        nodes[k] = math.exp(ell[line + k * stride] - top)
            geometry = (ell, curvature, bulge, ell_max, n, stride, periodic, line)
            lookup = (cells, uniform, tables, nodes, gaussian, top)
            for i in range(n):
                p = line + i * stride
                if not uniform and sigma2[p] > 0.0:
                    A = h * h / (2.0 * sigma2[p])
                    free = rise / (2.0 * A)
                    norm = h / math.sqrt(2.0 * math.pi * sigma2[p])
                if sigma2[0 if uniform else p] <= 0.0:  # no noise at this node: z' = z
                    for r in range(y.shape[0]):
                        out[r, p] = ell[p] if log_out else y[r, p] * math.exp(ell[p])
                    continue
                diffuse_fitted_node(y, out, log_out, geometry, lookup, A, free, norm, i)
