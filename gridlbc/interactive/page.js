"use strict";
// gridlbc interactive page: linear Bellman combination evaluated in the browser.
// Mirrors gridlbc.interpolate (Kuhn barycentric), gridlbc.solution (log-scaled slices, linear
// time interpolation, finite-difference B^T grad z, fitted components relative to their
// reference's log phi), gridlbc.combine (common scale, alpha),
// gridlbc.project (Gram system) and gridlbc.simulate (noise-free Euler rollout).
(function () {
  const started = performance.now();
  const DATA = JSON.parse(document.getElementById("gridlbc-data").textContent);

  // ---------------------------------------------------------------- the grid
  const axes = DATA.axes;
  const d = axes.length;
  const shape = axes.map((a) => a.n);
  const lo = axes.map((a) => a.lo);
  const hi = axes.map((a) => a.hi);
  const periodic = axes.map((a) => a.periodic);
  const spacing = axes.map((a) => (a.hi - a.lo) / (a.periodic ? a.n : a.n - 1));
  const period = axes.map((a) => a.hi - a.lo);
  const strides = new Array(d);
  let size = 1;
  for (let k = d - 1; k >= 0; k--) { strides[k] = size; size *= shape[k]; }

  const lambda = DATA.temperature;
  const T = DATA.horizon;
  const times = DATA.times;
  const S = times.length;
  const B = DATA.B; // d x m, constant for the supported systems
  const m = B[0].length;
  const Rinv = DATA.R_inv;
  const R = DATA.R;
  const axesWithB = [];
  for (let k = 0; k < d; k++) if (B[k].some((b) => b !== 0)) axesWithB.push(k);

  function decode(text) {
    const bin = atob(text);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return DATA.dtype === "float32" ? new Float32Array(bytes.buffer) : new Float64Array(bytes.buffer);
  }
  // fitting references (log phi, gridlbc.solution.FittingReference), shared by components
  const refs = DATA.references.map((r) => ({ R: decode(r.log_slices), scales: r.log_scales }));
  const comps = DATA.components.map((c) => ({
    label: c.label, cost: c.terminal_cost, logScales: c.log_scales, Z: decode(c.slices),
    R: c.reference === null ? null : refs[c.reference].R,
    refScales: c.reference === null ? null : refs[c.reference].scales,
    exitCost: c.exit_cost,
    exitNodes: c.exit_cost !== null && c.exit_cost.nodes !== undefined ? decode(c.exit_cost.nodes) : null,
  }));
  const n = comps.length;
  const decodeMs = performance.now() - started;

  // ------------------------------------------- barycentric interpolation (Kuhn)
  const frac = new Float64Array(d);
  const order = new Int32Array(d);
  function barycentric(x, idx, bw) {
    let base = 0;
    for (let k = 0; k < d; k++) {
      let s = (x[k] - lo[k]) / spacing[k];
      const nk = shape[k];
      let i;
      if (periodic[k]) {
        s = s - nk * Math.floor(s / nk);
        i = Math.floor(s);
        if (i >= nk) { i -= nk; s -= nk; }
      } else {
        if (s < 0) s = 0; else if (s > nk - 1) s = nk - 1;
        i = Math.min(Math.floor(s), nk - 2);
      }
      frac[k] = s - i;
      base += i * strides[k];
    }
    for (let k = 0; k < d; k++) order[k] = k; // stable sort, decreasing fractions
    for (let a = 1; a < d; a++) {
      const key = order[a];
      let b = a - 1;
      while (b >= 0 && frac[order[b]] < frac[key]) { order[b + 1] = order[b]; b--; }
      order[b + 1] = key;
    }
    idx[0] = base;
    bw[0] = 1 - frac[order[0]];
    let node = base;
    for (let j = 0; j < d; j++) {
      const k = order[j];
      const nk = shape[k];
      const coord = Math.floor(node / strides[k]) % nk;
      if (coord === nk - 1) node -= (nk - 1) * strides[k]; else node += strides[k];
      idx[j + 1] = node;
      bw[j + 1] = frac[k] - (j + 1 < d ? frac[order[j + 1]] : 0);
    }
  }

  // the nodes and factor of the derivative along k at a node: central, one-sided at closed ends
  const stencil = { up: 0, down: 0, scale: 0 };
  function neighbours(node, k) {
    const s = strides[k], nk = shape[k], h = spacing[k];
    const i = Math.floor(node / s) % nk;
    if (periodic[k]) {
      stencil.up = i < nk - 1 ? node + s : node - (nk - 1) * s;
      stencil.down = i > 0 ? node - s : node + (nk - 1) * s;
      stencil.scale = 0.5 / h;
    } else if (i === 0) { stencil.up = node + s; stencil.down = node; stencil.scale = 1 / h; }
    else if (i === nk - 1) { stencil.up = node; stencil.down = node - s; stencil.scale = 1 / h; }
    else { stencil.up = node + s; stencil.down = node - s; stencil.scale = 0.5 / h; }
    return stencil;
  }
  // dZ/dx_k at a node of slice offset `off`
  function gradient(Z, off, node, k) {
    const st = neighbours(node, k);
    return diff(Z[off + st.up], Z[off + st.down]) * st.scale;
  }
  // the difference in the stored precision, as the compiled kernel takes it
  const diff = DATA.dtype === "float32" ? (a, b) => Math.fround(a - b) : (a, b) => a - b;

  // ----------------------------------------------------- time interpolation
  function checkTime(t) {
    if (!Number.isFinite(t) || t < -1e-9 * T || t > T + 1e-9 * T) {
      throw new Error("time must lie in [0, T] = [0, " + T + "], got " + t);
    }
    return Math.min(Math.max(t, 0), T);
  }
  // per component: slice j, weights tau of slices j, j+1 and the common log scale L; for a
  // fitted component tau weights y = z/phi (relative to e^C, C the larger of log(z's scale /
  // phi's)), theta0/1 weight log phi, and L = C + the larger of phi's scales
  function timeWeights(t) {
    let j = 0; // searchsorted(times, t, "right") - 1, clipped to [0, S-2]
    while (j < S && times[j] <= t) j++;
    j = Math.min(Math.max(j - 1, 0), S - 2);
    const theta = Math.min(Math.max((t - times[j]) / (times[j + 1] - times[j]), 0), 1);
    return comps.map((c) => {
      let a = c.logScales[j], b = c.logScales[j + 1];
      let top = 0;
      if (c.R) {
        a -= c.refScales[j]; b -= c.refScales[j + 1];
        top = Math.max(c.refScales[j], c.refScales[j + 1]);
      }
      const C = Math.max(a, b);
      return { j: j, L: C + top, tau0: (1 - theta) * Math.exp(a - C),
        tau1: theta * Math.exp(b - C), theta0: 1 - theta, theta1: theta, top: top };
    });
  }

  // y = z/phi at a node of slice offset `off`, and its central difference along k (in double)
  function ratio(c, off, node) {
    const z = c.Z[off + node];
    return z > 0 ? Math.exp(Math.log(z) - c.R[off + node]) : 0;
  }
  function ratioGradient(c, off, node, k) {
    const st = neighbours(node, k);
    return (ratio(c, off, st.up) - ratio(c, off, st.down)) * st.scale;
  }

  // scaled z and B^T grad z of component c at x (up to e^L); writes g (length m)
  const idxV = new Int32Array(d + 1);
  const bwV = new Float64Array(d + 1);
  const gEll = new Float64Array(m), gY = new Float64Array(m);
  function fittedFields(c, tw, x, g) { // z = e^{I[log phi]} I[y], grad z = z grad I[log phi] + e^{..} grad I[y]
    const R = c.R, off0 = tw.j * size, off1 = off0 + size;
    let ell = tw.theta0 * c.refScales[tw.j] + tw.theta1 * c.refScales[tw.j + 1], y = 0;
    for (let v = 0; v <= d; v++) {
      const node = idxV[v];
      ell += bwV[v] * (tw.theta0 * R[off0 + node] + tw.theta1 * R[off1 + node]);
      y += bwV[v] * (tw.tau0 * ratio(c, off0, node) + tw.tau1 * ratio(c, off1, node));
    }
    gEll.fill(0); gY.fill(0);
    for (const k of axesWithB) {
      for (let v = 0; v <= d; v++) {
        const node = idxV[v];
        const dl = tw.theta0 * gradient(R, off0, node, k) + tw.theta1 * gradient(R, off1, node, k);
        const dy = tw.tau0 * ratioGradient(c, off0, node, k) + tw.tau1 * ratioGradient(c, off1, node, k);
        for (let r = 0; r < m; r++) {
          gEll[r] += bwV[v] * B[k][r] * dl;
          gY[r] += bwV[v] * B[k][r] * dy;
        }
      }
    }
    const phi = Math.exp(ell - tw.top);
    for (let r = 0; r < m; r++) g[r] = phi * (gEll[r] * y + gY[r]);
    return phi * y;
  }
  function componentFields(c, tw, x, g) {
    if (exitNodes === null) barycentric(x, idxV, bwV);
    else if (inExit(x)) return endedFields(c, tw, x, g); // inExit leaves x's stencil in idxV, bwV
    if (c.R) return fittedFields(c, tw, x, g);
    const Z = c.Z, off0 = tw.j * size, off1 = off0 + size;
    let z = 0;
    for (let v = 0; v <= d; v++) {
      z += bwV[v] * (tw.tau0 * Z[off0 + idxV[v]] + tw.tau1 * Z[off1 + idxV[v]]);
    }
    for (let r = 0; r < m; r++) g[r] = 0;
    for (const k of axesWithB) {
      for (let v = 0; v <= d; v++) {
        const node = idxV[v];
        const dz = tw.tau0 * gradient(Z, off0, node, k) + tw.tau1 * gradient(Z, off1, node, k);
        for (let r = 0; r < m; r++) g[r] += bwV[v] * B[k][r] * dz;
      }
    }
    return z;
  }

  // in the exit set the task has ended: z = exp(-g_E/lambda) exactly and no control
  // (gridlbc.Solution.fields, SPEC §9); g_E a quadratic or a constant, else interpolated from its
  // values at the nodes (x's stencil is in idxV, bwV)
  function endedFields(c, tw, x, g) {
    const cost = c.exitCost;
    let exitCost = 0;
    if (cost.constant !== undefined) exitCost = cost.constant;
    else if (cost.quadratic !== undefined) exitCost = quadratic(cost.quadratic, x);
    else for (let v = 0; v <= d; v++) exitCost += bwV[v] * c.exitNodes[idxV[v]];
    for (let r = 0; r < m; r++) g[r] = 0;
    return Math.exp(-exitCost / lambda - tw.L);
  }

  // -------------------------------------------------------------- combination
  function checkWeights(w) {
    if (w.length !== n) throw new Error("weights must be " + n + " numbers, one per component, got " + w.length);
    if (!w.every(Number.isFinite)) throw new Error("weights must be finite");
    if (!w.some((v) => v !== 0)) throw new Error("weights are all zero: the combined desirability would vanish");
    const sum = w.reduce((a, b) => a + b, 0);
    if (!(sum > 0)) throw new Error("weights sum to " + sum.toPrecision(4) + " ≤ 0: Σ w_i z_i must be positive");
    return w;
  }
  function scaleFactors(tws, w) { // f_i = w_i e^{L_i - L}, L = max_i L_i
    let L = -Infinity;
    for (const tw of tws) L = Math.max(L, tw.L);
    return { L: L, f: tws.map((tw, i) => w[i] * Math.exp(tw.L - L)) };
  }
  function policyFrom(z, g) {
    const u = new Array(m);
    for (let r = 0; r < m; r++) {
      let s = 0;
      for (let q = 0; q < m; q++) s += g[q] * Rinv[r][q];
      u[r] = z > 0 ? lambda * s / z : NaN;
    }
    return u;
  }
  // value, policy and alpha of the combination at one state and time
  function evaluate(w, x, t) {
    const tws = timeWeights(checkTime(t));
    const sf = scaleFactors(tws, w);
    const zi = new Array(n);
    const g = new Float64Array(m), gi = new Float64Array(m);
    let z = 0;
    for (let i = 0; i < n; i++) {
      zi[i] = sf.f[i] * componentFields(comps[i], tws[i], x, gi);
      z += zi[i];
      for (let r = 0; r < m; r++) g[r] += sf.f[i] * gi[r];
    }
    return {
      value: z > 0 ? -lambda * (Math.log(z) + sf.L) : Infinity,
      policy: policyFrom(z, g),
      alpha: zi.map((v) => (z > 0 ? v / z : NaN)),
    };
  }

  // ------------------------------------------------------------------ costs
  function quadratic(cost, x) {
    const diff = new Array(d);
    for (let k = 0; k < d; k++) {
      let a = x[k] - cost.center[k];
      const P = cost.periods ? cost.periods[k] : null;
      if (P !== null) { a = pyMod(a + 0.5 * P, P) - 0.5 * P; }
      diff[k] = a;
    }
    let s = 0;
    for (let i = 0; i < d; i++) for (let j = 0; j < d; j++) s += diff[i] * cost.weights[i][j] * diff[j];
    return s;
  }
  function pyMod(a, P) { // numpy's mod for P > 0: the result has the sign of P
    const r = a % P;
    return r !== 0 && r < 0 ? r + P : r;
  }
  const quadraticCosts = comps.every((c) => c.cost !== null);
  function compositeTerminalCost(w, x) { // g = -λ log Σ w_i exp(-g_i/λ)
    const e = comps.map((c) => -quadratic(c.cost, x) / lambda);
    const top = Math.max(...e);
    let s = 0;
    for (let i = 0; i < n; i++) s += w[i] * Math.exp(e[i] - top);
    return s > 0 ? -lambda * (Math.log(s) + top) : Infinity;
  }

  // ------------------------------------------------------------- the system
  const P = DATA.system.parameters;
  let drift;
  if (DATA.system.name === "Pendulum") {
    const inertia = P.mass * P.length * P.length;
    drift = (x) => [x[1], (P.gravity / P.length) * Math.sin(x[0]) - P.damping * x[1] / inertia];
  } else if (DATA.system.name === "PointMass") {
    drift = (x) => [x[1], 0];
  } else {
    throw new Error("unsupported system " + DATA.system.name);
  }
  function wrap(x) {
    for (let k = 0; k < d; k++) if (periodic[k]) x[k] = lo[k] + pyMod(x[k] - lo[k], period[k]);
    return x;
  }
  // the exit set of a first-exit problem: its shapes (gridlbc.regions.Box, Ball, their union;
  // null for an infinite bound or radius), else its nodes, as gridlbc.load knows a callable E
  // (gridlbc.regions.GridRegion: a state is in it where the barycentric interpolation of the
  // nodes' membership is at least 1/2)
  const exitNodes = DATA.exit === null ? null : Uint8Array.from(atob(DATA.exit), (c) => c.charCodeAt(0));
  const exitRegion = DATA.exit_region;
  function inShape(shape, x) {
    if (shape.union) return shape.union.some((part) => inShape(part, x));
    if (shape.box) {
      const lower = shape.box.lower, upper = shape.box.upper;
      for (let k = 0; k < d; k++) {
        if (lower[k] !== null && x[k] < lower[k]) return false;
        if (upper[k] !== null && x[k] > upper[k]) return false;
      }
      return true;
    }
    let s = 0; // a ball, to the nearest image on periodic axes (gridlbc.costs.wrap_difference)
    for (let k = 0; k < d; k++) {
      const r = shape.ball.radius[k];
      if (r === null) continue;
      let a = x[k] - shape.ball.center[k];
      if (periodic[k]) a = pyMod(a + 0.5 * period[k], period[k]) - 0.5 * period[k];
      s += (a / r) ** 2;
    }
    return s <= 1.0;
  }
  function inExit(x) { // also leaves x's stencil in idxV, bwV
    if (exitNodes === null) return false;
    barycentric(x, idxV, bwV);
    if (exitRegion !== null) return inShape(exitRegion, x);
    let membership = 0;
    for (let v = 0; v <= d; v++) membership += bwV[v] * exitNodes[idxV[v]];
    return membership >= 0.5;
  }

  // noise-free Euler rollout of the combined policy from (x0, t0), as gridlbc.simulate
  function rollout(w, x0, t0) {
    const K = Math.max(1, Math.ceil((T - t0) / (T / DATA.rollout_steps) - 1e-9));
    const step = (T - t0) / K;
    let x = wrap(x0.slice());
    const states = [x.slice()], ts = [t0], controls = [], alphas = [];
    let cost = 0, message = "";
    const stateCost = DATA.state_cost;
    let exited = inExit(x);
    for (let k = 0; k < K && !exited; k++) {
      const t = t0 + k * step;
      const e = evaluate(w, x, t);
      if (!e.policy.every(Number.isFinite)) {
        message = "the policy is undefined (desirability underflowed) at t = " + t.toFixed(3);
        break;
      }
      const a = drift(x);
      if (stateCost !== null) cost += (stateCost === "other" ? NaN : quadratic(stateCost, x)) * step;
      let effort = 0;
      for (let i = 0; i < m; i++) for (let j = 0; j < m; j++) effort += e.policy[i] * R[i][j] * e.policy[j];
      cost += 0.5 * effort * step;
      const next = new Array(d);
      for (let q = 0; q < d; q++) {
        let v = a[q];
        for (let r = 0; r < m; r++) v += B[q][r] * e.policy[r];
        next[q] = x[q] + v * step + 0;
      }
      x = wrap(next);
      states.push(x.slice()); ts.push(k + 1 === K ? T : t0 + (k + 1) * step);
      controls.push(e.policy); alphas.push(e.alpha);
      exited = inExit(x);
    }
    if (DATA.stationary && !exited && message === "") {
      message = "the rollout had not reached the exit set by t = " + T + " s";
    }
    const complete = message === "";
    // a first-exit task pays its exit cost, which the page does not know: no total then
    const terminal = complete && quadraticCosts && !DATA.stationary ? compositeTerminalCost(w, x) : NaN;
    return { states: states, times: ts, controls: controls, alphas: alphas, steps: K,
      cost: cost + terminal, message: message, complete: complete };
  }

  // ------------------------------------------------------------- projection
  function solveLinear(A, b) { // Gaussian elimination with partial pivoting
    const k = b.length, M = A.map((row, i) => row.concat([b[i]]));
    for (let c = 0; c < k; c++) {
      let p = c;
      for (let r = c + 1; r < k; r++) if (Math.abs(M[r][c]) > Math.abs(M[p][c])) p = r;
      [M[c], M[p]] = [M[p], M[c]];
      for (let r = c + 1; r < k; r++) {
        const f = M[r][c] / M[c][c];
        for (let q = c; q <= k; q++) M[r][q] -= f * M[c][q];
      }
    }
    const out = new Array(k);
    for (let r = k - 1; r >= 0; r--) {
      let s = M[r][k];
      for (let q = r + 1; q < k; q++) s -= M[r][q] * out[q];
      out[r] = s / M[r][r];
    }
    return out;
  }
  function logDet(A) { // log|det A| and its sign, by elimination
    const k = A.length, M = A.map((row) => row.slice());
    let sign = 1, log = 0;
    for (let c = 0; c < k; c++) {
      let p = c;
      for (let r = c + 1; r < k; r++) if (Math.abs(M[r][c]) > Math.abs(M[p][c])) p = r;
      if (p !== c) { [M[c], M[p]] = [M[p], M[c]]; sign = -sign; }
      if (M[c][c] === 0) return { sign: 0, log: -Infinity };
      if (M[c][c] < 0) sign = -sign;
      log += Math.log(Math.abs(M[c][c]));
      for (let r = c + 1; r < k; r++) {
        const f = M[r][c] / M[c][c];
        for (let q = c; q < k; q++) M[r][q] -= f * M[c][q];
      }
    }
    return { sign: sign, log: log };
  }
  function eigenvalues(A) { // symmetric A, cyclic Jacobi rotations
    const k = A.length, M = A.map((row) => row.slice());
    for (let sweep = 0; sweep < 100; sweep++) {
      let off = 0;
      for (let p = 0; p < k; p++) for (let q = p + 1; q < k; q++) off += M[p][q] * M[p][q];
      if (off < 1e-300) break;
      for (let p = 0; p < k; p++) for (let q = p + 1; q < k; q++) {
        if (M[p][q] === 0) continue;
        const th = (M[q][q] - M[p][p]) / (2 * M[p][q]);
        const t = Math.sign(th || 1) / (Math.abs(th) + Math.sqrt(th * th + 1));
        const c = 1 / Math.sqrt(t * t + 1), s = t * c;
        for (let r = 0; r < k; r++) { // columns p, q
          const a = M[r][p], b = M[r][q];
          M[r][p] = c * a - s * b; M[r][q] = s * a + c * b;
        }
        for (let r = 0; r < k; r++) { // rows p, q
          const a = M[p][r], b = M[q][r];
          M[p][r] = c * a - s * b; M[q][r] = s * a + c * b;
        }
      }
    }
    return M.map((row, i) => row[i]);
  }
  const gridPeriodic = periodic.some((p) => p);
  function projectionMethod(costs) {
    const periodicCost = costs.some((c) => c.periods && c.periods.some((p) => p !== null));
    const pd = costs.every((c) => Math.min(...eigenvalues(c.weights)) > 0);
    return !gridPeriodic && !periodicCost && pd ? "analytic" : "quadrature";
  }
  function gramAnalytic(costs) {
    const A = costs.map((c) => c.weights.map((row) => row.map((v) => 2 * v / lambda)));
    const k = costs.length, G = [];
    for (let i = 0; i < k; i++) G.push(new Array(k));
    for (let i = 0; i < k; i++) for (let j = i; j < k; j++) {
      const Sm = A[i].map((row, r) => row.map((v, q) => v + A[j][r][q]));
      const ld = logDet(Sm);
      if (ld.sign <= 0 || !Number.isFinite(ld.log)) throw new Error("A_i + A_j is singular");
      const dc = costs[i].center.map((v, q) => v - costs[j].center[q]);
      const Ajdc = A[j].map((row) => row.reduce((s, v, q) => s + v * dc[q], 0));
      const y = solveLinear(Sm, Ajdc);
      let quad = 0;
      for (let r = 0; r < d; r++) for (let q = 0; q < d; q++) quad += dc[r] * A[i][r][q] * y[q];
      G[i][j] = G[j][i] = Math.exp(0.5 * d * Math.log(2 * Math.PI) - 0.5 * ld.log - 0.5 * quad);
    }
    return { G: G, scales: costs.map(() => 0) };
  }
  let nodeCoords = null, trapezoid = null;
  function gramQuadrature(costs) {
    if (nodeCoords === null) {
      nodeCoords = []; trapezoid = new Float64Array(size);
      for (let p = 0; p < size; p++) {
        const x = new Array(d);
        let q = 1;
        for (let k = 0; k < d; k++) {
          const i = Math.floor(p / strides[k]) % shape[k];
          x[k] = lo[k] + spacing[k] * i;
          q *= (!periodic[k] && (i === 0 || i === shape[k] - 1)) ? 0.5 * spacing[k] : spacing[k];
        }
        nodeCoords.push(x); trapezoid[p] = q;
      }
    }
    const H = [], scales = [];
    for (const c0 of costs) {
      const c = c0.periods ? c0 : Object.assign({}, c0, { periods: period.map((p, k) => (periodic[k] ? p : null)) });
      const g = nodeCoords.map((x) => quadratic(c, x));
      const gmin = Math.min(...g);
      scales.push(-gmin / lambda);
      H.push(Float64Array.from(g, (v) => Math.exp(-(v - gmin) / lambda)));
    }
    const k = costs.length, G = [];
    for (let i = 0; i < k; i++) G.push(new Array(k));
    for (let i = 0; i < k; i++) for (let j = i; j < k; j++) {
      let s = 0;
      for (let p = 0; p < size; p++) s += H[i][p] * trapezoid[p] * H[j][p];
      G[i][j] = G[j][i] = s;
    }
    return { G: G, scales: scales };
  }
  // weights w with Σ w_i h_i the L2 projection of the target reward (gridlbc.projection)
  function project(center) {
    if (!quadraticCosts) throw new Error("projection needs quadratic terminal costs (these components have other costs)");
    const W = comps[0].cost.weights;
    const target = { center: center, weights: W, periods: period.map((p, k) => (periodic[k] ? p : null)) };
    const everything = comps.map((c) => c.cost).concat([target]);
    const method = projectionMethod(everything);
    const q = method === "analytic" ? gramAnalytic(everything) : gramQuadrature(everything);
    const G = q.G, sc = q.scales;
    const A = G.slice(0, n).map((row) => row.slice(0, n));
    const b = G.slice(0, n).map((row) => row[n]);
    const tn2 = G[n][n];
    const D = A.map((row, i) => 1 / Math.sqrt(row[i]));
    const Ahat = A.map((row, i) => row.map((v, j) => v * D[i] * D[j]));
    const ev = eigenvalues(Ahat).map(Math.abs);
    const condition = Math.max(...ev) / Math.min(...ev);
    if (!Number.isFinite(condition) || condition > 1 / 2.220446049250313e-16) {
      throw new Error("the component rewards are linearly dependent (Gram condition " + condition.toPrecision(3) + ")");
    }
    const Db = b.map((v, i) => D[i] * v);
    const what = solveLinear(Ahat, Db);
    const fit = what.reduce((s, v, i) => s + v * Db[i], 0);
    const residual = Math.sqrt(Math.max(tn2 - fit, 0) / tn2);
    const weights = what.map((v, i) => D[i] * v * Math.exp(sc[n] - sc[i]));
    const tol = DATA.projection, messages = [];
    const wmax = Math.max(...weights.map(Math.abs)), sum = weights.reduce((a, v) => a + v, 0);
    if (Math.min(...weights) < -tol.negative_tolerance * wmax) messages.push("negative weights: the blended cost has minima away from the goal; place components around it");
    if (Math.abs(sum - 1) > tol.sum_tolerance) messages.push("weights sum to " + sum.toPrecision(3) + ", far from 1: the components are too far apart or too narrow to interpolate this goal");
    if (residual > tol.residual_tolerance) messages.push("relative residual " + residual.toPrecision(2) + ": the goal's reward lies far from the span of the components'");
    if (condition > tol.condition_limit) messages.push("Gram condition number " + condition.toPrecision(3) + ": weights sensitive to rounding");
    return { weights: weights, residual: residual, condition: condition, method: method, messages: messages };
  }

  // =================================================================== the page
  const state = {
    weights: DATA.initial.weights.slice(), x0: DATA.initial.state.slice(), t: DATA.initial.time,
    goal: null, projection: null, mode: "start",
  };
  const params = new URLSearchParams(location.search);
  function numbers(text, what, count) {
    const v = text.split(",").map((s) => Number(s.trim()));
    if (v.length !== count || !v.every(Number.isFinite)) throw new Error(what + " must be " + count + " comma-separated numbers, got " + JSON.stringify(text));
    return v;
  }
  const $ = (id) => document.getElementById(id);
  const probe = { error: null };
  try {
    if (params.has("weights") && params.has("goal")) throw new Error("give either weights= or goal=, not both");
    if (params.has("weights")) state.weights = checkWeights(numbers(params.get("weights"), "weights", n));
    if (params.has("goal")) {
      state.goal = numbers(params.get("goal"), "goal", d);
      state.projection = project(state.goal);
      state.weights = state.projection.weights.slice();
    }
    if (params.has("state")) state.x0 = numbers(params.get("state"), "state", d);
    if (params.has("time")) state.t = checkTime(Number(params.get("time")));
    checkWeights(state.weights);
  } catch (err) {
    probe.error = err.message;
  }
  if (probe.error === null) {
    try {
      const e = evaluate(state.weights, state.x0, state.t);
      const finite = (v) => (Number.isFinite(v) ? v : null);
      $("probe").textContent = JSON.stringify({ value: finite(e.value), policy: e.policy.map(finite), alpha: e.alpha.map(finite) });
    } catch (err) { probe.error = err.message; }
  }
  if (probe.error !== null) $("probe").textContent = JSON.stringify({ error: probe.error });

  // ---------------------------------------------------------------- drawing
  function lut(hex) {
    const out = new Uint8Array(hex.length / 2);
    for (let i = 0; i < out.length; i++) out[i] = parseInt(hex.substr(2 * i, 2), 16);
    return out;
  }
  const CMAP = { value: lut(DATA.colormaps.value), policy: lut(DATA.colormaps.policy) };
  const COLORS = ["#e8702a", "#2a9de8", "#d63fb8", "#35b26b", "#e8c12a", "#8a5cf0", "#e84a4a", "#4ac8c8"];
  const [RW, RH] = DATA.raster;
  const pixelStates = [];
  for (let py = 0; py < RH; py++) for (let px = 0; px < RW; px++) {
    pixelStates.push([lo[0] + (px + 0.5) / RW * (hi[0] - lo[0]), hi[1] - (py + 0.5) / RH * (hi[1] - lo[1])]);
  }
  // per component and pixel: z~_i and (B^T grad z)~_i at the current time (weights-independent)
  const fieldZ = comps.map(() => new Float64Array(RW * RH));
  const fieldG = comps.map(() => new Float64Array(RW * RH * m));
  let fieldTws = null;
  function computeFields() {
    fieldTws = timeWeights(state.t);
    const g = new Float64Array(m);
    for (let i = 0; i < n; i++) {
      for (let p = 0; p < pixelStates.length; p++) {
        fieldZ[i][p] = componentFields(comps[i], fieldTws[i], pixelStates[p], g);
        for (let r = 0; r < m; r++) fieldG[i][p * m + r] = g[r];
      }
    }
  }
  const valueImg = new Float64Array(RW * RH), policyImg = new Float64Array(RW * RH);
  function combineFields() { // v and u_1 on the raster for the current weights
    const sf = scaleFactors(fieldTws, state.weights);
    const g = new Float64Array(m);
    for (let p = 0; p < valueImg.length; p++) {
      let z = 0;
      g.fill(0);
      for (let i = 0; i < n; i++) {
        z += sf.f[i] * fieldZ[i][p];
        for (let r = 0; r < m; r++) g[r] += sf.f[i] * fieldG[i][p * m + r];
      }
      valueImg[p] = z > 0 ? -lambda * (Math.log(z) + sf.L) : NaN;
      let s = 0;
      for (let q = 0; q < m; q++) s += g[q] * Rinv[0][q];
      policyImg[p] = z > 0 ? lambda * s / z : NaN;
    }
  }
  function quantile(arr, q) { // of every 3rd entry: the colour range, not a statistic
    const v = new Float64Array(Math.ceil(arr.length / 3));
    let k = 0;
    for (let p = 0; p < arr.length; p += 3) if (Number.isFinite(arr[p])) v[k++] = arr[p];
    const sorted = v.subarray(0, k).sort();
    return k ? sorted[Math.min(k - 1, Math.floor(q * (k - 1)))] : NaN;
  }
  const MARGIN = { left: 44, right: 62, top: 22, bottom: 36 };
  function mapGeometry(canvas) {
    return { x: MARGIN.left, y: MARGIN.top, w: canvas.width - MARGIN.left - MARGIN.right,
      h: canvas.height - MARGIN.top - MARGIN.bottom };
  }
  function toScreen(geo, x) {
    return [geo.x + (x[0] - lo[0]) / (hi[0] - lo[0]) * geo.w, geo.y + (hi[1] - x[1]) / (hi[1] - lo[1]) * geo.h];
  }
  function niceTicks(a, b, count) {
    const span = b - a, raw = span / count, mag = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 2.5, 5, 10].map((s) => s * mag).find((s) => s >= raw);
    const out = [];
    for (let v = Math.ceil(a / step) * step; v <= b + 1e-9 * span; v += step) out.push(Math.abs(v) < 1e-12 * span ? 0 : v);
    return out;
  }
  const offscreen = document.createElement("canvas");
  offscreen.width = RW; offscreen.height = RH;
  function drawMap(canvas, img, cmap, range, label) {
    const ctx = canvas.getContext("2d"), geo = mapGeometry(canvas);
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    const octx = offscreen.getContext("2d"), data = octx.createImageData(RW, RH);
    const [a, b] = range;
    for (let p = 0; p < img.length; p++) {
      const v = img[p];
      if (!Number.isFinite(v)) { data.data.set([128, 128, 128, 255], 4 * p); continue; }
      const c = Math.max(0, Math.min(255, Math.round((v - a) / (b - a) * 255)));
      data.data[4 * p] = cmap[3 * c]; data.data[4 * p + 1] = cmap[3 * c + 1];
      data.data[4 * p + 2] = cmap[3 * c + 2]; data.data[4 * p + 3] = 255;
    }
    octx.putImageData(data, 0, 0);
    ctx.imageSmoothingEnabled = true;
    ctx.drawImage(offscreen, geo.x, geo.y, geo.w, geo.h);
    // axes
    ctx.strokeStyle = "#333"; ctx.lineWidth = 1; ctx.strokeRect(geo.x, geo.y, geo.w, geo.h);
    ctx.fillStyle = "#222"; ctx.font = "12px system-ui, sans-serif";
    ctx.textAlign = "center"; ctx.textBaseline = "top";
    for (const v of niceTicks(lo[0], hi[0], 6)) {
      const sx = toScreen(geo, [v, lo[1]])[0];
      ctx.fillRect(sx, geo.y + geo.h, 1, 4); ctx.fillText(fmt(v), sx, geo.y + geo.h + 5);
    }
    ctx.fillText(axisLabel(0) + " →", geo.x + geo.w / 2, geo.y + geo.h + 19);
    ctx.textAlign = "right"; ctx.textBaseline = "middle";
    for (const v of niceTicks(lo[1], hi[1], 6)) {
      const sy = toScreen(geo, [lo[0], v])[1];
      ctx.fillRect(geo.x - 4, sy, 4, 1); ctx.fillText(fmt(v), geo.x - 6, sy);
    }
    ctx.textAlign = "left"; ctx.textBaseline = "bottom"; ctx.fillText("↑ " + axisLabel(1), 4, geo.y - 5);
    // colour bar
    const cx = geo.x + geo.w + 12, cw = 12;
    for (let r = 0; r < geo.h; r++) {
      const c = Math.round((1 - r / (geo.h - 1)) * 255);
      ctx.fillStyle = "rgb(" + cmap[3 * c] + "," + cmap[3 * c + 1] + "," + cmap[3 * c + 2] + ")";
      ctx.fillRect(cx, geo.y + r, cw, 1);
    }
    ctx.strokeStyle = "#333"; ctx.strokeRect(cx, geo.y, cw, geo.h);
    ctx.fillStyle = "#222"; ctx.textAlign = "left"; ctx.textBaseline = "middle";
    for (const v of niceTicks(a, b, 5)) {
      const sy = geo.y + (b - v) / (b - a) * geo.h;
      ctx.fillRect(cx + cw, sy, 3, 1); ctx.fillText(fmt(v), cx + cw + 5, sy);
    }
    ctx.textAlign = "left"; ctx.textBaseline = "bottom"; ctx.fillText(label, cx, geo.y - 5);
    drawOverlay(ctx, geo);
  }
  function axisLabel(k) {
    const a = axes[k], units = DATA.system.name === "Pendulum" ? ["θ (rad from upright)", "ω (rad/s)"] : ["position", "velocity"];
    return a.name && !["theta", "omega", "position", "velocity"].includes(a.name) ? a.name : units[k];
  }
  function fixed(v, digits) { // toFixed without "-0.000"
    const text = v.toFixed(digits);
    return Number(text) === 0 ? (0).toFixed(digits) : text;
  }
  function fmt(v) {
    if (v === 0) return "0";
    const a = Math.abs(v);
    return a >= 1000 || a < 0.01 ? v.toExponential(1) : Number(v.toPrecision(3)).toString();
  }
  let roll = null;
  function drawOverlay(ctx, geo) {
    ctx.save();
    ctx.beginPath(); ctx.rect(geo.x, geo.y, geo.w, geo.h); ctx.clip();
    // component goals
    comps.forEach((c, i) => {
      if (c.cost === null) return;
      const [sx, sy] = toScreen(geo, clampState(c.cost.center));
      ctx.fillStyle = COLORS[i % COLORS.length]; ctx.strokeStyle = "#fff"; ctx.lineWidth = 1.5;
      ctx.beginPath(); ctx.moveTo(sx, sy - 7); ctx.lineTo(sx + 7, sy); ctx.lineTo(sx, sy + 7); ctx.lineTo(sx - 7, sy); ctx.closePath();
      ctx.fill(); ctx.stroke();
    });
    if (state.goal) {
      const [sx, sy] = toScreen(geo, clampState(state.goal));
      ctx.strokeStyle = "#fff"; ctx.lineWidth = 2.5;
      ctx.beginPath(); ctx.moveTo(sx - 8, sy - 8); ctx.lineTo(sx + 8, sy + 8); ctx.moveTo(sx + 8, sy - 8); ctx.lineTo(sx - 8, sy + 8); ctx.stroke();
    }
    if (roll) {
      ctx.beginPath();
      let prev = null;
      for (const x of roll.states) {
        const p = toScreen(geo, clampState(x));
        // break the line where a periodic coordinate wrapped
        if (prev === null || Math.abs(x[0] - prev[0]) > 0.5 * (hi[0] - lo[0]) || Math.abs(x[1] - prev[1]) > 0.5 * (hi[1] - lo[1])) ctx.moveTo(p[0], p[1]);
        else ctx.lineTo(p[0], p[1]);
        prev = x;
      }
      ctx.lineJoin = "round";
      ctx.strokeStyle = "#fff"; ctx.lineWidth = 4.5; ctx.stroke(); // halo: visible on any colour
      ctx.strokeStyle = "#111"; ctx.lineWidth = 2; ctx.stroke();
      const s0 = toScreen(geo, clampState(roll.states[0])), s1 = toScreen(geo, clampState(roll.states[roll.states.length - 1]));
      ctx.lineWidth = 2; ctx.strokeStyle = "#fff"; ctx.fillStyle = "#000";
      ctx.beginPath(); ctx.arc(s0[0], s0[1], 5.5, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      ctx.fillStyle = "#fff"; ctx.beginPath(); ctx.arc(s1[0], s1[1], 5, 0, 2 * Math.PI); ctx.fill();
      ctx.strokeStyle = "#000"; ctx.lineWidth = 1; ctx.stroke();
    }
    ctx.restore();
  }
  function clampState(x) {
    return x.map((v, k) => (periodic[k] ? lo[k] + pyMod(v - lo[k], period[k]) : Math.min(Math.max(v, lo[k]), hi[k])));
  }
  function drawChart() {
    const canvas = $("rollout-chart"), ctx = canvas.getContext("2d");
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    if (!roll || roll.alphas.length === 0) return;
    const left = 50, right = 20, gap = 26, top = 8, bottom = 30;
    const w = canvas.width - left - right, h = (canvas.height - top - bottom - gap) / 2;
    const t0 = roll.times[0], t1 = T;
    const sx = (t) => left + (t - t0) / Math.max(t1 - t0, 1e-12) * w;
    const us = roll.controls.map((u) => u[0]);
    let umin = Math.min(0, ...us), umax = Math.max(0, ...us);
    if (umax - umin < 1e-9) { umin -= 1; umax += 1; }
    const panels = [{ y: top, lo: 0, hi: 1, label: "α" }, { y: top + h + gap, lo: umin, hi: umax, label: "u" }];
    ctx.font = "12px system-ui, sans-serif";
    for (const pn of panels) {
      const sy = (v) => pn.y + (pn.hi - v) / (pn.hi - pn.lo) * h;
      ctx.strokeStyle = "#333"; ctx.lineWidth = 1; ctx.strokeRect(left, pn.y, w, h);
      ctx.fillStyle = "#222"; ctx.textAlign = "right"; ctx.textBaseline = "middle";
      for (const v of niceTicks(pn.lo, pn.hi, 3)) { ctx.fillRect(left - 4, sy(v), 4, 1); ctx.fillText(fmt(v), left - 6, sy(v)); }
      ctx.save(); ctx.translate(12, pn.y + h / 2); ctx.rotate(-Math.PI / 2); ctx.textAlign = "center"; ctx.fillText(pn.label, 0, 0); ctx.restore();
      pn.sy = sy;
    }
    ctx.textAlign = "center"; ctx.textBaseline = "top";
    for (const v of niceTicks(t0, t1, 8)) { const x = sx(v); ctx.fillRect(x, canvas.height - bottom, 1, 4); ctx.fillText(fmt(v), x, canvas.height - bottom + 5); }
    ctx.fillText("time t (s)", left + w / 2, canvas.height - 14);
    const ts = roll.times.slice(0, roll.alphas.length);
    for (let i = 0; i < n; i++) {
      ctx.strokeStyle = COLORS[i % COLORS.length]; ctx.lineWidth = 2; ctx.beginPath();
      ts.forEach((t, k) => { const y = panels[0].sy(Math.min(Math.max(roll.alphas[k][i], -0.05), 1.05)); if (k) ctx.lineTo(sx(t), y); else ctx.moveTo(sx(t), y); });
      ctx.stroke();
    }
    ctx.strokeStyle = "#888"; ctx.setLineDash([4, 3]); ctx.beginPath();
    ctx.moveTo(left, panels[1].sy(0)); ctx.lineTo(left + w, panels[1].sy(0)); ctx.stroke(); ctx.setLineDash([]);
    ctx.strokeStyle = "#1d2330"; ctx.lineWidth = 2; ctx.beginPath();
    ts.forEach((t, k) => { const y = panels[1].sy(us[k]); if (k) ctx.lineTo(sx(t), y); else ctx.moveTo(sx(t), y); });
    ctx.stroke();
  }

  // ------------------------------------------------------------ the controls
  function weightControls() {
    const box = $("weights");
    comps.forEach((c, i) => {
      const div = document.createElement("div");
      div.className = "weight";
      div.innerHTML = '<div class="name"><span class="swatch" style="background:' + COLORS[i % COLORS.length] +
        '"></span><span></span></div><div class="row"><input type="range" min="-1" max="3" step="0.01">' +
        '<input type="number" step="0.01"></div>';
      div.querySelector(".name span:last-child").textContent = c.label;
      const slider = div.querySelector("input[type=range]"), box2 = div.querySelector("input[type=number]");
      slider.addEventListener("input", () => { setWeight(i, Number(slider.value)); });
      box2.addEventListener("change", () => { setWeight(i, Number(box2.value)); });
      box.appendChild(div);
      c.slider = slider; c.box = box2;
    });
  }
  function showWeights() {
    comps.forEach((c, i) => {
      c.slider.value = String(state.weights[i]);
      const v = state.weights[i];
      c.box.value = Math.abs(v) < 5e-4 ? "0" : v.toFixed(3);
    });
  }
  function setWeight(i, v) {
    if (!Number.isFinite(v)) return;
    state.weights[i] = v;
    state.goal = null; state.projection = null;
    showWeights(); update(false);
  }
  function update(timeChanged) {
    const status = $("status");
    try { checkWeights(state.weights); } catch (err) {
      status.textContent = err.message; status.className = "note warn"; return;
    }
    status.textContent = ""; status.className = "note";
    const t0 = performance.now();
    if (timeChanged || fieldTws === null) computeFields();
    const t1 = performance.now();
    combineFields();
    const t2 = performance.now();
    const vr = [quantile(valueImg, 0), quantile(valueImg, 0.98)];
    if (!(vr[1] > vr[0])) vr[1] = vr[0] + 1;
    const ul = quantile(policyImg.map(Math.abs), 0.99) || 1;
    const t3 = performance.now();
    roll = rollout(state.weights, state.x0, state.t);
    const t4 = performance.now();
    const grey = valueImg.some((v) => !Number.isFinite(v));
    $("grey-note").textContent = grey ? "Grey: the embedded desirability is zero there (below float32's range, v more than 103λ above its minimum, or Σ w_i z_i ≤ 0 with negative weights): value +∞, policy undefined." : "";
    drawMap($("value-map"), valueImg, CMAP.value, vr, "v");
    drawMap($("policy-map"), policyImg, CMAP.policy, [-ul, ul], "u");
    drawChart();
    showReadout();
    showProjection();
    const t5 = performance.now();
    return { fields: t1 - t0, combine: t2 - t1, colour_range: t3 - t2, rollout: t4 - t3, draw: t5 - t4, total: t5 - t0 };
  }
  function showReadout() {
    const e = evaluate(state.weights, state.x0, state.t);
    const x = state.x0.map((v) => v.toFixed(3)).join(", ");
    const end = roll.states[roll.states.length - 1].map((v) => v.toFixed(3)).join(", ");
    let html = "<table><tr><td>state x</td><td>(" + x + "), t = " + state.t.toFixed(3) + "</td></tr>" +
      "<tr><td>value v</td><td>" + (Number.isFinite(e.value) ? e.value.toFixed(4) : "∞ (z underflowed)") + "</td></tr>" +
      "<tr><td>policy u</td><td>" + e.policy.map((v) => v.toFixed(4)).join(", ") + "</td></tr>";
    e.alpha.forEach((a, i) => {
      html += '<tr><td><span class="swatch" style="background:' + COLORS[i % COLORS.length] + '"></span> α<sub>' + (i + 1) + "</sub></td><td>" + fixed(a, 4) + "</td></tr>";
    });
    html += "<tr><td>rollout ends</td><td>(" + end + ") at t = " + roll.times[roll.states.length - 1].toFixed(2) + "</td></tr>";
    if (roll.complete && Number.isFinite(roll.cost)) html += "<tr><td>its cost</td><td>" + roll.cost.toFixed(4) + " (noise-free; v is the expected cost with noise)</td></tr>";
    if (roll.message) html += '<tr><td colspan="2" class="warn">' + roll.message + "</td></tr>";
    $("readout").innerHTML = html + "</table>";
  }
  function showProjection() {
    const box = $("projection");
    if (!state.projection) { box.textContent = quadraticCosts ? "" : "(projection needs quadratic terminal costs)"; return; }
    const p = state.projection;
    box.innerHTML = "goal (" + state.goal.map((v) => v.toFixed(3)).join(", ") + "): weights " +
      p.weights.map((v) => fixed(v, 3)).join(", ") + ", Σw = " + p.weights.reduce((a, v) => a + v, 0).toFixed(3) +
      ", residual " + p.residual.toPrecision(2) + " (" + p.method + ")" +
      p.messages.map((s) => '<br><span class="warn">' + s + "</span>").join("");
  }
  function stateAt(canvas, event) {
    const rect = canvas.getBoundingClientRect(), geo = mapGeometry(canvas);
    const px = (event.clientX - rect.left) * canvas.width / rect.width, py = (event.clientY - rect.top) * canvas.height / rect.height;
    if (px < geo.x || px > geo.x + geo.w || py < geo.y || py > geo.y + geo.h) return null;
    return [lo[0] + (px - geo.x) / geo.w * (hi[0] - lo[0]), hi[1] - (py - geo.y) / geo.h * (hi[1] - lo[1])];
  }
  function onClick(event) {
    const x = stateAt(event.currentTarget, event);
    if (x === null) return;
    if (state.mode === "goal") {
      try {
        state.projection = project(x); state.goal = x; state.weights = state.projection.weights.slice();
        showWeights();
      } catch (err) { $("status").textContent = err.message; return; }
    } else {
      state.x0 = x;
    }
    update(false);
  }

  function init() {
    weightControls();
    showWeights();
    const time = $("time");
    time.max = String(T); time.step = String(T / 1000); time.value = String(state.t);
    time.disabled = DATA.stationary;
    const showTime = () => {
      $("time-label").textContent = DATA.stationary ? "first exit: no time (the task ends at the exit set)" : "t = " + state.t.toFixed(3) + " s";
    };
    showTime();
    time.addEventListener("input", () => { state.t = Number(time.value); showTime(); update(true); });
    $("all-ones").addEventListener("click", () => { state.weights = comps.map(() => 1); state.goal = null; state.projection = null; showWeights(); update(false); });
    for (const r of document.querySelectorAll("input[name=mode]")) r.addEventListener("change", () => { state.mode = r.value; });
    $("value-map").addEventListener("click", onClick);
    $("policy-map").addEventListener("click", onClick);
    const sc = DATA.state_cost === null ? "none" : "q(x) included";
    $("about").innerHTML = DATA.system.name + " " + JSON.stringify(DATA.system.parameters).replace(/"/g, "") +
      (DATA.stationary ? "; first exit (rollouts stop at the exit set, or after " + T + " s)" : "; horizon T = " + T + " s") + ", temperature λ = " + lambda + ", R = " + JSON.stringify(R) + ", state cost: " + sc +
      ". Embedded: " + DATA.embedding + ". The page computes exactly what <code>gridlbc.combine</code> computes on these data" +
      " (grey on a map: desirability underflowed). Rollout: noise-free Euler steps of T/" + DATA.rollout_steps + ", as <code>gridlbc.simulate(..., noise=False)</code>." +
      (DATA.note ? " " + DATA.note : "");
    if (probe.error !== null) { $("status").textContent = "query: " + probe.error; $("status").className = "note warn"; }
    const first = update(true);
    const timing = { decode_ms: decodeMs, first_render_ms: first ? first.total : null };
    const repeats = Number(params.get("bench") || 0);
    if (repeats > 0 && first) { // recompute the heat maps: new weights, and a new time
      const w0 = state.weights.slice(), tq = state.t, samples = { combine: [], time: [] };
      for (let r = 0; r < repeats; r++) {
        state.weights = w0.map((v, i) => v * (1 + 0.01 * (r + 1) * (i + 1)));
        samples.combine.push(update(false));
        state.t = T * (r + 1) / (repeats + 2);
        samples.time.push(update(true));
      }
      state.weights = w0; state.t = tq;
      const median = (a) => a.slice().sort((x, y) => x - y)[Math.floor(a.length / 2)];
      const summary = (list) => Object.fromEntries(Object.keys(list[0]).map((k) => [k, median(list.map((o) => o[k]))]));
      timing.weights_change_ms = summary(samples.combine);
      timing.time_change_ms = summary(samples.time);
      timing.repeats = repeats;
      timing.raster = [RW, RH];
      update(true);
    }
    $("timing").textContent = JSON.stringify(timing);
    const r = roll;
    $("probe-details").textContent = JSON.stringify({
      weights: state.weights, state: state.x0, time: state.t,
      projection: state.projection,
      rollout: { final_state: r.states[r.states.length - 1], cost: Number.isFinite(r.cost) ? r.cost : null, steps: r.steps, complete: r.complete },
    });
  }
  init();
})();
