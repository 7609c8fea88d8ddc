"""The fitted diffusion at one node: the scan of a line's cells to both sides, one kernel
(inlined into :func:`gridlbc.backends.numba.fitted_diffusion.diffuse_fitted_kernel`)."""

from __future__ import annotations

import math

from .fitted_cells import (
    FIT_IMAGES,
    FIT_SLACK,
    FIT_WINDOW,
    cell_constants,
    cell_curvature,
    cell_mass,
)
from .options import jit_inline


@jit_inline
def diffuse_fitted_node(y, out, log_out, geometry, lookup, A, free, norm, i):
    """:func:`~gridlbc.backends.numba.fitted_diffusion.diffuse_fitted_kernel` at node i of a
    line, into ``out`` (log ∫ G_σ φ̄ with ``log_out``), for the Gaussian's A = h²/(2σ²) there,
    ``free`` = the line's rise/(2A) and ``norm`` = h/√(2πσ²). The line's ``geometry`` is
    (ell, its curvature per node, its bulge, the largest ell of all lines, n, stride, periodic,
    the line's first node); its ``lookup`` is (cells, uniform, tables, nodes, gaussian,
    line_top): ``cells`` the line's cell constants when ``uniform`` (one σ²) and, with
    ``tables``, ``nodes`` = e^{ℓ_k − L}, ``gaussian`` = e^{−A c²} and ``line_top`` = L (the
    kernel's docstring)."""
    ell, curvature, bulge, ell_max, n, stride, periodic, line = geometry
    cells, uniform, tables, nodes, gaussian, line_top = lookup
    n_rhs = y.shape[0]
    p = line + i * stride
    reach = FIT_IMAGES * n
    peak = ell[p]  # the largest cell peak so far, which sets the window
    scale = peak  # E: the sums are kept relative to e^E, raised only when a peak passes E + 30
    factor = 1.0 / nodes[i] if tables else 0.0  # e^{L − E}, E = ℓ_i: no exp
    accumulated = False
    mass = 0.0  # log_out: ∫ G_σ φ̄ over e^E (in a register, not in ``out``)
    if not log_out:
        for r in range(n_rhs):
            out[r, p] = 0.0
    for side in range(2):
        step = 1 if side == 0 else -1
        near = i  # unfolded index of the cell's node nearest to x_p, then the far one
        k_near = i
        heading = step  # the direction of the folded index (mirrors turn it round)
        near_log = ell[p]  # the log-integrand at the near node
        near_value = (
            nodes[i] * factor
            if tables  # and the integrand over e^E (−1: not known)
            else math.exp(near_log - scale)
        )
        for c in range(reach):
            far = near + step
            k_far = k_near + heading
            if k_far == n:
                k_far, heading = (0, heading) if periodic else (n - 2, -heading)
            elif k_far == -1:
                k_far, heading = (n - 1, heading) if periodic else (1, -heading)
            gauss = -A * c * c  # the Gaussian's log at the cell's near end
            near_ell, far_ell = ell[line + k_near * stride], ell[line + k_far * stride]
            if gauss + ell_max + bulge < peak - FIT_WINDOW or (
                c > free and gauss + near_ell + bulge < peak - FIT_WINDOW
            ):
                break
            far_log = far_ell - A * (far - i) * (far - i)
            if gauss + max(near_ell, far_ell) + bulge < peak - FIT_WINDOW:  # the cell is out
                near, k_near = far, k_far
                near_log, near_value = far_log, -1.0
                continue
            lo_node, hi_node = (k_near, k_far) if side == 0 else (k_far, k_near)
            a = near - i if side == 0 else far - i  # (the cell's left end − x_p)/h
            k0, k1 = line + lo_node * stride, line + hi_node * stride
            cell = min(lo_node, hi_node)  # its folded index (a periodic line's seam: n − 1)
            if max(lo_node, hi_node) - cell > 1:
                cell = n - 1
            if uniform:
                kappa, Ac, root = cells[0, cell], cells[1, cell], cells[2, cell]
                half_inverse, prefactor = cells[3, cell], cells[4, cell]
            else:
                kappa = cell_curvature(curvature, cell, n, A)
                Ac, root, half_inverse, prefactor = cell_constants(A, kappa)
            B = ell[k1] - ell[k0] - 2.0 * A * a - 0.5 * kappa
            C = ell[k0] - A * a * a
            mu = B * half_inverse
            s = min(max(mu, 0.0), 1.0)
            top = C + s * (B - Ac * s)  # the cell's peak
            k_cell_near = k_near
            near, k_near = far, k_far
            if top > peak:
                peak = top
            elif top < peak - FIT_WINDOW:
                near_log, near_value = far_log, -1.0
                continue
            if top > scale + FIT_SLACK:  # rescale what is summed so far to e^top
                rescale = math.exp(scale - top)
                mass *= rescale
                if accumulated and not log_out:
                    for r in range(n_rhs):
                        out[r, p] *= rescale
                if near_value >= 0.0:
                    near_value *= rescale
                factor *= rescale
                scale = top
            if tables:
                if near_value < 0.0:
                    near_value = nodes[k_cell_near] * factor * gaussian[c]
                far_value = nodes[k_far] * factor * gaussian[c + 1]
            else:
                if near_value < 0.0:
                    near_value = math.exp(near_log - scale)
                far_value = math.exp(far_log - scale)
            F0, F1 = (near_value, far_value) if side == 0 else (far_value, near_value)
            near_log, near_value = far_log, far_value
            accumulated = True
            total = cell_mass(root, mu, top, scale, F0, F1, prefactor)
            mass += total
            if log_out:
                continue
            # ∫₀¹ s e^{f} ds from ∫₀¹ (s − μ) e^{f} ds = (e^{f(0)} − e^{f(1)})/(2A_c)
            w1 = max(mu * total + (F0 - F1) * half_inverse, 0.0)
            w0 = max(total - w1, 0.0)
            for r in range(n_rhs):
                out[r, p] += w0 * y[r, k0] + w1 * y[r, k1]
    excess = scale + math.log(mass * norm) - line_top  # log ∫ G_σ φ̄ above the line's top
    if log_out:
        out[0, p] = line_top + min(excess, 0.0)
        return
    norm *= math.exp(scale - max(excess, 0.0))
    for r in range(n_rhs):
        out[r, p] *= norm
