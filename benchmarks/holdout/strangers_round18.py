"""Stranger round 18: kinds of problem rounds 3–17 did not cover, posed as a new user would with
the public API (SPEC §1–3, §6, §9–10):

- time encoded as a state axis with ṡ = 1 (no control, no noise): tracking a moving target
  (``track_time_axis``, λ = 0.3; ``track_cold``, λ = 0.01; ``track_long``, T = 20, ten periods;
  ``track_time_4d``, beside a point mass, 4-D), an impulse in time a sixth of an s-cell wide
  (``time_pulse``), a cost that switches on in time between the s-nodes (``time_cliff``, and in
  the phase pair's blind spot next to the axis centre, ``time_cliff_blind``), a deadline as a
  first exit through a line on a periodic clock axis (``fe_deadline``), and the average cost of
  a periodic task with the clock on a periodic axis (``avg_clock``);
- a parameter as a frozen state axis (k̇ = 0: a family of springs from unstable to stiff,
  ``param_axis``);
- plateaus and cliffs (step functions) in the state cost, between the nodes (``cliff_plateau``
  λ = 0.1, ``cliff_cold`` λ = 0.01, a first exit across a cliff band ``fe_cliff_band``);
- very long horizons against the dynamics' time scale (``long_lq``, T = 80 = 160 time scales;
  ``long_saturation``, T = 30 with saturating stable and unstable drifts);
- an anisotropic 3-D grid, spacings 3000× apart (``aniso_3d``);
- control cost ≫ state cost (R = 200, ``rcost_huge``);
- λ = 2.9 in 3-D (``hot_3d``), λ = 0.01 and 0.005 (``cliff_cold``, ``track_cold``,
  ``hopf_frozen``, ``sliding_frozen``);
- exit sets that are lines on a periodic axis (``exit_line_torus``, ``_cold``; a slab 2.2 cells
  wide centred between nodes, ``exit_line_between``);
- 1-D problems embedded in 3-D and 4-D (idle axes with rotation and noise, no cost:
  ``embedded_1d_3d``, ``embedded_1d_4d``, idle axes of 5 nodes ``embedded_idle5``);
- strongly nonlinear drifts: a Hopf limit cycle (``hopf`` λ = 0.3, ``_cold`` 0.05, ``_frozen``
  0.01, ``_stiff`` ṙ = 15 r(1 − r²)), a sliding-mode (bang-bang) pull ẋ₀ = −2 tanh((x₀ −
  0.37)/w) (``sliding_mode`` λ = 0.1, ``_cold`` 0.02, ``_frozen`` 0.005, ``sliding_wide`` w = h,
  ``sliding_node`` switch on a node, ``sliding_3d``), a smooth stiff pull for contrast
  (``stiff_pull``, −30 (x₀ − 0.37));
- ``gridlbc.combine`` with weights 10⁻⁵ and 10⁵ (``combo_extreme``, solve_many first exits) and
  10⁻³ and 10³ of saved-and-loaded solutions (``combo_loaded``);
- ``save``/``load`` round trips re-reading the estimate (``*_loaded``).

Not run by the tests. Layout as rounds 16–17 (``P18``: name → (builder, states, truth, tag));
round 16's command line and ``table16`` (round 12's runner, ``--levels``/``--finer``, round 13's
``--tol``, round 15's ``quick``) pointed at this round's problems and results folder;
``combo_*`` run through round 13's ``save_combination``, ``*_loaded`` through ``saveload_run``.
"w": any ``gridlbc.GridlbcWarning``; "abs" = ê/|v − v*| in absolute terms.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round18.py NAME [NAME ...]
    ... --truth NAME ... | --levels NAME ... | --finer NAME ... | --tol NAME ... | --table
    ... --check      (the truths' second methods)

Truths ("tag"), none from the library's grid solvers:

- "ricc": closed-loop Riccati ODEs (round 15's ``riccati``/``ricc_truth``; ``tracker_1d``, my own
  time-varying LQ tracker −Ṗ = 2aP − P²/R + 2W(t), −ṗ = (a − P/R)p − 2W(t)c(t), −ċ₀ = −p²/2R +
  λP/2R + W c², LSODA rtol 1e-11, max_step 1e-3 across pulses and cliffs in time; round 16's
  ``lq_affine`` for the combination). The time-axis problems are exact because s₀ + t is
  deterministic; ``fe_deadline`` is the horizon problem with T = (−x₀) mod 2π.
- "exact": ``torus_line_truth`` (exponentials on the circle cut at the exit), ``clock_parts`` (the
  periodic LQ tracker in closed form: P = √(2W), p = A sin s + B cos s, c = 0.5), round 17's
  ``cos_series_exit`` for ``combo_extreme``.
- "1-D": separable sums of 1-D solves: round 13's ``cn_1d`` (Crank–Nicolson, 20 001 / 40 001
  nodes) or, where CN rings below zero (cold, narrow or long), my own ``be_1d`` (monotone
  backward Euler, upwind, renormalised each step, Richardson in Δt, 20 001 / 40 001 nodes);
  ``radial_cn`` (my own CN in r for the radial Hopf problems, 8001 / 16 001 nodes).
- "bvp": round 13's ``bvp_1d`` (``fe_cliff_band``).

Checks of the truths (2026-12-06, ``--check`` and by hand): ``tracker_1d`` equals my own
``cn_td`` (CN with a time-dependent q) to 2e-6 on track_time_axis (4001 → 8001 nodes:
1.532424/3.945220/4.102505 against 1.532425/3.945219/4.102511) and on the pulse (2.80625 →
2.80458 → ODE 2.80403, second order); ``clock_parts`` against tracker_1d over T = 10π, 12π (c =
0.5 exactly; v − cT − h one constant, 0.10387962, at five states); ``torus_line_truth`` equals my
own central differences (200 001 nodes) to 1e-8; ``be_1d`` on sliding_frozen's x₀ at 40 001 /
80 001 nodes and 4× the steps moves by 3e-4 (1.40641 → 1.40667) — the tabled ± is conservative;
``well_between`` first had CN's truth, which rang below zero (NaN at two states): replaced by
be_1d before any judgement. ``hopf_stiff``'s centre is confirmed by the library's own 201² solve
(0.4586 on 101², 0.4649 on 201², truth 0.4680).

Run (library of commit 1e25207, 2026-12-06, one thread; ``--table``)::

    problem             state                  predicted     truth   tag      ±    error     est est/err    abs  w wc   t/s
    track_time_axis     [0.3, 0.0]                1.5298    1.5324  ricc  0.00%   -0.17%   0.42%    2.48   2.47  n      0.3
    track_time_axis     [-1.0, 0.7]               3.9335    3.9452  ricc  0.00%   -0.30%   0.68%    2.30   2.29  n      0.3
    track_time_axis     [1.2, 1.5]                4.0946    4.1025  ricc  0.00%   -0.19%   0.46%    2.40   2.39  n      0.3
    track_time_axis     [0.0, 1.1]                1.3704    1.3736  ricc  0.00%   -0.24%   0.57%    2.41   2.41  n      0.3
    track_time_4d       [0.5, -0.5, 0.3, 0.0]     1.1645    1.0561  ricc  0.00%  +10.27%  21.96%    2.14   2.36  Y      6.9
    track_time_4d       [-1.0, 1.0, -0.8, 0.8]    4.3562    4.2569  ricc  0.00%   +2.33%   2.36%    1.01   1.04  Y      6.9
    track_time_4d       [0.2, 0.4, 1.0, 2.0]      2.2042    2.1612  ricc  0.00%   +1.99%  17.28%    8.68   8.85  Y      6.9
    cliff_plateau       [0.0, 0.0]                0.5116    0.5118   1-D  0.00%   -0.05%   2.57%   49.74  49.71  Y      0.7
    cliff_plateau       [-0.8, 0.5]               1.3747    1.3678   1-D  0.01%   +0.51%   9.84%   19.34  19.44  Y      0.7
    cliff_plateau       [1.0, -1.0]               1.7142    1.7072   1-D  0.01%   +0.41%   8.39%   20.58  20.66  Y      0.7
    cliff_plateau       [0.6, 0.3]                0.6352    0.6360   1-D  0.00%   -0.12%  11.13%   91.40  91.29  Y      0.7
    cliff_cold          [0.0, 0.0]                0.4543    0.4543   1-D  0.00%   -0.00%  63.74% 88553.35 88552.72  Y      0.2
    cliff_cold          [-0.8, 0.5]               1.1264    1.1413   1-D  0.01%   -1.30%  46.00%   35.39  34.93  Y      0.2
    cliff_cold          [1.0, -1.0]               1.4657    1.4807   1-D  0.01%   -1.01%  38.49%   38.07  37.68  Y      0.2
    cliff_cold          [0.6, 0.3]                0.4950    0.4982   1-D  0.00%   -0.64%  88.52%  139.18 138.29  Y      0.2
    long_lq             [0.0, 0.0]               13.9686   14.0280  ricc  0.00%   -0.42%   0.83%    1.96   1.95  n     21.3
    long_lq             [1.5, -1.0]              14.5006   14.5608  ricc  0.00%   -0.41%   0.80%    1.94   1.93  n     21.3
    long_lq             [-2.0, 2.0]              15.1461   15.2082  ricc  0.00%   -0.41%   0.76%    1.87   1.86  n     21.3
    long_saturation     [0.0, 0.0]               38.0264   38.2068   1-D  0.22%   -0.47%   1.61%    3.41   3.39  n      6.1
    long_saturation     [1.0, 0.5]               38.4510   38.6670   1-D  0.22%   -0.56%   1.66%    2.97   2.95  n      6.1
    long_saturation     [-1.5, -1.2]             41.5766   41.7945   1-D  0.20%   -0.52%   1.61%    3.09   3.07  n      6.1
    aniso_3d            [0.0, 0.3, -10.0]         1.2796    1.2744  ricc  0.00%   +0.41%   1.91%    4.67   4.69  n      2.3
    aniso_3d            [-0.01, -1.0, 20.0]       2.1102    2.1015  ricc  0.00%   +0.41%   1.46%    3.54   3.56  n      2.3
    aniso_3d            [0.01, 0.8, 5.0]          2.1085    2.1035  ricc  0.00%   +0.24%   1.07%    4.48   4.49  n      2.3
    rcost_huge          [0.5, 0.3]               12.1653   12.1894  ricc  0.00%   -0.20%   3.19%   16.10  16.07  n      0.7
    rcost_huge          [-1.0, 0.8]              10.8683   10.8895  ricc  0.00%   -0.19%   0.43%    2.19   2.19  n      0.7
    rcost_huge          [1.2, -1.2]              29.3259   29.3919  ricc  0.00%   -0.22%   0.25%    1.09   1.09  n      0.7
    hot_3d              [0.5, -0.5, 0.3]          5.7723    5.7627  ricc  0.00%   +0.17%   0.65%    3.86   3.86  n      5.1
    hot_3d              [-1.5, 1.0, 1.0]          7.8483    7.8964  ricc  0.00%   -0.61%   0.46%    0.75   0.75  n      5.1
    hot_3d              [2.0, 0.5, -1.5]          9.3669    9.4001  ricc  0.00%   -0.35%   0.42%    1.18   1.18  n      5.1
    exit_line_torus     [1.0, 0.0]                1.7501    1.7756 exact  0.00%   -1.43%   2.12%    1.48   1.46  n      0.1
    exit_line_torus     [-1.0, 2.0]               0.9638    0.9764 exact  0.00%   -1.29%   2.12%    1.65   1.63  n      0.1
    exit_line_torus     [2.8, -1.0]               2.6213    2.6575 exact  0.00%   -1.36%   2.12%    1.56   1.54  n      0.1
    exit_line_torus     [-0.3, 0.5]               0.4972    0.5024 exact  0.00%   -1.04%   2.56%    2.46   2.44  n      0.1
    exit_line_between   [1.0, 0.0]                1.5300    1.5450 exact  0.00%   -0.97%   1.52%    1.56   1.55  n      0.4
    exit_line_between   [-1.0, 2.0]               0.9272    0.9372 exact  0.00%   -1.06%   1.52%    1.44   1.42  n      0.4
    exit_line_between   [2.8, -1.0]               2.5847    2.6183 exact  0.00%   -1.28%   1.63%    1.27   1.25  n      0.4
    exit_line_between   [-0.3, 0.5]               0.4606    0.4632 exact  0.00%   -0.56%   1.74%    3.09   3.08  n      0.4
    embedded_1d_3d      [0.0, 0.5, -0.5]          0.5732    0.5731   1-D  0.00%   +0.02%   0.42%   17.68  17.69  n      3.7
    embedded_1d_3d      [-1.0, 1.0, 1.0]          2.2630    2.2693   1-D  0.00%   -0.28%   1.15%    4.15   4.14  n      3.7
    embedded_1d_3d      [1.2, -1.5, 0.3]          1.2441    1.2443   1-D  0.00%   -0.02%   0.36%   23.63  23.63  n      3.7
    embedded_1d_3d      [0.6, 0.0, 0.0]           0.6517    0.6513   1-D  0.00%   +0.05%   0.38%    6.92   6.93  n      3.7
    embedded_1d_4d      [0.0, 0.5, -0.5, 0.0]     0.5730    0.5731   1-D  0.00%   -0.02%   3.04%  129.68 129.65  Y      4.9
    embedded_1d_4d      [-1.0, 1.0, 1.0, -1.0]    2.2834    2.2693   1-D  0.00%   +0.62%   3.52%    5.65   5.68  Y      4.9
    embedded_1d_4d      [1.2, -1.5, 0.3, 0.7]     1.2423    1.2443   1-D  0.00%   -0.16%   0.84%    5.34   5.33  Y      4.9
    hopf                [0.0, 0.0]                0.9264    0.9278   1-D  0.00%   -0.15%   0.40%    2.70   2.69  n      2.1
    hopf                [1.0, 0.0]                0.4746    0.4760   1-D  0.01%   -0.31%   0.62%    2.00   1.99  n      2.1
    hopf                [0.5, -0.6]               0.5023    0.5038   1-D  0.01%   -0.28%   0.59%    2.09   2.09  n      2.1
    hopf                [-1.4, 1.0]               0.5908    0.5930   1-D  0.00%   -0.37%   0.57%    1.54   1.54  n      2.1
    hopf_cold           [0.0, 0.0]                0.8716    0.8731   1-D  0.00%   -0.17%   0.41%    2.38   2.38  n      1.1
    hopf_cold           [1.0, 0.0]                0.1764    0.1766   1-D  0.00%   -0.11%   1.82%   15.91  15.89  n      1.1
    hopf_cold           [0.5, -0.6]               0.2003    0.2006   1-D  0.00%   -0.16%   1.77%   11.21  11.19  n      1.1
    hopf_cold           [-1.4, 1.0]               0.3076    0.3089   1-D  0.00%   -0.41%   1.18%    2.85   2.84  n      1.1
    combo_extreme       [0.0, 0.0]                3.4899    3.4915 exact  0.00%   -0.04%   0.45%   10.17  10.16  n      4.7
    combo_extreme       [-0.5, 1.0]               4.2134    4.2294 exact  0.00%   -0.38%   0.43%    1.14   1.14  n      4.7
    combo_extreme       [0.2, -1.2]               3.3900    3.3938 exact  0.00%   -0.11%   0.16%    1.45   1.45  n      4.7
    combo_extreme       [-1.5, 0.4]               6.2884    6.3174 exact  0.00%   -0.46%   0.50%    1.09   1.08  n      4.7
    well_between        [0.0, 0.0]                2.0154    1.6554   1-D  0.26%  +21.75%  89.29%    4.11   5.00  Y      0.2
    well_between        [-0.4, 0.5]               2.1394    1.9715   1-D  0.22%   +8.52%  76.61%    9.00   9.76  Y      0.2
    well_between        [0.6, -1.0]               2.4123    2.2870   1-D  0.19%   +5.48%  68.53%   12.51  13.20  Y      0.2
    time_pulse          [0.0, 0.0]                0.4691    0.6907  ricc  0.00%  -32.09% 116.59%    3.63   2.47  Y      0.4
    time_pulse          [1.5, 0.5]                0.5568    0.6083  ricc  0.00%   -8.46%   3.71%    0.44   0.40  Y      0.4
    time_pulse          [-1.0, 0.9]               1.2391    2.8040  ricc  0.00%  -55.81%  97.19%    1.74   0.77  Y      0.4
    time_pulse          [0.5, 1.02]               0.3375    0.4456  ricc  0.00%  -24.26% 162.79%    6.71   5.08  Y      0.4
    time_cliff          [0.0, 0.0]                1.0922    1.0961  ricc  0.00%   -0.36%   4.07%   11.29  11.25  n      0.4
    time_cliff          [1.5, 0.5]                0.9116    0.9222  ricc  0.00%   -1.15%   1.95%    1.70   1.68  n      0.4
    time_cliff          [-1.0, 0.9]               4.3355    4.5802  ricc  0.00%   -5.34%  12.68%    2.37   2.25  n      0.4
    time_cliff          [0.5, 1.02]               1.0939    1.1039  ricc  0.00%   -0.91%   5.35%    5.90   5.85  n      0.4
    time_cliff_blind    [0.0, 0.5]                1.0270    1.0527  ricc  0.00%   -2.44%   2.16%    0.89   0.86  Y      0.4
    time_cliff_blind    [-1.0, 1.2]               2.9322    2.9589  ricc  0.00%   -0.90%   3.01%    3.34   3.31  Y      0.4
    time_cliff_blind    [2.0, 1.9]                2.1320    2.2583  ricc  0.00%   -5.59%   9.87%    1.77   1.67  Y      0.4
    time_cliff_blind    [0.5, 1.6]                1.1577    1.1671  ricc  0.00%   -0.81%   2.52%    3.10   3.08  Y      0.4
    sliding_cold        [0.0, 0.0]                1.2802    1.4208   1-D  0.21%   -9.90%   5.61%    0.57   0.51  Y      0.2
    sliding_cold        [0.37, 0.5]               1.3440    1.5036   1-D  0.20%  -10.62%   5.60%    0.53   0.47  Y      0.2
    sliding_cold        [1.5, -1.0]               1.7154    1.8303   1-D  0.16%   -6.28%   4.11%    0.66   0.61  Y      0.2
    sliding_cold        [-1.2, 0.3]               2.2816    2.3901   1-D  0.18%   -4.54%   4.11%    0.91   0.86  Y      0.2
    sliding_frozen      [0.0, 0.0]                1.1897    1.4097   1-D  0.86%  -15.61%   4.08%    0.26   0.22  n      0.4
    sliding_frozen      [0.37, 0.5]               1.2517    1.4934   1-D  0.81%  -16.18%   3.56%    0.22   0.18  n      0.4
    sliding_frozen      [1.5, -1.0]               1.6401    1.8195   1-D  0.67%   -9.86%   2.79%    0.28   0.26  n      0.4
    sliding_frozen      [-1.2, 0.3]               2.2058    2.3716   1-D  0.75%   -6.99%   2.79%    0.40   0.37  n      0.4
    sliding_wide        [0.0, 0.0]                1.2664    1.4103   1-D  0.86%  -10.20%   4.04%    0.40   0.36  n      0.7
    sliding_wide        [0.37, 0.5]               1.3340    1.4930   1-D  0.81%  -10.65%   4.15%    0.39   0.35  n      0.7
    sliding_wide        [1.5, -1.0]               1.6947    1.8184   1-D  0.67%   -6.80%   2.62%    0.38   0.36  n      0.7
    sliding_wide        [-1.2, 0.3]               2.2550    2.3722   1-D  0.75%   -4.94%   2.62%    0.53   0.50  n      0.7
    stiff_pull          [0.0, 0.0]                1.3855    1.3851   1-D  0.87%   +0.03%   0.10%    3.19   3.19  n      1.4
    stiff_pull          [0.37, 0.5]               1.4930    1.4927   1-D  0.81%   +0.02%   0.10%    5.86   5.86  n      1.4
    stiff_pull          [1.5, -1.0]               1.8432    1.8431   1-D  0.66%   +0.00%   0.08%   34.53  34.53  n      1.4
    stiff_pull          [-1.2, 0.3]               1.5032    1.5016   1-D  0.81%   +0.11%   0.10%    0.95   0.95  n      1.4
    sliding_node        [0.0, 0.0]                1.2277    1.4419   1-D  0.88%  -14.85%   2.10%    0.14   0.12  Y      0.4
    sliding_node        [0.37, 0.5]               1.2926    1.5284   1-D  0.83%  -15.43%   3.47%    0.22   0.19  Y      0.4
    sliding_node        [1.5, -1.0]               1.6804    1.8444   1-D  0.70%   -8.89%   2.10%    0.24   0.21  Y      0.4
    sliding_node        [-1.2, 0.3]               2.2416    2.3961   1-D  0.76%   -6.45%   2.10%    0.33   0.30  Y      0.4
    sliding_3d          [0.0, 0.0, 0.0]           1.2101    1.4202   1-D  0.42%  -14.79%   4.70%    0.32   0.27  Y      1.7
    sliding_3d          [0.37, 0.5, -0.5]         1.4006    1.6240   1-D  0.37%  -13.75%   4.98%    0.36   0.31  Y      1.7
    sliding_3d          [1.5, -1.0, 0.3]          1.7305    1.8732   1-D  0.32%   -7.62%   1.69%    0.22   0.20  Y      1.7
    sliding_3d          [-1.2, 0.3, 1.0]          2.7212    2.8680   1-D  0.31%   -5.12%   1.69%    0.33   0.31  Y      1.7
    exit_line_cold      [1.0, 0.0]                1.4298    1.7756 exact  0.00%  -19.47%  24.59%    1.26   1.02  Y      0.2
    exit_line_cold      [-1.0, 2.0]               0.6904    0.9764 exact  0.00%  -29.29%  42.57%    1.45   1.03  Y      0.2
    exit_line_cold      [2.8, -1.0]               1.6728    2.6576 exact  0.00%  -37.06%  66.52%    1.80   1.13  Y      0.2
    exit_line_cold      [-0.3, 0.5]               0.4149    0.5024 exact  0.00%  -17.43%  24.59%    1.41   1.16  Y      0.2
    track_long          [0.3, 0.0]               19.0144   19.6519  ricc  0.00%   -3.24%   5.22%    1.61   1.56  Y      3.5
    track_long          [-1.0, 1.7]              19.8983   20.5593  ricc  0.00%   -3.22%   5.60%    1.74   1.69  Y      3.5
    track_long          [1.2, 3.5]               22.1974   22.9615  ricc  0.00%   -3.33%   7.41%    2.23   2.15  Y      3.5
    track_long          [0.0, 2.2]               19.4313   20.0878  ricc  0.00%   -3.27%   6.34%    1.94   1.88  Y      3.5
    embedded_idle5      [0.0, 0.5, -0.5]          0.5732    0.5731   1-D  0.00%   +0.02%   0.42%   17.61  17.61  n      1.0
    embedded_idle5      [-1.0, 1.0, 1.0]          2.2630    2.2693   1-D  0.00%   -0.28%   1.14%    4.11   4.10  n      1.0
    embedded_idle5      [1.2, -1.5, 0.3]          1.2441    1.2443   1-D  0.00%   -0.02%   0.14%    9.28   9.28  n      1.0
    embedded_idle5      [0.6, 0.0, 0.0]           0.6517    0.6513   1-D  0.00%   +0.05%   0.14%    2.57   2.57  n      1.0
    hopf_frozen         [0.0, 0.0]                0.8928    0.8909   1-D  0.02%   +0.21%   0.46%    2.15   2.15  n      0.9
    hopf_frozen         [1.0, 0.0]                0.1253    0.1251   1-D  0.00%   +0.12%   2.44%   20.29  20.32  n      0.9
    hopf_frozen         [0.5, -0.6]               0.1476    0.1477   1-D  0.00%   -0.02%   2.44%  119.53 119.50  n      0.9
    hopf_frozen         [-1.4, 1.0]               0.2595    0.2607   1-D  0.00%   -0.46%   1.57%    3.43   3.41  n      0.9
    hopf_stiff          [0.0, 0.0]                0.4586    0.4680   1-D  0.00%   -2.00%   0.57%    0.28   0.28  n      5.8
    hopf_stiff          [1.0, 0.0]                0.2500    0.2500   1-D  0.00%   -0.01%   1.35%  146.00 145.99  n      5.8
    hopf_stiff          [0.5, -0.6]               0.2521    0.2521   1-D  0.00%   +0.00%   1.37%  522.77 522.78  n      5.8
    hopf_stiff          [-1.4, 1.0]               0.2597    0.2597   1-D  0.00%   +0.02%   1.37%   56.30  56.31  n      5.8
    track_cold          [0.3, 0.0]                0.9509    0.9524  ricc  0.00%   -0.16%   0.25%    1.60   1.59  Y      0.4
    track_cold          [-1.0, 0.7]               3.3546    3.3652  ricc  0.00%   -0.31%   0.45%    1.44   1.43  Y      0.4
    track_cold          [1.2, 1.5]                3.5157    3.5225  ricc  0.00%   -0.19%   0.29%    1.50   1.50  Y      0.4
    track_cold          [0.0, 1.1]                0.7915    0.7936  ricc  0.00%   -0.27%   0.40%    1.50   1.49  Y      0.4
    fe_deadline         [-1.0, 0.0]               0.9876    0.9690  ricc  0.00%   +1.92%   5.75%    3.00   3.06  Y      0.6
    fe_deadline         [-2.5, 1.5]               2.2203    2.3525  ricc  0.00%   -5.62%   6.14%    1.09   1.03  Y      0.6
    fe_deadline         [2.0, -1.0]               2.4983    2.5589  ricc  0.00%   -2.37%   3.59%    1.51   1.48  Y      0.6
    fe_deadline         [-0.3, 2.0]               1.5853    1.5355  ricc  0.00%   +3.24%   3.59%    1.11   1.14  Y      0.6
    avg_clock           c                         0.4932    0.5000 exact  0.00%   -1.35%   0.97%    0.72   0.71  Y  n   0.4
    avg_clock           h [0.5, 0.3]              0.0104    0.0141 exact  0.00%   -1.24%   3.83%    3.08   3.08  Y      0.4
    avg_clock           h [-1.0, 2.0]             2.4274    2.6344 exact  0.00%   -7.85%   9.48%    1.21   1.11  Y      0.4
    avg_clock           h [1.2, -2.5]             3.8434    4.0167 exact  0.00%   -4.31%   5.37%    1.24   1.19  Y      0.4
    param_axis          [0.5, -0.5, 0.25]         0.6626    0.6571  ricc  0.00%   +0.83%   1.77%    2.14   2.16  n      3.2
    param_axis          [-1.0, 1.0, 1.3]          1.3498    1.3436  ricc  0.00%   +0.46%   1.77%    3.84   3.86  n      3.2
    param_axis          [1.5, 0.8, 3.1]           3.7921    3.7910  ricc  0.00%   +0.03%   2.56%   88.38  88.41  n      3.2
    param_axis          [0.0, 2.0, -0.6]          4.3692    4.4100  ricc  0.00%   -0.92%   1.77%    1.92   1.90  n      3.2
    fe_cliff_band       [0.0, 0.0]                0.3404    0.3486   bvp  0.00%   -2.35%  11.83%    5.04   4.93  Y      1.4
    fe_cliff_band       [-0.5, 0.5]               0.9486    1.0279   bvp  0.00%   -7.71%  11.83%    1.53   1.42  Y      1.4
    fe_cliff_band       [-1.2, -1.0]              1.8076    2.0030   bvp  0.00%   -9.75%  12.57%    1.29   1.16  Y      1.4
    fe_cliff_band       [-1.9, 1.0]               2.3360    2.5430   bvp  0.00%   -8.14%  11.83%    1.45   1.33  Y      1.4
    combo_loaded        [100.0, -50.0]            0.0893    0.0900  ricc  0.00%   -0.28%   0.67%    2.37   2.37  n      7.5
    combo_loaded        [101.0, -49.5]            0.5382    0.5399  ricc  0.00%   -0.32%   0.34%    1.05   1.05  n      7.5
    combo_loaded        [98.5, -51.0]             1.8449    1.8485  ricc  0.00%   -0.20%   0.18%    0.93   0.92  n      7.5
    sliding_mode        [0.0, 0.0]                1.5013    1.4797   1-D  0.00%   +1.45%   3.26%    2.24   2.27  n      0.4
    sliding_mode        [0.37, 0.5]               1.5813    1.5586   1-D  0.00%   +1.46%   4.20%    2.88   2.92  n      0.4
    sliding_mode        [1.5, -1.0]               1.9009    1.8881   1-D  0.00%   +0.68%   2.55%    3.78   3.80  n      0.4
    sliding_mode        [-1.2, 0.3]               2.4889    2.4673   1-D  0.00%   +0.88%   2.55%    2.91   2.94  n      0.4
    well_between_loaded [0.0, 0.0]                2.0154    1.6554   1-D  0.26%  +21.75%  89.29%    4.11   5.00  Y      0.6
    well_between_loaded [-0.4, 0.5]               2.1394    1.9715   1-D  0.22%   +8.52%  76.61%    9.00   9.76  Y      0.6
    well_between_loaded [0.6, -1.0]               2.4123    2.2870   1-D  0.19%   +5.48%  68.53%   12.51  13.20  Y      0.6
    fe_cliff_band_loaded [0.0, 0.0]                0.3404    0.3486   bvp  0.00%   -2.35%  11.83%    5.04   4.93  Y      0.6
    fe_cliff_band_loaded [-0.5, 0.5]               0.9486    1.0279   bvp  0.00%   -7.71%  11.83%    1.53   1.42  Y      0.6
    fe_cliff_band_loaded [-1.2, -1.0]              1.8076    2.0030   bvp  0.00%   -9.75%  12.57%    1.29   1.16  Y      0.6
    fe_cliff_band_loaded [-1.9, 1.0]               2.3360    2.5430   bvp  0.00%   -8.14%  11.83%    1.45   1.33  Y      0.6

    150 pairs, 40 solves; > 10 % off silently: 4 [('sliding_frozen', 15.6), ('sliding_frozen',
    16.2), ('sliding_wide', 10.2), ('sliding_wide', 10.7)]; estimate < ½ the error above 2 %
    (relative, rounds 12–15): 17 [('time_pulse', 8.5, 3.7), ('sliding_frozen', 15.6, 4.1),
    ('sliding_frozen', 16.2, 3.6), ('sliding_frozen', 9.9, 2.8), ('sliding_frozen', 7.0, 2.8),
    ('sliding_wide', 10.2, 4.0), ('sliding_wide', 10.7, 4.2), ('sliding_wide', 6.8, 2.6),
    ('sliding_node', 14.9, 2.1), ('sliding_node', 15.4, 3.5), ('sliding_node', 8.9, 2.1),
    ('sliding_node', 6.4, 2.1), ('sliding_3d', 14.8, 4.7), ('sliding_3d', 13.8, 5.0),
    ('sliding_3d', 7.6, 1.7), ('sliding_3d', 5.1, 1.7), ('hopf_stiff', 2.0, 0.6)]; the same in
    absolute terms (ê < ½ |v − v*|): 18 [('time_pulse', 8.5, 0.4), ('sliding_cold', 10.6, 0.47),
    ('sliding_frozen', 15.6, 0.22), ('sliding_frozen', 16.2, 0.18), ('sliding_frozen', 9.9,
    0.26), ('sliding_frozen', 7.0, 0.37), ('sliding_wide', 10.2, 0.36), ('sliding_wide', 10.7,
    0.35), ('sliding_wide', 6.8, 0.36), ('sliding_node', 14.9, 0.12), ('sliding_node', 15.4,
    0.19), ('sliding_node', 8.9, 0.21), ('sliding_node', 6.4, 0.3), ('sliding_3d', 14.8, 0.27),
    ('sliding_3d', 13.8, 0.31), ('sliding_3d', 7.6, 0.2), ('sliding_3d', 5.1, 0.31),
    ('hopf_stiff', 2.0, 0.28)]; false alarms (warned, every pair < 5 %): 5 ['cliff_plateau',
    'cliff_cold', 'embedded_1d_4d', 'track_long', 'track_cold'] (< 2 %: ['cliff_plateau',
    'cliff_cold', 'embedded_1d_4d', 'track_cold']); c's own estimate > 5 % with c < 5 % off: [];
    truths uncertain beyond 2 %: []

Not tabled: ``rcost_box`` (``rcost_huge`` on the box the stranger first chose, 81² on [−2, 2]²):
−9.8 %, −0.5 %, −29.7 % against the unbounded Riccati value with estimates of 0.26–0.47 % and no
warning; the uncontrolled paths from (1.2, −1.2) leave ±2 within T = 3, and the walls reflect
on every grid alike — the box itself, which :doc:`accuracy` says the estimate cannot see (on
[−7, 7]², ``rcost_huge``: −0.2 %). ``exit_line_between`` first as a slab 0.002 wide between
nodes: refused with a clear ValueError ("contains no node of the grid ... widen it, or refine").
``exit_line_cold_loaded`` and ``time_pulse_loaded``: ``gridlbc.save`` wrote the solution without
complaint, ``gridlbc.load`` raised ``TypeError: Shaped.__init__() missing 1 required positional
argument: 'd'`` (a user's ControlAffineSystem without ``parameters()``: save records {} and load
calls the class with no arguments). ``solve(time_pulse, tol=0.03, states=X)`` did not finish in
300 s.

Tally: 40 solves, 150 pairs. Raised: no default solve; ``gridlbc.load`` on two user-class
solutions (above). Silent (> 10 % off, no warning): 4 pairs, ``sliding_frozen`` (−15.6 %,
−16.2 %; estimates 4.1 %, 3.6 %) and ``sliding_wide`` (−10.2 %, −10.7 %; 4.0 %, 4.2 %); their
other states are −7 … −10 % with estimates of 2.6–2.8 %. Estimate below half the error (relative,
errors above 2 %): 17 pairs — the sliding family (``sliding_frozen``, ``_wide``, ``_node``,
``_3d``; the last two warned by other checks), ``time_pulse`` at (1.5, 0.5) (−8.5 % against
3.7 %, warned) and ``hopf_stiff``'s centre (−2.0 % against 0.57 %). False alarms (warned, every
pair below 5 %): ``cliff_plateau``, ``cliff_cold``, ``embedded_1d_4d`` (errors ≤ 1.3 %, S 3–89 %:
the cubic reconstruction of a step between the nodes overshoots, which S reads as a goal — the
documented mechanism of round 9), ``track_cold`` (≤ 0.3 %, the local confirmation at one line
of the box) and ``track_long`` (3.2–3.3 %, est 5.2–7.4 %, warned also of the control's 39 cells
per step). Quiet and right: the rest, including T = 80, spacings 3000× apart, R = 200, λ = 2.9,
weights 10⁻⁵/10⁵ and save/load round trips (the loaded estimate equals the fresh one).

Mechanisms (measured; reproducible with the builders here):

- Silent, sliding-mode drift (``sliding_frozen``, ``sliding_wide``): the default step of the
  fitted splitting is Courant 7 against the drift's rms speed (|a| ≈ 2, h = 0.05: dt = T/12 =
  0.167, 6.7 cells per step); it knows the drift's speed, not its gradient, and the switch
  (slope 200 and 40) is crossed in one step, where the midpoint rule lands paths across the
  sliding line by up to 0.33 (0.4 → 0.73, next to the cost's minimum at 0.8): v too low. v at
  (0, 0) with dt = 1/6, 1/24, 1/96, 1/384: 1.1897, 1.4278, 1.4054, 1.4019 (truth 1.4097); the
  smooth stiff pull ``stiff_pull`` gets dt = 0.0095 from its large speed and is right to 0.03 %.
  The estimate: ``s.embedded._read(s, X)`` gives v_h = 1.1897, v_2h = 1.1738 (both 0.22 low:
  the step error scales with neither), the pair 4.9 %, floor 2.8 % → 4.1 %; S = 0 (costs
  smooth), γ (``gridlbc.accuracy.cost_gap``) 0.1 %. The flow check
  (``gridlbc.accuracy.flow.flow_excess``) reads F = 3.67 cells (≥ ½) but p = 1.78 (≥ 1), so
  it stays quiet: a switch's interpolation error shrinks at first order or better in the L1
  sum, unlike a narrow gust's; on the node (``sliding_node``) the 2h interpolant is "no worse"
  and it warns. ``sliding_wide``: F = 0.56, p = 1.86; v_h 1.2664, v_2h 1.1494 (errors 0.144 and
  0.261, local order 0.86), divided by 2^q − 1 = 2.29 with the solve's order 1.72 → 0.051
  against 0.144. ``solve(tol=0.03, states=X)`` fixes both in 2 s (113 × 81: +0.3 … +0.6 %;
  165 × 81: −0.4 … +0.2 %).
- Under half, warned, ``time_pulse`` (1.5, 0.5): the pulse (25 high, 0.008 wide at s = 1.03) is
  sampled at the s-nodes 1.0 and 1.05 (w = 0.22 and 1.3 against an integral 0.5): all grids
  undercharge it; local term 3.7 %, S 0.45 % (τ = T hold: a noiseless axis cannot hold), γ
  0.06 % at that state (the paths pass the pulse far from x₀ = 1 … ) — other states 97–163 %.
- ``hopf_stiff`` centre (unstable node, rate 15): v_h 0.4586, v_2h 0.4508, 201² 0.4649, truth
  0.4680 (local order ≈ 0.9 between 2h and h), divided by 3 (q = 2) → 0.26 % against 2.0 %.

Results in ``strangers_round18_results/`` (gitignored; a copy in the main checkout's).
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import strangers_round12 as r12
import strangers_round13 as r13
import strangers_round15 as r15
import strangers_round16 as r16
import strangers_round17 as r17
from scipy.integrate import solve_ivp
from strangers_round12 import HERE, const
from strangers_round13 import Shaped, cn_1d
from strangers_round15 import ricc_truth, riccati

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.regions import Box
from gridlbc.systems import LinearSystem

OUT = HERE / "strangers_round18_results"
PI = math.pi
INF = np.inf
S = r16.S
quad = r16.quad


# ---------------- shared truth helpers -----------------------------------------------------------
def tracker_1d(c_fun, W, WT, lam, T, a=0.0, R=1.0, W_fun=None, max_step=np.inf, cT=None):
    """Exact value of the 1-D tracking problem ẋ = a x + u, q = W (x − c(t))², g = WT (x −
    c(T))², control ½ R u², noise λ/R: v(x, 0) = ½ P x² + p x + c₀ with (SPEC §6, time-varying
    c_q) −Ṗ = 2aP − P²/R + 2W, −ṗ = (a − P/R) p − 2W c(t), −ċ₀ = −p²/(2R) + (λ/2R) P + W c(t)²;
    P(T) = 2WT, p(T) = −2WT c(T), c₀(T) = WT c(T)² (solve_ivp LSODA, rtol 1e-11). Returns a
    function x → v(x, 0)."""

    def rhs(t, y):
        P, p, _c0 = y
        c = c_fun(t)
        W = W0 if W_fun is None else W_fun(t)
        return [
            -(2 * a * P - P * P / R + 2 * W),
            -((a - P / R) * p - 2 * W * c),
            -(-p * p / (2 * R) + lam / (2 * R) * P + W * c * c),
        ]

    W0 = W
    cT = c_fun(T) if cT is None else cT
    y0 = [2 * WT, -2 * WT * cT, WT * cT * cT]
    sol = solve_ivp(rhs, (T, 0.0), y0, rtol=1e-11, atol=1e-13, method="LSODA", max_step=max_step)
    P, p, c0 = sol.y[:, -1]
    return lambda x: 0.5 * P * np.asarray(x) ** 2 + p * np.asarray(x) + c0


def cn_td(q_fun, g_fun, lam, T, a_fun=None, R=1.0, lo=-4.0, hi=4.0, n=8001, steps=4000):
    """My own Crank–Nicolson (Rannacher start) of −∂_t z = a z′ + (λ/2R) z″ − (q(x, t)/λ) z,
    z(T) = e^{−g/λ}, reflecting ends, with a state cost that depends on time; returns (x, v(x,
    0)). The second method for ``tracker_1d``."""
    x = np.linspace(lo, hi, n)
    h = x[1] - x[0]
    D = lam / (2 * R) / h**2 * np.ones(n)
    C = (np.zeros(n) if a_fun is None else a_fun(x)) / (2 * h)
    lw, up = (D - C).copy(), (D + C).copy()
    up[0] += lw[0]
    lw[-1] += up[-1]
    K = sp.diags([-2 * D, lw[1:], up[:-1]], [0, -1, 1], format="csc")
    eye = sp.identity(n, format="csc")
    g = g_fun(x)
    shift = g.min()
    z = np.exp(-(g - shift) / lam)
    dt = T / steps
    t = T
    for k in range(steps):
        if k < 4:  # four implicit half-steps
            for _ in range(2):
                t -= dt / 2
                M = K - sp.diags(q_fun(x, t) / lam)
                z = spla.spsolve((eye - 0.5 * dt * M).tocsc(), z)
            continue
        M1 = K - sp.diags(q_fun(x, t) / lam)
        M0 = K - sp.diags(q_fun(x, t - dt) / lam)
        z = spla.spsolve((eye - 0.5 * dt * M0).tocsc(), (eye + 0.5 * dt * M1) @ z)
        t -= dt
    return x, shift - lam * np.log(z)


def sep_cn(parts, lam, T, lo=-2.0, hi=2.0, method=cn_1d):
    """A separable truth: v = Σ_k v_k(x_k), each v_k by round 13's ``cn_1d`` (a_k, q_k, g_k) on
    [lo, hi] (20 001 / 40 001 nodes, 4000 / 8000 steps); the uncertainty adds the axes'."""
    fs = [None if p is None else method(p[0], p[1], p[2], lam, T, lo=lo, hi=hi) for p in parts]

    def truth(X):
        X = np.asarray(X)
        v, u = np.zeros(len(X)), np.zeros(len(X))
        for k, f in enumerate(fs):
            if f is None:
                continue
            vk, uk = f(X[:, [k]])
            v, u = v + vk, u + uk
        return v, u

    return truth


def zero(y):
    return 0.0 * y


def be_1d(a_fun, q_fun, g_fun, lam, T, R=1.0, lo=-2.0, hi=2.0, ns=((20001, 4000), (40001, 8000))):
    """My own monotone backward-Euler solve of ∂_τ z = a z′ + (λ/2R) z″ − (q/λ) z (upwinded drift,
    reflecting ends: an M-matrix, so z stays positive however cold), at Δt and Δt/2 on each of
    two grids, Richardson-extrapolated in v (2 v_{Δt/2} − v_{Δt}); the uncertainty is the two
    grids' difference plus the extrapolation's size. For cold, narrow costs where Crank–Nicolson
    rings below zero (``well_between``)."""

    def one(n, steps, y):
        x = np.linspace(lo, hi, n)
        h = x[1] - x[0]
        D = lam / (2 * R) / h**2 * np.ones(n)
        a = a_fun(x)
        lw = D + np.maximum(-a, 0) / h
        up = D + np.maximum(a, 0) / h
        main = -(lw + up) - q_fun(x) / lam
        up2, lw2 = up.copy(), lw.copy()
        up2[0] += lw[0]
        lw2[-1] += up[-1]
        M = sp.diags([main, lw2[1:], up2[:-1]], [0, -1, 1], format="csc")
        eye = sp.identity(n, format="csc")
        g = g_fun(x)
        out = []
        for k in (steps, 2 * steps):
            lu = spla.splu((eye - (T / k) * M).tocsc())
            logscale = 0.0
            z = np.exp(-(g - g.min()) / lam)
            for _ in range(k):
                z = lu.solve(z)
                m = z.max()
                z /= m
                logscale += math.log(m)
            out.append(g.min() - lam * (np.log(np.interp(y, x, z)) + logscale))
        return 2 * out[1] - out[0], np.abs(out[1] - out[0])

    def truth(X):
        X = np.asarray(X)
        (v1, _), (v2, e2) = (one(n, k, X[:, 0]) for n, k in ns)
        return v2, np.abs(v2 - v1) + e2

    return truth


# ---------------- 1. time as a state axis: tracking a moving target -----------------------------
OM = 2.0
LAM_TR = 0.3


def tr_c(s):
    return np.sin(OM * s)


def track_time_axis():
    """A user encodes a time-varying target as an extra state axis s with ṡ = 1 (no control, no
    noise): ẋ₀ = u, q = 2 (x₀ − sin 2s)², g = (x₀ − sin 2s)², λ = 0.3, T = 2; x₀ ∈ [−2.5, 2.5]
    (101 nodes), s ∈ [0, 4] (81 nodes). Checked at s₀ + T ≤ 3.5 (the wall at s = 4 is not
    reached)."""
    return Problem(
        Shaped(2, drift=lambda x: np.stack([0 * x[:, 0], np.ones(len(x))], 1), axes=(0,)),
        Grid([Axis(-2.5, 2.5, 101), Axis(0.0, 4.0, 81)]),
        2.0,
        lambda x: (x[:, 0] - tr_c(x[:, 1])) ** 2,
        state_cost=lambda x: 2.0 * (x[:, 0] - tr_c(x[:, 1])) ** 2,
        temperature=LAM_TR,
    )


def track_truth(X, lam=LAM_TR, T=2.0, W=2.0, WT=1.0, idx=(0, 1)):
    X = np.asarray(X)
    out = []
    for x0, s0 in X[:, list(idx)]:
        out.append(float(tracker_1d(lambda t, s0=s0: math.sin(OM * (s0 + t)), W, WT, lam, T)(x0)))
    return np.array(out), np.zeros(len(X))


def track_check():
    """tracker_1d against cn_td at two resolutions (printed)."""
    X = S((0.3, 0.0), (-1.0, 0.7), (1.2, 1.5))
    v, _ = track_truth(X)
    for n, k in ((4001, 2000), (8001, 4000)):
        w = []
        for x0, s0 in X:
            xs, vs = cn_td(
                lambda x, t, s0=s0: 2.0 * (x - math.sin(OM * (s0 + t))) ** 2,
                lambda x, s0=s0: (x - math.sin(OM * (s0 + 2.0))) ** 2,
                LAM_TR,
                2.0,
                n=n,
                steps=k,
            )
            w.append(np.interp(x0, xs, vs))
        print("track ODE", np.round(v, 6), "CN", n, np.round(w, 6))


# 4-D: a point mass (x, v) and the tracker (y, s)
A_PM = np.array([[0.0, 1.0], [0.0, 0.0]])
B_PM = np.array([[0.0], [1.0]])
W_PM = np.diag([1.0, 0.1])
WT_PM = np.diag([1.0, 0.2])
OM4 = 1.2


def track_time_4d():
    """A point mass (x, v; force u₀) beside a tracker (y: ẏ = u₁; s: ṡ = 1): q = x² + 0.1 v² + 2
    (y − sin 1.2 s)², g = x² + 0.2 v² + (y − sin 1.2 s)², λ = 0.3, T = 1.5; 21 × 21 × 25 × 21 on
    [−3, 3] × [−4, 4] × [−2.5, 2.5] × [0, 4]."""

    def drift(x):
        return np.stack([x[:, 1], 0 * x[:, 0], 0 * x[:, 0], np.ones(len(x))], 1)

    def c(s):
        return np.sin(OM4 * s)

    return Problem(
        Shaped(4, drift=drift, axes=(1, 2)),
        Grid([Axis(-3, 3, 21), Axis(-4, 4, 21), Axis(-2.5, 2.5, 25), Axis(0.0, 4.0, 21)]),
        1.5,
        lambda x: x[:, 0] ** 2 + 0.2 * x[:, 1] ** 2 + (x[:, 2] - c(x[:, 3])) ** 2,
        state_cost=lambda x: x[:, 0] ** 2 + 0.1 * x[:, 1] ** 2 + 2 * (x[:, 2] - c(x[:, 3])) ** 2,
        temperature=0.3,
    )


def track4_truth(X):
    X = np.asarray(X)
    P, c0 = riccati(A_PM, B_PM, np.eye(1), W_PM, WT_PM, 0.3, 1.5)
    vpm = 0.5 * np.einsum("ni,ij,nj->n", X[:, :2], P, X[:, :2]) + c0
    vt = [
        float(tracker_1d(lambda t, s0=s0: math.sin(OM4 * (s0 + t)), 2.0, 1.0, 0.3, 1.5)(y0))
        for y0, s0 in X[:, 2:]
    ]
    return vpm + np.array(vt), np.zeros(len(X))


# ---------------- 2. plateaus and cliffs in the state cost --------------------------------------
CL = (-0.53, 0.73)  # cliffs 0.4 and 0.6 cells off the nodes of 81 on [−2, 2]


def cliff_q(y):
    return np.where((y > CL[0]) & (y < CL[1]), 0.3, 2.3)


def quarter(y):
    return 0.5 * y**2


def cliff_plateau(lam=0.1):
    """ẋ = u on [−2, 2]² (81²), q = plateau 0.3 on (−0.53, 0.73) and 2.3 outside (cliffs between
    the nodes) + 0.5 x₁², g = 0, T = 1.5, λ = 0.1."""
    return Problem(
        r12.free(2),
        r12.box2(81),
        1.5,
        const(0.0),
        state_cost=lambda x: cliff_q(x[:, 0]) + quarter(x[:, 1]),
        temperature=lam,
    )


def cliff_cold():
    """cliff_plateau at λ = 0.01."""
    return cliff_plateau(0.01)


# ---------------- 3. long horizons against fast dynamics ---------------------------------------
A_LONG = np.array([[-2.0, 1.5], [-1.5, -2.0]])
W_LONG = np.diag([1.0, 0.5])
WT_LONG = np.diag([2.0, 2.0])


def long_lq():
    """ẋ = A x + u with A = [[−2, 1.5], [−1.5, −2]] (time scale 0.5), q = x₀² + 0.5 x₁², g =
    Quadratic(0, 2), λ = 0.5, T = 80 (160 time scales), 81² on [−3, 3]²."""
    return Problem(
        LinearSystem(A_LONG, np.eye(2)),
        Grid([Axis(-3, 3, 81)] * 2),
        80.0,
        Quadratic([0.0, 0.0], [2.0, 2.0]),
        state_cost=quad(W_LONG),
        temperature=0.5,
    )


def sat_a0(y):
    return -2.0 * np.tanh(3.0 * y)


def sat_q0(y):
    return (y - 0.5) ** 2


def sat_a1(y):
    return 1.5 * np.tanh(2.0 * y)  # unstable, saturating


def sat_q1(y):
    return y**2


def long_saturation():
    """ẋ₀ = −2 tanh 3x₀ + u₀ (a stable saturating pull), ẋ₁ = 1.5 tanh 2x₁ + u₁ (an unstable
    saturating push), q = (x₀ − 0.5)² + x₁², g = 0, λ = 0.4, T = 30, 81² on [−2, 2]²."""
    return Problem(
        Shaped(2, drift=lambda x: np.stack([sat_a0(x[:, 0]), sat_a1(x[:, 1])], 1)),
        r12.box2(81),
        30.0,
        const(0.0),
        state_cost=lambda x: sat_q0(x[:, 0]) + sat_q1(x[:, 1]),
        temperature=0.4,
    )


# ---------------- 4. anisotropic grids ----------------------------------------------------------
DSC = np.array([0.01, 1.0, 30.0])  # the axes' scales, 3000× apart
A_Y = np.array([[-1.0, 1.0, 0.0], [0.0, -0.5, 1.0], [-0.5, 0.0, -1.0]])
W_Y = np.diag([1.0, 0.5, 0.8])
WT_Y = np.diag([1.0, 1.0, 1.0])


def aniso_3d():
    """A coupled 3-D linear system in coordinates x = D y with D = diag(0.01, 1, 30) (spacings
    0.0015, 0.15 and 4.5: 3000× apart): ẋ = D A_y D⁻¹ x + D u, q = yᵀW y, g = |y|², λ = 0.5,
    T = 1.5; 41³ on D [−3, 3]³."""
    D, Di = np.diag(DSC), np.diag(1 / DSC)
    return Problem(
        LinearSystem(D @ A_Y @ Di, D),
        Grid([Axis(-3 * s, 3 * s, 41) for s in DSC]),
        1.5,
        Quadratic([0.0] * 3, (1 / DSC**2).tolist()),
        state_cost=quad(Di @ W_Y @ Di),
        temperature=0.5,
    )


def aniso_truth(X):
    D, Di = np.diag(DSC), np.diag(1 / DSC)
    return ricc_truth(D @ A_Y @ Di, D, np.eye(3), Di @ W_Y @ Di, Di @ WT_Y @ Di, 0.5, 1.5)(X)


# ---------------- 5. control cost ≫ state cost ------------------------------------------------
A_RH = np.array([[0.3, 1.0], [0.0, 0.2]])


def rcost_huge(grid=None):
    """An unstable ẋ = A x + u (A = [[0.3, 1], [0, 0.2]]) with R = 200 I (noise λ/R = 0.0025: a
    quarter cell² per unit time), q = x₀² + x₁², g = Quadratic(0, 1), λ = 0.5, T = 3, 141² on
    [−7, 7]² (the uncontrolled paths from the checked states stay within ±4.7).

    First posed on 81² over [−2, 2]² (``rcost_box``): there the paths from (1.2, −1.2) run into
    the reflecting walls, and the solve is 10–30 % below the unbounded Riccati value with
    estimates of 0.3–0.5 %, no warning — the box itself, which the estimate is documented not to
    see (every grid reflects alike)."""
    return Problem(
        LinearSystem(A_RH, np.eye(2)),
        Grid([Axis(-7, 7, 141)] * 2) if grid is None else grid,
        3.0,
        Quadratic([0.0, 0.0], [1.0, 1.0]),
        state_cost=quad(np.eye(2)),
        control_cost=200.0 * np.eye(2),
        temperature=0.5,
    )


def rcost_box():
    """rcost_huge on the box the stranger first chose, 81² on [−2, 2]² (its truth, the unbounded
    Riccati value, is not this reflecting problem's: kept out of the table's tally)."""
    return rcost_huge(r12.box2(81))


# ---------------- 6. λ = 3 in 3-D, λ = 0.01 ------------------------------------------------------
A_H3 = np.array([[0.0, 1.0, 0.0], [-2.0, -0.5, 1.0], [0.0, 0.0, -1.0]])
B_H3 = np.eye(3)


def hot_3d():
    """ẋ = A x + u (3-D, an oscillator fed by a lag), q = x₀² + 0.2 x₁² + 0.5 x₂², g =
    Quadratic(0, (2, 1, 1)), λ = 2.9, T = 1, 41³ on [−4, 4]³."""
    return Problem(
        LinearSystem(A_H3, B_H3),
        Grid([Axis(-4, 4, 41)] * 3),
        1.0,
        Quadratic([0.0] * 3, [2.0, 1.0, 1.0]),
        state_cost=quad(np.diag([1.0, 0.2, 0.5])),
        temperature=2.9,
    )


# ---------------- 7. first exit through a line on a periodic axis -------------------------------
W_TOR = 0.4
Q_TOR = 0.5
GE_TOR = 0.3
LAM_TOR = 0.2


def exit_line_torus(c=0.0, n=64, width=0.002):
    """A 2-D torus [−π, π)² (n nodes per axis), ẋ₀ = 0.4 + u₀, ẋ₁ = 1.5 + u₁, exit the thin slab
    |x₀ − c| ≤ 0.001 (a Box: a line across the torus), exit cost 0.3, q = 0.5, λ = 0.2. x₁
    carries no cost: v depends on x₀ only."""
    return Problem(
        Shaped(2, drift=lambda x: np.stack([np.full(len(x), W_TOR), np.full(len(x), 1.5)], 1)),
        Grid([Axis(-PI, PI, n, periodic=True)] * 2),
        None,
        state_cost=const(Q_TOR),
        temperature=LAM_TOR,
        exit=Box([c - width / 2, -INF], [c + width / 2, INF]),
        exit_cost=const(GE_TOR),
    )


def exit_line_between():
    """exit_line_torus with a slab 2.2 cells wide centred at π/64, midway between two nodes of the
    64-node axis (its edges 0.6 cells off the nodes 0 and h outside them). (The slab 0.002 wide
    there is refused: "contains no node of the grid", a clear ValueError.)"""
    return exit_line_torus(c=PI / 64, width=2.2 * 2 * PI / 64)


def torus_line_truth(c=0.0, width=0.002, lam=LAM_TOR, w=W_TOR, q=Q_TOR, gE=GE_TOR):
    """Closed form: on y = (x₀ − c) mod 2π ∈ (0, 2π), (λ/2) z″ + w z′ − (q/λ) z = 0, z(0) = z(2π)
    = e^{−g_E/λ}: z = A e^{m₁y} + B e^{m₂y}, m = (−w ± √(w² + 2q))/λ."""

    def truth(X):
        y = np.mod(np.asarray(X)[:, 0] - c - width / 2, 2 * PI)
        disc = math.sqrt(w * w + 2 * q)
        m1, m2 = (-w + disc) / lam, (-w - disc) / lam
        L = 2 * PI - width
        # z = A e^{m1 (y − L)} + B e^{m2 y}: both bounded
        M = np.array([[math.exp(-m1 * L), 1.0], [1.0, math.exp(m2 * L)]])
        zb = math.exp(-gE / lam)
        A, B = np.linalg.solve(M, [zb, zb])
        z = A * np.exp(m1 * (y - L)) + B * np.exp(m2 * y)
        return -lam * np.log(z), np.zeros(len(y))

    return truth


def torus_line_fd(c, X, width=0.002, n=200001, lam=LAM_TOR, w=W_TOR, q=Q_TOR, gE=GE_TOR):
    """The second method: my own central differences on (0, 2π − width), Dirichlet both ends."""
    y = np.linspace(0, 2 * PI - width, n)
    h = y[1] - y[0]
    D, C = lam / 2 / h**2, w / (2 * h)
    m = n - 2
    M = sp.diags(
        [np.full(m, -2 * D - q / lam), np.full(m - 1, D - C), np.full(m - 1, D + C)], [0, -1, 1]
    )
    rhs = np.zeros(m)
    zb = math.exp(-gE / lam)
    rhs[0] -= (D - C) * zb
    rhs[-1] -= (D + C) * zb
    z = np.concatenate([[zb], spla.spsolve(M.tocsc(), rhs), [zb]])
    return -lam * np.log(np.interp(np.mod(np.asarray(X)[:, 0] - c - width / 2, 2 * PI), y, z))


# ---------------- 8. a 1-D problem embedded in 3-D ---------------------------------------------
def step_q(y):
    return np.where(y < -0.37, 1.5, 0.2) + 0.3 * y**2


def kink_g(y):
    return 0.8 * np.abs(y - 0.61)


def flow_e(y):
    return 0.6 * np.sin(y)


def embedded_1d_3d():
    """ẋ₀ = 0.6 sin x₀ + u₀, q = [1.5 if x₀ < −0.37 else 0.2] + 0.3 x₀², g = 0.8 |x₀ − 0.61|;
    x₁, x₂ carry a rotation (ẋ₁ = −2x₂, ẋ₂ = 2x₁) and noise but no cost: v depends on x₀ only.
    λ = 0.15, T = 1.2, 81 × 17 × 17 on [−2, 2]³."""

    def drift(x):
        return np.stack([flow_e(x[:, 0]), -2 * x[:, 2], 2 * x[:, 1]], 1)

    return Problem(
        Shaped(3, drift=drift),
        Grid([Axis(-2, 2, 81), Axis(-2, 2, 17), Axis(-2, 2, 17)]),
        1.2,
        lambda x: kink_g(x[:, 0]),
        state_cost=lambda x: step_q(x[:, 0]),
        temperature=0.15,
    )


def embedded_1d_4d():
    """The same x₀ task with three idle axes (rotation in (x₁, x₂), x₃ noise only): 41 × 13 ×
    13 × 13 on [−2, 2]⁴, λ = 0.15, T = 1.2."""

    def drift(x):
        return np.stack([flow_e(x[:, 0]), -2 * x[:, 2], 2 * x[:, 1], 0 * x[:, 0]], 1)

    return Problem(
        Shaped(4, drift=drift),
        Grid([Axis(-2, 2, 41)] + [Axis(-2, 2, 13)] * 3),
        1.2,
        lambda x: kink_g(x[:, 0]),
        state_cost=lambda x: step_q(x[:, 0]),
        temperature=0.15,
    )


def embedded_idle5():
    """embedded_1d_3d with idle axes of 5 nodes each (81 × 5 × 5): the axes the user does not
    care about, barely gridded (their embedded levels have 3 and 2 nodes)."""
    p = embedded_1d_3d()
    return p.replace(grid=Grid([Axis(-2, 2, 81), Axis(-2, 2, 5), Axis(-2, 2, 5)]))


# ---------------- 9. a limit cycle (Hopf normal form) ------------------------------------------
HOPF_W = 4.0


def hopf(lam=0.3, K=1.0):
    """ṙ = r(1 − r²), θ̇ = 4 in Cartesian form (ẋ = x(1 − r²) − 4y + u₀, ẏ = y(1 − r²) + 4x +
    u₁), q = 2 (r − 1)², g = 3 (r − 0.7)², λ = 0.3, T = 2, 101² on [−2.5, 2.5]². Radial costs:
    v = v(r)."""

    def drift(x):
        r2 = (x**2).sum(1)
        return np.stack(
            [
                K * x[:, 0] * (1 - r2) - HOPF_W * x[:, 1],
                K * x[:, 1] * (1 - r2) + HOPF_W * x[:, 0],
            ],
            1,
        )

    def r(x):
        return np.sqrt((x**2).sum(1))

    return Problem(
        Shaped(2, drift=drift),
        Grid([Axis(-2.5, 2.5, 101)] * 2),
        2.0,
        lambda x: 3.0 * (r(x) - 0.7) ** 2,
        state_cost=lambda x: 2.0 * (r(x) - 1.0) ** 2,
        temperature=lam,
    )


def hopf_cold():
    """hopf at λ = 0.05."""
    return hopf(0.05)


def hopf_stiff():
    """hopf with a stiff attraction to the cycle, ṙ = 15 r(1 − r²) (rate 30 at r = 1), λ = 0.05."""
    return hopf(0.05, K=15.0)


def hopf_frozen():
    """hopf at λ = 0.01."""
    return hopf(0.01)


def radial_cn(lam, T=2.0, rmax=4.0, ns=((8001, 4000), (16001, 8000)), K=1.0):
    """My own Crank–Nicolson in r for a radial z: ∂_τ z = (r(1 − r²) + λ/(2r)) z′ + (λ/2) z″ −
    (q/λ) z (at r = 0: λ z″, the Laplacian's limit), z′ = 0 at r = 0 and r = 4 (drift −60
    there), z(0) = e^{−g/λ}; Rannacher start. Uncertainty: the two resolutions' difference."""

    def one(n, steps, rr):
        r = np.linspace(0, rmax, n)
        h = r[1] - r[0]
        D = np.full(n, lam / 2 / h**2)
        rs = np.where(r > 0, r, 1.0)
        C = (K * r * (1 - r**2) + np.where(r > 0, lam / (2 * rs), 0.0)) / (2 * h)
        D[0] = lam / h**2  # λ z″ at the centre
        lw, up = (D - C).copy(), (D + C).copy()
        up[0] += lw[0]
        lw[-1] += up[-1]
        main = -2 * D - 2.0 * (r - 1) ** 2 / lam
        M = sp.diags([main, lw[1:], up[:-1]], [0, -1, 1], format="csc")
        eye = sp.identity(n, format="csc")
        g = 3.0 * (r - 0.7) ** 2
        z = np.exp(-(g - g.min()) / lam)
        dt = T / steps
        lu_h = spla.splu((eye - 0.25 * dt * M).tocsc())
        for _ in range(4):
            z = lu_h.solve(z)
        lu = spla.splu((eye - 0.5 * dt * M).tocsc())
        B = (eye + 0.5 * dt * M).tocsr()
        for _ in range(steps - 2):
            z = lu.solve(B @ z)
        return g.min() - lam * np.log(np.interp(rr, r, z))

    def truth(X):
        rr = np.sqrt((np.asarray(X) ** 2).sum(1))
        v = [one(n, k, rr) for n, k in ns]
        return v[1], np.abs(v[1] - v[0])

    return truth


# ---------------- 10. a combination with weights 10⁵ and 10⁻⁵ ---------------------------------
OFF = 5.0


def gA(y):
    return r17.gE_tanh(y)


def gB(y):
    return OFF + 1.5 * (1.0 - np.tanh(3.0 * (y - 0.5)))


W_EXT = (1e-5, 1e5)


def combo_extreme():
    """round 17's fe_aniso_exitcost (first exit x₀ ≥ 0.45, R = diag(4, 0.25), λ = 0.25) solved for
    two exit costs by solve_many, g_A = 1.5 (1 + tanh 3x₁) and g_B = 5 + 1.5 (1 − tanh 3(x₁ −
    0.5)), combined with weights (10⁻⁵, 10⁵): ln 10⁵ λ = 2.9 shifts B under A, so both count."""
    return r17.fe_aniso_exitcost()


def combo_truth(X):
    lam = r17.LAM_AX
    return r17.cos_series_exit(
        lambda y: W_EXT[0] * np.exp(-gA(y) / lam) + W_EXT[1] * np.exp(-gB(y) / lam)
    )(X)


def combo_run(name):
    _b, X, *_ = P18[name]
    costs = [lambda x: gA(x[:, 1]), lambda x: gB(x[:, 1])]
    r13.save_combination(
        name,
        X,
        lambda: gridlbc.solve_many(r17.fe_aniso_exitcost(), costs),
        list(W_EXT),
        OUT,
        r16._warned,
    )


# ---------------- 11. a narrow well between nodes, solved, saved and loaded ---------------------
WELL = (0.025 + 0.0, 0.006)  # midway between the nodes 0 and 0.05 (81 on [−2, 2]), 0.12 cells


def well_q(y):
    return 1.0 - 0.95 * np.exp(-0.5 * ((y - WELL[0]) / WELL[1]) ** 2) + 0.3 * y**2


def well_between():
    """ẋ = u on [−2, 2]² (81²), q = 1 − 0.95 e^{−(x₀ − 0.025)²/(2·0.006²)} + 0.3 x₀² + 0.2 x₁²
    (a well 0.12 cells wide midway between two nodes next to the centre), g = 0, λ = 0.02,
    T = 2."""
    return Problem(
        r12.free(2),
        r12.box2(81),
        2.0,
        const(0.0),
        state_cost=lambda x: well_q(x[:, 0]) + 0.2 * x[:, 1] ** 2,
        temperature=0.02,
    )


def q02(y):
    return 0.2 * y**2


def saveload_run(name):
    """The default solve of ``well_between`` (or another base), saved by gridlbc.save, read back
    by gridlbc.load; v and the estimate of the LOADED solution are recorded (and the fresh one's
    beside them). A system that its record cannot rebuild (round 13's ``Shaped``: save warns of
    it since 2026-12-06) is loaded with ``system=``, as the warning says."""
    base = name.replace("_loaded", "")
    build, X, *_ = P18[base]
    (OUT / f"{name}_load_error.txt").unlink(missing_ok=True)
    (OUT / f"{name}_solve.json").unlink(missing_ok=True)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        s = gridlbc.solve(build())
        v0, e0 = s.value(X), s.error_estimate(X)
        path = OUT / f"{base}.npz"
        gridlbc.save(s, path)
        rebuildable = not any("cannot rebuild it" in str(x.message) for x in w)
        try:
            s2 = gridlbc.load(path, system=None if rebuildable else s.problem.system)
        except Exception as ex:  # recorded, not judged (no loaded solution)
            msg = f"gridlbc.load raised {type(ex).__name__}: {ex}"
            print(f"{name}: {msg}", flush=True)
            (OUT / f"{name}_load_error.txt").write_text(msg + "\n")
            return
        v, est = s2.value(X), s2.error_estimate(X)
    out = dict(
        name=name,
        X=X.tolist(),
        time=time.perf_counter() - t0,
        kind="exit",
        v=v.tolist(),
        est=est.tolist(),
        fresh_v=v0.tolist(),
        fresh_est=e0.tolist(),
        warned=r16._warned(w),
        warnings=[f"{x.category.__name__}: {str(x.message)[:300]}" for x in w],
    )
    print(
        f"{name}: loaded v {np.round(v, 4)} est {np.round(est, 4)}; fresh {np.round(v0, 4)}"
        f" est {np.round(e0, 4)}",
        out["warnings"],
        flush=True,
    )
    (OUT / f"{name}_solve.json").write_text(json.dumps(out, indent=1))


# ---------------- 12. an impulse in time on the time axis ---------------------------------------
PULSE = (1.03, 0.008, 25.0)  # centre (between s-nodes 1.0 and 1.05), width, height


def pulse_w(s):
    return 0.2 + PULSE[2] * np.exp(-0.5 * ((s - PULSE[0]) / PULSE[1]) ** 2)


def time_pulse():
    """The time axis again (ẋ₀ = u, ṡ = 1, no noise on s): q = w(s) (x₀ − 1)² with w = 0.2 + 25
    e^{−(s − 1.03)²/(2·0.008²)}, a checkpoint at s = 1.03 (a sixth of an s-cell wide, between
    the s-nodes 1.0 and 1.05) that charges 0.5 (x₀ − 1)² in all; g = 0.5 x₀², λ = 0.2, T = 2;
    x₀ ∈ [−2.5, 2.5] (101), s ∈ [0, 4] (81)."""
    return Problem(
        Shaped(2, drift=lambda x: np.stack([0 * x[:, 0], np.ones(len(x))], 1), axes=(0,)),
        Grid([Axis(-2.5, 2.5, 101), Axis(0.0, 4.0, 81)]),
        2.0,
        lambda x: 0.5 * x[:, 0] ** 2,
        state_cost=lambda x: pulse_w(x[:, 1]) * (x[:, 0] - 1.0) ** 2,
        temperature=0.2,
    )


def pulse_truth(X):
    """tracker_1d with W(t) = w(s₀ + t), c = 1 (the time-varying Riccati ODE; max_step 0.001 so
    LSODA does not step over the pulse), and g = 0.5 x² written as WT (x − 0)² — the target of g
    (0) differs from q's (1): ``cT=0``. Checked against cn_td (two resolutions)."""
    X = np.asarray(X)
    out = []
    for x0, s0 in X:
        f = tracker_1d(
            lambda t: 1.0,
            None,
            0.5,
            0.2,
            2.0,
            W_fun=lambda t, s0=s0: float(pulse_w(s0 + t)),
            max_step=1e-3,
            cT=0.0,
        )
        out.append(float(f(x0)))
    return np.array(out), np.zeros(len(X))


def pulse_check():
    X = S((0.0, 0.0), (1.5, 0.5), (-1.0, 0.9))
    print("pulse ODE", np.round(pulse_truth(X)[0], 6))
    for n, k in ((4001, 4000), (8001, 8000)):
        w = []
        for x0, s0 in X:
            xs, vs = cn_td(
                lambda x, t, s0=s0: pulse_w(s0 + t) * (x - 1.0) ** 2,
                lambda x: 0.5 * x**2,
                0.2,
                2.0,
                n=n,
                steps=k,
            )
            w.append(np.interp(x0, xs, vs))
        print("pulse CN", n, np.round(w, 6))


def cliff_w(s):
    return np.where(s > 1.03, 3.0, 0.2)


def time_cliff():
    """time_pulse with a switch instead of a pulse: q = w(s) (x₀ − 1)² with w = 0.2 before
    s = 1.03 and 3 after (a step in time between the s-nodes 1.0 and 1.05), g = 0.5 x₀², λ = 0.2,
    T = 2."""
    return time_pulse().replace(state_cost=lambda x: cliff_w(x[:, 1]) * (x[:, 0] - 1.0) ** 2)


def time_cliff_truth(X):
    """As pulse_truth with W(t) = cliff_w(s₀ + t) (LSODA, max_step 0.001)."""
    X = np.asarray(X)
    out = []
    for x0, s0 in X:
        f = tracker_1d(
            lambda t: 1.0,
            None,
            0.5,
            0.2,
            2.0,
            W_fun=lambda t, s0=s0: float(cliff_w(s0 + t)),
            max_step=1e-3,
            cT=0.0,
        )
        out.append(float(f(x0)))
    return np.array(out), np.zeros(len(X))


def blind_w(s):
    return np.where(s > 2.025, 6.0, 0.2)


def time_cliff_blind():
    """time_cliff with the switch 0.2 → 6 at s = 2.025, midway between the s-nodes 2.0 and 2.05
    next to the centre of the 81-node axis (the phase pair's blind spot)."""
    return time_pulse().replace(state_cost=lambda x: blind_w(x[:, 1]) * (x[:, 0] - 1.0) ** 2)


def time_cliff_blind_truth(X):
    X = np.asarray(X)
    out = []
    for x0, s0 in X:
        f = tracker_1d(
            lambda t: 1.0,
            None,
            0.5,
            0.2,
            2.0,
            W_fun=lambda t, s0=s0: float(blind_w(s0 + t)),
            max_step=1e-3,
            cT=0.0,
        )
        out.append(float(f(x0)))
    return np.array(out), np.zeros(len(X))


def exit_line_cold():
    """exit_line_torus at λ = 0.02 (64² torus, exit the line x₀ = 0, ẋ₀ = 0.4 + u₀)."""
    return exit_line_torus().replace(temperature=0.02)


# ---------------- 13. a sliding-mode drift: saturation narrower than a cell ---------------------
SL = (0.37, 0.01)


def slide_a(y):
    return -2.0 * np.tanh((y - SL[0]) / SL[1])


def slide_q(y):
    return 0.5 + (y - 0.8) ** 2


def sliding_cold():
    """sliding_mode at λ = 0.02."""
    return sliding_mode().replace(temperature=0.02)


def sliding_frozen():
    """sliding_mode at λ = 0.005."""
    return sliding_mode().replace(temperature=0.005)


def wide_a(y):
    return -2.0 * np.tanh((y - SL[0]) / 0.05)


def sliding_wide():
    """sliding_frozen (λ = 0.005) with the switch over a whole cell: ẋ₀ = −2 tanh((x₀ − 0.37)/0.05)
    + u₀."""
    return sliding_mode().replace(
        system=Shaped(2, drift=lambda x: np.stack([wide_a(x[:, 0]), 0 * x[:, 1]], 1)),
        temperature=0.005,
    )


def pull_a(y):
    return -30.0 * (y - SL[0])


def stiff_pull():
    """sliding_frozen's task with a smooth, linear but stiff pull to the same line (a user's
    class, not a LinearSystem): ẋ₀ = −30 (x₀ − 0.37) + u₀, λ = 0.005."""
    return sliding_mode().replace(
        system=Shaped(2, drift=lambda x: np.stack([pull_a(x[:, 0]), 0 * x[:, 1]], 1)),
        temperature=0.005,
    )


def node_a(y):
    return -2.0 * np.tanh((y - 0.35) / 0.01)


def sliding_node():
    """sliding_frozen with the switching line on the node x₀ = 0.35 (λ = 0.005)."""
    return sliding_mode().replace(
        system=Shaped(2, drift=lambda x: np.stack([node_a(x[:, 0]), 0 * x[:, 1]], 1)),
        temperature=0.005,
    )


def sliding_3d():
    """sliding_frozen's x₀ (ẋ₀ = −2 tanh((x₀ − 0.37)/0.01) + u₀) beside two free axes with
    q = 0.5 x₁² + 0.5 x₂², λ = 0.01, T = 2, 41³ on [−2, 2]³."""
    return Problem(
        Shaped(3, drift=lambda x: np.stack([slide_a(x[:, 0]), 0 * x[:, 1], 0 * x[:, 2]], 1)),
        Grid([Axis(-2, 2, 41)] * 3),
        2.0,
        const(0.0),
        state_cost=lambda x: slide_q(x[:, 0]) + quarter(x[:, 1]) + quarter(x[:, 2]),
        temperature=0.01,
    )


def sliding_mode():
    """ẋ₀ = −2 tanh((x₀ − 0.37)/0.01) + u₀ (a bang-bang pull to the line x₀ = 0.37, between the
    nodes 0.35 and 0.4, switching over a fifth of a cell), ẋ₁ = u₁; q = 0.5 + (x₀ − 0.8)² +
    0.5 x₁², g = 0, λ = 0.1, T = 2, 81² on [−2, 2]²."""
    return Problem(
        Shaped(2, drift=lambda x: np.stack([slide_a(x[:, 0]), 0 * x[:, 1]], 1)),
        r12.box2(81),
        2.0,
        const(0.0),
        state_cost=lambda x: slide_q(x[:, 0]) + quarter(x[:, 1]),
        temperature=0.1,
    )


# ---------------- 13b. the time axis over a long horizon ----------------------------------------
OML = 3.0


def track_long():
    """track_time_axis over a long horizon: ẋ₀ = u, ṡ = 1, q = 2 (x₀ − sin 3s)², g = (x₀ − sin
    3s)², λ = 0.3, T = 20 (ten periods of the target); x₀ ∈ [−2.5, 2.5] (101), s ∈ [0, 24]
    (241 nodes, 21 per period)."""
    return Problem(
        Shaped(2, drift=lambda x: np.stack([0 * x[:, 0], np.ones(len(x))], 1), axes=(0,)),
        Grid([Axis(-2.5, 2.5, 101), Axis(0.0, 24.0, 241)]),
        20.0,
        lambda x: (x[:, 0] - np.sin(OML * x[:, 1])) ** 2,
        state_cost=lambda x: 2.0 * (x[:, 0] - np.sin(OML * x[:, 1])) ** 2,
        temperature=LAM_TR,
    )


def track_long_truth(X):
    """tracker_1d (the time-varying Riccati ODE, max_step 0.01) at each state's s₀."""
    X = np.asarray(X)
    out = [
        float(
            tracker_1d(
                lambda t, s0=s0: math.sin(OML * (s0 + t)), 2.0, 1.0, LAM_TR, 20.0, max_step=0.01
            )(x0)
        )
        for x0, s0 in X
    ]
    return np.array(out), np.zeros(len(X))


def track_cold():
    """track_time_axis at λ = 0.01."""
    return track_time_axis().replace(temperature=0.01)


def track_cold_truth(X):
    return track_truth(X, lam=0.01)


# ---------------- 13c. a deadline: first exit through a line on a periodic clock axis -----------
def fe_deadline():
    """A deadline as a first exit: a clock x₀ on a periodic axis [−π, π) (64 nodes) that only
    the drift moves (ẋ₀ = 1, no control, no noise), x₁ ∈ [−3, 3] (61) with ẋ₁ = u; the task ends
    when the clock crosses x₀ = 0 (a Box slab 0.002 wide round the node 0) with exit cost 2 (x₁ −
    1)²; q = 0.2 + 0.5 x₁², λ = 0.3. v(x₀, x₁) is the horizon problem with T = (−x₀) mod 2π."""
    return Problem(
        Shaped(2, drift=lambda x: np.stack([np.ones(len(x)), 0 * x[:, 1]], 1), axes=(1,)),
        Grid([Axis(-PI, PI, 64, periodic=True), Axis(-3, 3, 61)]),
        None,
        state_cost=lambda x: 0.2 + 0.5 * x[:, 1] ** 2,
        temperature=0.3,
        exit=Box([-0.001, -INF], [0.001, INF]),
        exit_cost=lambda x: 2.0 * (x[:, 1] - 1.0) ** 2,
    )


def deadline_truth(X):
    """tracker_1d with W = 0.5 about 0, g = 2 (x − 1)² (cT = 1), T = (−x₀) mod 2π, plus 0.2 T."""
    X = np.asarray(X)
    out = []
    for x0, x1 in X:
        T = float(np.mod(-x0, 2 * PI))
        out.append(float(tracker_1d(lambda t: 0.0, 0.5, 2.0, 0.3, T, cT=1.0)(x1)) + 0.2 * T)
    return np.array(out), np.zeros(len(X))


# ---------------- 13d. the average cost of a periodic task: the clock on a periodic axis --------
W_CK, LAM_CK = 2.0, 0.3


def avg_clock():
    """The average cost of tracking sin s, the clock s on a periodic axis [−π, π) (64 nodes; ṡ =
    1, no control, no noise): ẋ₀ = u, q = 2 (x₀ − sin s)², λ = 0.3; x₀ ∈ [−2.5, 2.5] (101)."""
    return Problem(
        Shaped(2, drift=lambda x: np.stack([0 * x[:, 0], np.ones(len(x))], 1), axes=(0,)),
        Grid([Axis(-2.5, 2.5, 101), Axis(-PI, PI, 64, periodic=True)]),
        "average",
        state_cost=lambda x: W_CK * (x[:, 0] - np.sin(x[:, 1])) ** 2,
        temperature=LAM_CK,
    )


def clock_parts(W=W_CK, lam=LAM_CK):
    """Closed form (periodic LQ tracking, SPEC §6 with a periodic target): P = √(2W), p(s) =
    A sin s + B cos s with B = −2W/(1 + P²), A = P B; c = ⟨−p²/2 + λP/2 + W sin² s⟩ = −(A² + B²)/4
    + λP/2 + W/2; c₀(s) = [(B² − A²)/4 + W/2] sin 2s / 2 − (AB/2) cos 2s / 2; h = ½ P x² + p x +
    c₀ − its least value."""
    P = math.sqrt(2 * W)
    B = -2 * W / (1 + P * P)
    A = P * B
    c = -(A * A + B * B) / 4 + lam * P / 2 + W / 2
    k1, k2 = ((B * B - A * A) / 4 + W / 2) / 2, -(A * B / 2) / 2

    def h(x, s):
        p = A * np.sin(s) + B * np.cos(s)
        return 0.5 * P * x**2 + p * x + k1 * np.sin(2 * s) + k2 * np.cos(2 * s)

    ss = np.linspace(-PI, PI, 200001)
    p = A * np.sin(ss) + B * np.cos(ss)
    hmin = np.min(k1 * np.sin(2 * ss) + k2 * np.cos(2 * ss) - p**2 / (2 * P))
    return c, h, hmin


def clock_truth(X):
    X = np.asarray(X)
    c, h, hmin = clock_parts()
    return np.concatenate([[c], h(X[:, 0], X[:, 1]) - hmin]), np.zeros(len(X) + 1)


def clock_check():
    """The closed form against tracker_1d over long horizons T = 10π, 12π: (v(12π) − v(10π))/2π
    → c; at one s₀, v(x, s₀; 12π) − cT − h(x, s₀) is one constant in x; and over horizons that
    end at the same phase, one constant in s₀ too (h's s-part)."""
    c, h, _hmin = clock_parts()
    vs = {}
    X = S((0.5, 0.3), (-1.0, 0.3), (1.2, 0.3), (0.0, 2.0), (0.0, -2.5))
    for T in (10 * PI, 12 * PI):
        vs[T] = np.array(
            [
                float(tracker_1d(lambda t, s0=s0: math.sin(s0 + t), W_CK, 0.0, LAM_CK, T)(x0))
                for x0, s0 in X
            ]
        )
    print("clock c", c, "from T 10π/12π:", (vs[12 * PI] - vs[10 * PI]) / (2 * PI))
    d = vs[12 * PI] - c * 12 * PI - h(X[:, 0], X[:, 1])
    print("clock: v − cT − h at s₀ = 0.3 (one constant):", d[:3])
    # along s: with a horizon T ending at the same absolute phase, v(0, s; T) − c T − h(0, s) is
    # one constant: T = 12π − s₀ + 0.3 ends at s = 0.3 + 12π for every s₀
    Y = S((0.0, 0.3), (0.0, 2.0), (0.0, -2.5), (0.7, 1.1))
    e = [
        float(
            tracker_1d(lambda t, s0=s0: math.sin(s0 + t), W_CK, 0.0, LAM_CK, 12 * PI + 0.3 - s0)(x0)
        )
        - c * (12 * PI + 0.3 - s0)
        - h(x0, s0)
        for x0, s0 in Y
    ]
    print("clock: same end phase, v − cT − h (one constant):", np.round(e, 8))


# ---------------- 14. a parameter as a frozen state axis ----------------------------------------
def param_axis():
    """A user solves a family of springs at once: the stiffness k as a third state with k̇ = 0 (no
    control, no noise): ẋ₀ = x₁, ẋ₁ = −k x₀ − 0.3 x₁ + u, q = x₀² + 0.2 x₁², g = x₀² + 0.5 x₁²,
    λ = 0.4, T = 2; 61 × 61 × 11 on [−3, 3] × [−4, 4] × [−1, 4] (k from an unstable −1 to 4,
    0.5 apart); checked at k between the nodes."""

    def drift(x):
        return np.stack([x[:, 1], -x[:, 2] * x[:, 0] - 0.3 * x[:, 1], 0 * x[:, 0]], 1)

    return Problem(
        Shaped(3, drift=drift, axes=(1,)),
        Grid([Axis(-3, 3, 61), Axis(-4, 4, 61), Axis(-1, 4, 11)]),
        2.0,
        Quadratic([0.0, 0.0, 0.0], [1.0, 0.5, 0.0]),
        state_cost=lambda x: x[:, 0] ** 2 + 0.2 * x[:, 1] ** 2,
        temperature=0.4,
    )


def param_truth(X):
    """Riccati (round 15's) for each state's own k."""
    X = np.asarray(X)
    out = []
    for x0, x1, k in X:
        A = np.array([[0.0, 1.0], [-k, -0.3]])
        f = ricc_truth(
            A, [[0.0], [1.0]], [[1.0]], np.diag([1.0, 0.2]), np.diag([1.0, 0.5]), 0.4, 2.0
        )
        out.append(float(f(np.array([[x0, x1]]))[0][0]))
    return np.array(out), np.zeros(len(X))


# ---------------- 15. first exit across a cliff band, cold ---------------------------------------
def band_q(y):
    return 0.3 + np.where((y > -0.83) & (y < -0.31), 2.0, 0.0)


def fe_cliff_band():
    """ẋ = u on [−2, 2]² (81²), exit x₀ ≥ 0.45 (a Box), exit cost 0, q = 0.3 + 2 on the band
    −0.83 < x₀ < −0.31 (cliffs 0.4 and 0.8 cells off the nodes), λ = 0.05: paths from the left must
    cross the band."""
    return Problem(
        r12.free(2),
        r12.box2(81),
        None,
        state_cost=lambda x: band_q(x[:, 0]),
        temperature=0.05,
        exit=Box([r13.A_E, -INF], [INF, INF]),
        exit_cost=const(0.0),
    )


# ---------------- 16. a combination of saved and loaded solutions, weights 10⁻³ and 10³ ----------
W_CL = (1e-3, 1e3)


def combo_loaded_run(name):
    """round 16's two far-away LQ components (shifted_far with goals c + (1, 0.5), c − (1, 1)),
    each solved by default, saved by gridlbc.save, read back by gridlbc.load, and combined with
    weights (10⁻³, 10³)."""
    _b, X, *_ = P18[name]

    def comps():
        sols = []
        for i, p in enumerate(r16.mix_far_goals_components()):
            s = gridlbc.solve(p)
            path = OUT / f"{name}_{i}.npz"
            gridlbc.save(s, path)
            sols.append(gridlbc.load(path))
        return sols

    r13.save_combination(name, X, comps, list(W_CL), OUT, r16._warned)


def combo_loaded_truth(X):
    """The composite desirability Σ w_i e^{−v_i/λ} of the components' exact LQ values (round 16's
    lq_affine with the linear term)."""
    Y = np.asarray(X) - r16.C_FAR
    lam = 0.25
    vs = [
        r16.lq_affine(r16.A_FAR, np.eye(2), np.eye(2), r16.W_FAR, 2 * np.eye(2), c, lam, 2.0)(Y)
        for c in r16.GOALS_FAR
    ]
    m = np.minimum(*vs)
    v = m - lam * np.log(sum(w * np.exp(-(vi - m) / lam) for w, vi in zip(W_CL, vs)))
    return v, np.zeros(len(v))


P18 = {
    "track_time_axis": (
        track_time_axis,
        S((0.3, 0.0), (-1.0, 0.7), (1.2, 1.5), (0.0, 1.1)),
        track_truth,
        "ricc",
    ),
    "track_time_4d": (
        track_time_4d,
        S((0.5, -0.5, 0.3, 0.0), (-1.0, 1.0, -0.8, 0.8), (0.2, 0.4, 1.0, 2.0)),
        track4_truth,
        "ricc",
    ),
    "cliff_plateau": (
        cliff_plateau,
        S((0.0, 0.0), (-0.8, 0.5), (1.0, -1.0), (0.6, 0.3)),
        sep_cn([(zero, cliff_q, zero), (zero, quarter, zero)], 0.1, 1.5),
        "1-D",
    ),
    "cliff_cold": (
        cliff_cold,
        S((0.0, 0.0), (-0.8, 0.5), (1.0, -1.0), (0.6, 0.3)),
        sep_cn([(zero, cliff_q, zero), (zero, quarter, zero)], 0.01, 1.5),
        "1-D",
    ),
    "long_lq": (
        long_lq,
        S((0.0, 0.0), (1.5, -1.0), (-2.0, 2.0)),
        ricc_truth(A_LONG, np.eye(2), np.eye(2), W_LONG, WT_LONG, 0.5, 80.0),
        "ricc",
    ),
    "long_saturation": (
        long_saturation,
        S((0.0, 0.0), (1.0, 0.5), (-1.5, -1.2)),
        sep_cn([(sat_a0, sat_q0, zero), (sat_a1, sat_q1, zero)], 0.4, 30.0, method=be_1d),
        "1-D",
    ),
    "aniso_3d": (
        aniso_3d,
        S((0.005, 0.3, -10.0), (-0.01, -1.0, 20.0), (0.012, 0.8, 5.0)),
        aniso_truth,
        "ricc",
    ),
    "rcost_huge": (
        rcost_huge,
        S((0.5, 0.3), (-1.0, 0.8), (1.2, -1.2)),
        ricc_truth(A_RH, np.eye(2), 200 * np.eye(2), np.eye(2), np.eye(2), 0.5, 3.0),
        "ricc",
    ),
    "hot_3d": (
        hot_3d,
        S((0.5, -0.5, 0.3), (-1.5, 1.0, 1.0), (2.0, 0.5, -1.5)),
        ricc_truth(A_H3, B_H3, np.eye(3), np.diag([1.0, 0.2, 0.5]), np.diag([2.0, 1, 1]), 2.9, 1.0),
        "ricc",
    ),
    "exit_line_torus": (
        exit_line_torus,
        S((1.0, 0.0), (-1.0, 2.0), (2.8, -1.0), (-0.3, 0.5)),
        torus_line_truth(0.0),
        "exact",
    ),
    "exit_line_between": (
        exit_line_between,
        S((1.0, 0.0), (-1.0, 2.0), (2.8, -1.0), (-0.3, 0.5)),
        torus_line_truth(PI / 64, 2.2 * 2 * PI / 64),
        "exact",
    ),
    "embedded_1d_3d": (
        embedded_1d_3d,
        S((0.0, 0.5, -0.5), (-1.0, 1.0, 1.0), (1.2, -1.5, 0.3), (0.6, 0.0, 0.0)),
        sep_cn([(flow_e, step_q, kink_g)], 0.15, 1.2),
        "1-D",
    ),
    "embedded_1d_4d": (
        embedded_1d_4d,
        S((0.0, 0.5, -0.5, 0.0), (-1.0, 1.0, 1.0, -1.0), (1.2, -1.5, 0.3, 0.7)),
        sep_cn([(flow_e, step_q, kink_g)], 0.15, 1.2),
        "1-D",
    ),
    "hopf": (hopf, S((0.0, 0.0), (1.0, 0.0), (0.5, -0.6), (-1.4, 1.0)), radial_cn(0.3), "1-D"),
    "hopf_cold": (
        hopf_cold,
        S((0.0, 0.0), (1.0, 0.0), (0.5, -0.6), (-1.4, 1.0)),
        radial_cn(0.05),
        "1-D",
    ),
    "combo_extreme": (
        combo_extreme,
        S((0.0, 0.0), (-0.5, 1.0), (0.2, -1.2), (-1.5, 0.4)),
        combo_truth,
        "exact",
    ),
    "well_between": (
        well_between,
        S((0.0, 0.0), (-0.4, 0.5), (0.6, -1.0)),
        sep_cn([(zero, well_q, zero), (zero, q02, zero)], 0.02, 2.0, method=be_1d),
        "1-D",
    ),
}
P18.update(
    {
        "time_pulse": (
            time_pulse,
            S((0.0, 0.0), (1.5, 0.5), (-1.0, 0.9), (0.5, 1.02)),
            pulse_truth,
            "ricc",
        ),
        "time_cliff": (
            time_cliff,
            S((0.0, 0.0), (1.5, 0.5), (-1.0, 0.9), (0.5, 1.02)),
            time_cliff_truth,
            "ricc",
        ),
        "time_cliff_blind": (
            time_cliff_blind,
            S((0.0, 0.5), (-1.0, 1.2), (2.0, 1.9), (0.5, 1.6)),
            time_cliff_blind_truth,
            "ricc",
        ),
        "sliding_cold": (
            sliding_cold,
            S((0.0, 0.0), (0.37, 0.5), (1.5, -1.0), (-1.2, 0.3)),
            sep_cn([(slide_a, slide_q, zero), (zero, quarter, zero)], 0.02, 2.0, method=be_1d),
            "1-D",
        ),
        "sliding_frozen": (
            sliding_frozen,
            S((0.0, 0.0), (0.37, 0.5), (1.5, -1.0), (-1.2, 0.3)),
            sep_cn([(slide_a, slide_q, zero), (zero, quarter, zero)], 0.005, 2.0, method=be_1d),
            "1-D",
        ),
        "sliding_wide": (
            sliding_wide,
            S((0.0, 0.0), (0.37, 0.5), (1.5, -1.0), (-1.2, 0.3)),
            sep_cn([(wide_a, slide_q, zero), (zero, quarter, zero)], 0.005, 2.0, method=be_1d),
            "1-D",
        ),
        "stiff_pull": (
            stiff_pull,
            S((0.0, 0.0), (0.37, 0.5), (1.5, -1.0), (-1.2, 0.3)),
            sep_cn([(pull_a, slide_q, zero), (zero, quarter, zero)], 0.005, 2.0, method=be_1d),
            "1-D",
        ),
        "sliding_node": (
            sliding_node,
            S((0.0, 0.0), (0.37, 0.5), (1.5, -1.0), (-1.2, 0.3)),
            sep_cn([(node_a, slide_q, zero), (zero, quarter, zero)], 0.005, 2.0, method=be_1d),
            "1-D",
        ),
        "sliding_3d": (
            sliding_3d,
            S((0.0, 0.0, 0.0), (0.37, 0.5, -0.5), (1.5, -1.0, 0.3), (-1.2, 0.3, 1.0)),
            sep_cn(
                [(slide_a, slide_q, zero), (zero, quarter, zero), (zero, quarter, zero)],
                0.01,
                2.0,
                method=be_1d,
            ),
            "1-D",
        ),
        "exit_line_cold": (
            exit_line_cold,
            S((1.0, 0.0), (-1.0, 2.0), (2.8, -1.0), (-0.3, 0.5)),
            torus_line_truth(0.0, lam=0.02),
            "exact",
        ),
        "rcost_box": (
            rcost_box,
            S((0.5, 0.3), (-1.0, 0.8), (1.2, -1.2)),
            ricc_truth(A_RH, np.eye(2), 200 * np.eye(2), np.eye(2), np.eye(2), 0.5, 3.0),
            "ricc",
        ),
        "track_long": (
            track_long,
            S((0.3, 0.0), (-1.0, 1.7), (1.2, 3.5), (0.0, 2.2)),
            track_long_truth,
            "ricc",
        ),
        "embedded_idle5": (
            embedded_idle5,
            S((0.0, 0.5, -0.5), (-1.0, 1.0, 1.0), (1.2, -1.5, 0.3), (0.6, 0.0, 0.0)),
            sep_cn([(flow_e, step_q, kink_g)], 0.15, 1.2),
            "1-D",
        ),
        "hopf_frozen": (
            hopf_frozen,
            S((0.0, 0.0), (1.0, 0.0), (0.5, -0.6), (-1.4, 1.0)),
            radial_cn(0.01),
            "1-D",
        ),
        "hopf_stiff": (
            hopf_stiff,
            S((0.0, 0.0), (1.0, 0.0), (0.5, -0.6), (-1.4, 1.0)),
            radial_cn(0.05, K=15.0, rmax=2.5, ns=((8001, 8000), (16001, 16000))),
            "1-D",
        ),
        "track_cold": (
            track_cold,
            S((0.3, 0.0), (-1.0, 0.7), (1.2, 1.5), (0.0, 1.1)),
            track_cold_truth,
            "ricc",
        ),
        "fe_deadline": (
            fe_deadline,
            S((-1.0, 0.0), (-2.5, 1.5), (2.0, -1.0), (-0.3, 2.0)),
            deadline_truth,
            "ricc",
        ),
        "avg_clock": (
            avg_clock,
            S((0.5, 0.3), (-1.0, 2.0), (1.2, -2.5)),
            clock_truth,
            "exact",
        ),
        "param_axis": (
            param_axis,
            S((0.5, -0.5, 0.25), (-1.0, 1.0, 1.3), (1.5, 0.8, 3.1), (0.0, 2.0, -0.6)),
            param_truth,
            "ricc",
        ),
        "fe_cliff_band": (
            fe_cliff_band,
            S((0.0, 0.0), (-0.5, 0.5), (-1.2, -1.0), (-1.9, 1.0)),
            r13.bvp_1d(zero, lambda y: 1.0 + 0 * y, band_q, 0.05),
            "bvp",
        ),
        "combo_loaded": (
            r16.shifted_far,
            S((100.0, -50.0), (101.0, -49.5), (98.5, -51.0)),
            combo_loaded_truth,
            "ricc",
        ),
        "sliding_mode": (
            sliding_mode,
            S((0.0, 0.0), (0.37, 0.5), (1.5, -1.0), (-1.2, 0.3)),
            sep_cn([(slide_a, slide_q, zero), (zero, quarter, zero)], 0.1, 2.0),
            "1-D",
        ),
    }
)


for _base in ("well_between", "exit_line_cold", "time_pulse", "fe_cliff_band"):
    P18[f"{_base}_loaded"] = P18[_base]


NOT_TABLED = {"rcost_box"}  # its truth (the unbounded Riccati value) is not the box problem's


def main(argv):
    # round 16's command line and table (round 12's runner, round 15's quick that records a
    # solve that raises) on this round's problems
    r16.P16, r16.OUT = P18, OUT
    r12._warned = r16._warned
    if "--table" in argv:
        r16.P16 = {k: v for k, v in P18.items() if k not in NOT_TABLED}
        r16.table16()
        return
    if "--check" in argv:
        track_check()
        pulse_check()
        clock_check()
        X = S((1.0, 0.0), (-1.0, 2.0), (2.8, -1.0), (-0.3, 0.5))
        for c, wd in ((0.0, 0.002), (PI / 64, 2.2 * 2 * PI / 64)):
            print("torus line", torus_line_truth(c, wd)(X)[0], "FD", torus_line_fd(c, X, wd))
        return
    r15.OUT = OUT
    r15.P15, r15.EXTRA15 = P18, {}
    r13.P13, r13.OUT, r12.quick = P18, OUT, r15.quick
    r12.P12, r12.OUT = P18, OUT
    OUT.mkdir(exist_ok=True)
    special = {
        "combo_extreme": combo_run,
        "combo_loaded": combo_loaded_run,
    }
    special.update({n: saveload_run for n in P18 if n.endswith("_loaded") and n not in special})
    names = [a for a in argv if not a.startswith("--")]
    flags = [a for a in argv if a.startswith("--")]
    if not any(f in flags for f in ("--levels", "--finer", "--tol")):
        for name in [n for n in names if n in special]:
            if "--truth" not in flags:
                special[name](name)
            r12.truth(name)
        names = [n for n in names if n not in special]
        if not names:
            return
    r13.main(names + flags)


if __name__ == "__main__":
    main(sys.argv[1:])
