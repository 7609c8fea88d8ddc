"""Solved desirability on a grid, evaluated anywhere in state and time.

A :class:`Solution` stores time slices of the desirability in log-scaled form,

    z(x_node, t_j) = Z[j, node] · exp(ℓ_j),      max_node Z[j] = 1,

so that z may span far more than float64's range without underflowing as a whole. At any state x
and time t ∈ [t_j, t_{j+1}] (θ = (t − t_j)/(t_{j+1} − t_j)):

    z(x, t)      = (1 − θ) I[z_j](x) + θ I[z_{j+1}](x)          (I: barycentric interpolation)
    v(x, t)      = −λ log z(x, t)
    u*(x, t)     = λ R⁻¹ I[Bᵀ∇z](x, t) / z(x, t)

with ∇z by finite differences at the simplex vertices. All three interpolants are linear in the
nodal z, so combinations of solutions evaluate exactly as the solution of the combined problem.

Linear interpolation of z is poor where v/λ changes by more than about one per cell: there z
varies by a large factor across a cell, and the central difference of z overstates ∇z/z by
sinh(Δ)/Δ for a rise Δ of v/λ per cell (a factor of 3 at Δ = 3, and far more beyond). The
fitted solvers therefore store and interpolate as their fitted step does: a solution knows its
:attr:`Solution.representation` (:mod:`gridlbc.representation`: :class:`LinearZ` above,
:class:`~gridlbc.representation.RelativeZ` relative to a shared fitting reference φ, :class:`LogZ`
for a solve fitted to its own terminal cost), and one evaluation path asks it for the interpolated
fields.

A solution also knows the operator that made it (:class:`OperatorSignature`: scheme, Δt,
fitting reference): solutions of one linear operator combine exactly (:func:`gridlbc.combine`).

States are ``(N, d)`` and give values ``(N,)`` and controls ``(N, m)``; one state ``(d,)`` gives a
scalar value and a control ``(m,)`` (:func:`gridlbc.problem.state_evaluation`, the convention of
every evaluation in the library).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from .grid import flat_chunks
from .interpolate import barycentric
from .problem import Problem, bracket, check_time, state_evaluation
from .representation import Fields, LinearZ, RelativeZ, Representation, Stencil


class ErrorEstimate(Protocol):
    """What a solution's error estimate answers (:class:`gridlbc.accuracy.EmbeddedEstimate`, which
    :mod:`gridlbc.accuracy` attaches after the solve): abs(v − v_exact) at states ``x`` (N, d),
    time ``t`` (:meth:`Solution.error_estimate`), and the order its coarser levels converge at
    (``observed_order``)."""

    observed_order: float

    def error(self, solution, x, t=0.0) -> np.ndarray: ...


FittingReference = RelativeZ
"""The former name of :class:`gridlbc.representation.RelativeZ` (log φ at the stored times)."""


@dataclass(frozen=True)
class SolveDiagnostics:
    """What a solve did and cost.

    Attributes
    ----------
    method : str
        The scheme (:data:`gridlbc.METHODS`).
    dt : float
        The time step.
    steps : int
        How many steps.
    store_every : int
        Every k-th step's slice is kept.
    wall_time, setup_time : float
        Seconds in total and building the step operator.
    underflow_nodes : int
        Nodes whose desirability is zero at t = 0 (value +inf there).
    stored_bytes, operator_bytes : int
        Bytes of the kept slices and of the step operator.
    courant : float
        max_k max|a_k| Δt / h_k.
    iterations : tuple of int
        Per-step iteration counts of an iterative solve (empty for direct and splitting steps).
    flushed_values : int
        Stored values that were positive in the float64 time stepping but rounded to zero by
        float32 storage (far below their slice's maximum; value +inf there).
    memory_estimate : int
        The bytes the solve was estimated to need (checked before allocating).
    fitting : str
        ``"none"``, or a fingerprint of the reference the drift was fitted to (as
        :attr:`OperatorSignature.reference <gridlbc.solution.OperatorSignature.reference>`).
    """

    method: str
    dt: float
    steps: int
    store_every: int
    wall_time: float
    setup_time: float
    underflow_nodes: int
    stored_bytes: int
    operator_bytes: int
    courant: float
    iterations: tuple[int, ...] = ()
    flushed_values: int = 0
    memory_estimate: int = 0
    fitting: str = "none"


@dataclass(frozen=True)
class OperatorSignature:
    """The step operator a solution was marched with: solutions of one problem with equal
    signatures (and equal stored times) are images of one linear map of their terminal data, so
    they combine exactly (paper §3; :func:`gridlbc.combine` compares signatures).

    Parameters
    ----------
    method : str
        The scheme (:data:`gridlbc.METHODS`).
    dt : float
        The time step Δt.
    reference : str
        ``"none"`` (the plain operator, independent of the terminal cost) or the digest of the
        fitting reference φ that the operator was built from.
    log_domain : bool
        Whether the solve was stepped in log z (a single terminal cost fitted to itself): its
        slices between t = 0 and T are then not linear in z, even where φ is the same.
    """

    method: str
    dt: float
    reference: str = "none"
    log_domain: bool = False


class FieldEvaluation:
    """Value, desirability and policy anywhere from
    interpolated :class:`~gridlbc.representation.Fields` (:mod:`gridlbc.representation`): the one
    evaluation path that :class:`Solution` and
    :class:`gridlbc.CombinedSolution` share. Subclasses provide ``problem`` and
    ``fields(x, t, gradient)``."""

    problem: Problem

    def fields(self, x, t, gradient: bool = True) -> Fields:
        """The interpolated :class:`~gridlbc.representation.Fields` at states ``x``, time ``t``."""
        raise NotImplementedError

    @property
    def temperature(self) -> float:
        return self.problem.temperature

    def scaled_fields(self, x, t, gradient: bool = True):
        """Interpolated z and Bᵀ∇z at states ``x``, time ``t``, up to a common factor e^L.

        Returns ``(L, z, g)`` with z(x, t) = z · e^L of shape ``(N,)`` and Bᵀ∇z(x, t) = g · e^L of
        shape ``(N, m)`` (``g`` is ``None`` when ``gradient`` is false). The building block of
        :func:`gridlbc.combine`.
        """
        return self.fields(x, t, gradient).scaled()

    @state_evaluation
    def log_desirability(self, x, t=0.0) -> np.ndarray:
        """log z(x, t), shape ``(N,)`` (a scalar for one state ``(d,)``) (−inf where z underflowed,
        with an UnderflowWarning)."""
        return self.fields(x, t, gradient=False).log_desirability()

    @state_evaluation
    def desirability(self, x, t=0.0) -> np.ndarray:
        """z(x, t) = exp(−v/λ), shape ``(N,)`` (a scalar for one state ``(d,)``). May underflow to 0
        far from the goal: use :meth:`log_desirability`
        or :meth:`~gridlbc.solution.FieldEvaluation.value` for the full range."""
        L, z, _ = self.scaled_fields(x, t, gradient=False)
        with np.errstate(under="ignore", over="ignore"):
            return z * np.exp(L)

    @state_evaluation
    def value(self, x, t=0.0) -> np.ndarray:
        """Optimal cost-to-go v(x, t) = −λ log z(x, t), shape ``(N,)`` (a scalar for one state
        ``(d,)``)."""
        return -self.temperature * self.log_desirability(x, t)

    @state_evaluation
    def policy(self, x, t=0.0) -> np.ndarray:
        """Optimal control u*(x, t) = λ R⁻¹ Bᵀ∇z / z = −R⁻¹ Bᵀ∇v, shape ``(N, m)`` (``(m,)`` for one
        state)."""
        return self.fields(x, t).policy(self.temperature, self.problem.R_inv)


INPUT_MATRIX_ENTRIES = 1 << 21
"""At most this many entries of B over the nodes (16 MiB) are kept with a solution, for the policy
read at many states (:meth:`Solution._input_matrix_nodes`)."""


@dataclass(frozen=True, eq=False)
class Solution(FieldEvaluation):
    """The solved desirability of a :class:`gridlbc.Problem` (one terminal cost).

    Attributes
    ----------
    problem : Problem
    times : ndarray (S,)
        Times of the stored slices, increasing from 0 to T.
    slices : ndarray (S, N)
        The stored nodal data (max 1 per slice, as ``representation`` says: z/e^ℓ, or
        log z − ℓ), float64 or float32.
    log_scales : ndarray (S,)
        ℓ_j of each slice.
    diagnostics : SolveDiagnostics
    operator : OperatorSignature
        The step operator that made it (what :func:`gridlbc.combine` compares).
    representation : LinearZ, RelativeZ or LogZ
        What the slices hold and how they are interpolated (:mod:`gridlbc.representation`).
    embedded : gridlbc.accuracy.EmbeddedEstimate or None
        The solves on the embedded grids that :meth:`error_estimate` reads (None if not solved:
        ``error_estimate=False``, or a grid too coarse to embed).
    refinement : tuple of gridlbc.accuracy.Refinement
        With ``solve(tol=...)``: the solves that led to this one (empty otherwise).
    """

    problem: Problem
    times: np.ndarray
    slices: np.ndarray
    log_scales: np.ndarray
    diagnostics: SolveDiagnostics
    operator: OperatorSignature
    representation: Representation = field(default_factory=LinearZ)
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    embedded: ErrorEstimate | None = field(default=None, repr=False, compare=False)
    refinement: tuple = field(default=(), repr=False, compare=False)

    @property
    def grid(self):
        return self.problem.grid

    @property
    def reference(self) -> RelativeZ | None:
        """The fitting reference φ of a :class:`~gridlbc.representation.RelativeZ` solution (its log
        φ at the stored times), else None."""
        return self.representation if isinstance(self.representation, RelativeZ) else None

    @property
    def nbytes(self) -> int:
        """Bytes held by the stored slices and their scales."""
        return int(self.slices.nbytes + self.log_scales.nbytes + self.times.nbytes)

    @state_evaluation
    def error_estimate(self, x, t=0.0) -> np.ndarray:
        """An a-posteriori estimate of ``abs(v(x, t) − v_exact(x, t))`` (docs page
        :doc:`accuracy`): the Richardson estimate ``abs(v_2h(x, t) − v(x, t)) / (2^q − 1)``
        from the embedded solve (grid spacing 2h, step 2Δt) with the observed order q where the
        two are close (1 elsewhere), at least the difference between the solves on the pair of
        :func:`gridlbc.accuracy.phase_pair` (which sees features between nodes; solved where
        the problem may have one, :func:`gridlbc.accuracy.reads_pair`), at least
        the typical relative error (:class:`gridlbc.accuracy.EmbeddedEstimate`), at least what
        the costs' excess between the nodes changes in the embedded solve (a goal or a well
        narrower than a cell: :mod:`gridlbc.accuracy.subcell`), and at least the cost that the
        grid's interpolants of the costs add along the solve's paths
        (:func:`gridlbc.accuracy.cost_gap`, sampled with a fixed seed from 16 paths per state);
        for a stationary solve also at least the generator's truncation error carried along the
        paths (:func:`gridlbc.accuracy.truncation_gap`: z falling faster than a cell carries);
        for a splitting solve with a horizon also at least what tracing each step's foot by two
        half steps changes along the paths (:func:`gridlbc.accuracy.tracing_gap`: a drift that
        switches within a step); and, for a task with a horizon or an exit set, at least the
        local certificate's abs(v_h − v_ℓ) less two of its standard errors, v_ℓ what the SDE
        makes of the solve's own values 8 steps later (:func:`gridlbc.accuracy.bellman_gap`: a
        value steeper than a cell where the costs are smooth), and the same for the whole
        remaining task where its paths are affordable (:func:`gridlbc.accuracy.local_error`:
        an error shared all the way to the horizon, next to an exit late in a task).

        Parameters
        ----------
        x : array_like (N, d) or (d,)
            States.
        t : float
            Time in [0, T].

        The sampled terms draw their paths from a fixed seed per call: the same states give the
        same estimate, and a state asked for with others differs from it asked for alone by the
        sampling noise.

        Returns
        -------
        ndarray (N,)
            The estimated absolute error of :meth:`~gridlbc.solution.FieldEvaluation.value` at each
            state (a scalar for one state); +inf where the value underflowed (it is +inf there,
            and nothing bounds its error).
        """
        if self.embedded is None:
            raise ValueError(
                "this solution carries no error estimate: it was solved with "
                "error_estimate=False, on a grid too coarse to embed (fewer than 5 nodes on "
                "an axis), or its problem cannot be posed on the grid with every other node (an "
                "exit set that holds none of its nodes: the solve warned); solve again with the "
                "default settings on a finer grid"
            )
        return self.embedded.error(self, x, t)

    # -- nodal access ---------------------------------------------------------------------------

    def log_desirability_nodes(self, j: int = 0) -> np.ndarray:
        """log z at every node of stored slice ``j`` (−inf where it underflowed), shape ``(N,)``.

        Parameters
        ----------
        j : int
            The stored slice (time ``times[j]``).
        """
        return self.representation.log_nodes(self.slices[j], self.log_scales[j])

    def value_nodes(self, j: int = 0) -> np.ndarray:
        """v = −λ log z at every node of stored slice ``j`` (+inf where z underflowed).

        Parameters
        ----------
        j : int
            The stored slice (time ``times[j]``).
        """
        return -self.temperature * self.log_desirability_nodes(j)

    def better_half(self) -> np.ndarray:
        """The flat mask of the nodes whose value at t = 0 is finite and at most its median over
        them: where a controlled process spends its time (the error estimate's judged states
        and the control-step check read it; docs page :doc:`accuracy`). Kept with the solution
        (read-only)."""
        if "better_half" not in self._cache:
            v = self.value_nodes(0)
            chosen = np.isfinite(v)
            if chosen.any():
                chosen &= v <= np.median(v[chosen])
            chosen.flags.writeable = False
            self._cache["better_half"] = chosen
        return self._cache["better_half"]

    # -- evaluation anywhere --------------------------------------------------------------------

    def _input_matrix_at(self, nodes: np.ndarray) -> np.ndarray:
        """B at the flat ``nodes`` (any shape), ``nodes.shape + (d, m)``: from B at every node,
        read once (:meth:`_input_matrix_nodes`), where that is kept."""
        B = self._input_matrix_nodes()
        if B is not None and B.ndim == 2:  # the same at every node
            return np.broadcast_to(B, nodes.shape + B.shape)
        if B is not None:
            return B[nodes]
        coords = self.grid.node_coordinates(nodes.ravel())
        B = np.asarray(self.problem.system.input_matrix(coords), dtype=float)
        return B.reshape(nodes.shape + B.shape[1:])

    def _input_matrix_nodes(self) -> np.ndarray | None:
        """B at every node, ``(size, d, m)``, or one ``(d, m)`` where it is the same at every
        node (a linear system's, or a pendulum's torque input); None where the grid holds more
        than :data:`INPUT_MATRIX_ENTRIES` entries of it (B is then read at the vertices each
        time). Kept with the solution."""
        if "input_matrix" in self._cache:
            return self._cache["input_matrix"]
        grid, system = self.grid, self.problem.system
        d, m = grid.ndim, system.control_dim
        B = None
        if system.linear_matrices() is not None:  # constant B: evaluate once
            B = np.asarray(system.input_matrix(grid.node_coordinates([0])), dtype=float)[0]
        elif grid.size * d * m <= INPUT_MATRIX_ENTRIES:
            B = np.empty((grid.size, d, m))
            for flat in flat_chunks(grid.size):
                coords = grid.node_coordinates(flat)
                B[flat[0] : flat[-1] + 1] = system.input_matrix(coords)
            if np.all(B[0] == B):
                B = B[0].copy()
        self._cache["input_matrix"] = B
        return B

    def stencil(self, x, t, gradient: bool = True) -> Stencil:
        """The simplices of states ``x`` ``(N, d)`` and the stored interval of time ``t``, with B
        at the vertices when ``gradient`` (:class:`~gridlbc.representation.Stencil`)."""
        grid = self.grid
        x = grid.check_states(x)
        j, theta = bracket(
            self.times, check_time(t, self.problem.require_horizon("a time-dependent solution"))
        )
        idx, bw = barycentric(grid, x)
        return Stencil(grid, idx, bw, j, theta, self._input_matrix_at(idx) if gradient else None)

    def fields(self, x, t, gradient: bool = True) -> Fields:
        """The representation's interpolated :class:`~gridlbc.representation.Fields` at states
        ``x`` ``(N, d)``, time ``t`` (the gradients, for the policy, only when ``gradient``); at
        the states in the exit set E, where the task has ended, the exact z = exp(−g_E/λ) and
        u = 0 (:meth:`~gridlbc.representation.Fields.ended`; SPEC §9: z = exp(−g_E/λ) on E),
        not the interpolant across E's boundary, which mixes in the values of the nodes outside
        it."""
        fields = self.fields_at(self.stencil(x, t, gradient))
        problem = self.problem
        if problem.exit is None:  # no further look at the states: the stencil checked them
            return fields
        x = problem.check_states(x)
        inside = problem.exit_mask(x)
        if not inside.any():
            return fields
        return fields.ended(inside, -problem.exit_values(x[inside]) / problem.temperature)

    def fields_at(self, stencil: Stencil) -> Fields:
        """The :meth:`fields` of a stencil already built (:meth:`stencil`), for a caller that
        reads it again (the estimate's paths read the state cost on the policy's stencil)."""
        return self.representation.fields(stencil, self.slices, self.log_scales)


@dataclass(frozen=True, eq=False)
class StationarySolution(Solution):
    """The solved desirability of a stationary problem (SPEC §9, :mod:`gridlbc.stationary`): a
    first-exit problem without a horizon, or the average-cost problem. One stored slice and no
    time: ``value(x)``, ``policy(x)``, ``desirability(x)`` accept a time ``t`` and ignore it.

    Attributes
    ----------
    problem : Problem
    times : ndarray (1,)
        ``[0.0]``: one slice, independent of time.
    slices : ndarray (1, N)
        z/e^ℓ at the nodes (max 1).
    log_scales : ndarray (1,)
        ℓ.
    diagnostics : SolveDiagnostics
        ``method`` "stationary", no steps; ``iterations`` of an iterative linear solve.
    operator : OperatorSignature
        ``method`` names the generator's rates; ``reference`` a digest of the generator, the
        exit nodes and q (solutions with equal signatures combine exactly).
    representation : LinearZ
        The slice holds z itself.
    embedded : gridlbc.accuracy.EmbeddedEstimate or None
        The solves on the embedded grids (:meth:`~gridlbc.Solution.error_estimate`).
    refinement : tuple of gridlbc.accuracy.Refinement
        With ``solve(tol=...)`` of a first-exit or average-cost problem: the solves that led to this one
        (:func:`gridlbc.stationary.solve_stationary_to_tolerance`); empty otherwise.
    average_cost : float or None
        The optimal cost per unit time c of an average-cost problem (its value is then the
        relative value h, min 0); None for first exit.
    average_cost_error : float or None
        The estimate of c's error (:class:`gridlbc.accuracy.estimate.ScalarEstimate`: from c on the
        grids h, 2h and 4h and the pair, and the state cost between the nodes under the
        stationary law); None for first exit or without the estimate.
    stationary_distribution : ndarray (N,) or None
        For average cost: the long-run share of time π_i that the solve's optimally controlled
        chain spends at each node (Σ π = 1; π ∝ e ⊙ ẽ, the right and left principal
        eigenvectors, :func:`gridlbc.stationary.average.stationary_distribution`), found with the
        error estimate (which samples the state cost under it); None otherwise.
    """

    average_cost: float | None = None
    average_cost_error: float | None = None
    stationary_distribution: np.ndarray | None = None

    def stencil(self, x, t=0.0, gradient: bool = True) -> Stencil:
        """The simplices of states ``x`` ``(N, d)`` (``t`` is ignored)."""
        grid = self.grid
        x = grid.check_states(x)
        idx, bw = barycentric(grid, x)
        B = self._input_matrix_at(idx) if gradient else None
        return Stencil(grid, idx, bw, 0, 0.0, B, steady=True)
