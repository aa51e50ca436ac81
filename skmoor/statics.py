"""Static equilibrium: Newton with load continuation, line search and a vanishing
regularization (needed to start from a slack, stress-free line whose tangent is singular).
"""
from __future__ import annotations

from dataclasses import dataclass

import warnings

import numpy as np
import scipy.sparse.linalg as spla


class ConvergenceError(RuntimeError):
    """A Newton solve did not converge; the message says where and what to try."""


@dataclass
class StaticSolution:
    x: np.ndarray  # reduced state, m / rad
    iterations: int
    residual: float  # final max |R|, N


def newton(residual, x0, *, xtol=1e-9, maxiter=60, shift=None, shift_matrix=None,
           relax_matrix=None, where="static solve"):
    """Solve residual(x) = (R, K) = 0 from x0 with a backtracking line search.

    shift_matrix (sparse, n x n) times ``shift`` is added to the tangent, cut tenfold
    each iteration and gone after six: with the
    geometric stiffness of a unit tension and a shift of the order of the expected
    tension, Newton starts from a slack, stress-free line whose own tangent is singular.
    relax_matrix (sparse, n x n: the mass matrix): pseudo-transient continuation, the
    tangent K + c M with c (1/s^2) first a hundredth of K's over M's largest diagonal and
    then scaled by each iteration's residual ratio |R_k| / |R_k-1| (switched evolution
    relaxation, Mulder & van Leer 1985) until it is 1e-8 of its start and dropped: a
    damped march towards the equilibrium far from it, Newton near it.
    Converged when max |dx| < xtol (m or rad) in a step without shift or relaxation.
    """
    x = np.array(x0, float)
    if x.size == 0:  # nothing free (a network of coupled objects alone)
        return StaticSolution(x, 0, 0.0)
    R, K = residual(x)
    shift = float(shift or 0.0)
    floor = shift * 1e-6
    relax = relax_floor = 0.0
    if relax_matrix is not None:
        ratio = np.abs(K.diagonal()).max() / max(np.abs(relax_matrix.diagonal()).max(), 1e-300)
        relax, relax_floor = 1e-2 * ratio, 1e-10 * ratio
    norm = np.linalg.norm(R)
    for it in range(1, maxiter + 1):
        A = K + shift * shift_matrix if shift > 0 else K
        if relax > 0:
            A = A + relax * relax_matrix
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore", spla.MatrixRankWarning)
            try:
                dx = spla.spsolve(A.tocsc(), -R)
            except RuntimeError:  # SuperLU: "failed to factorize" an exactly singular A
                dx = np.full_like(R, np.nan)
        if not np.all(np.isfinite(dx)):
            raise ConvergenceError(f"{where}: singular tangent at iteration {it}; is a line "
                                   "slack and weightless, or a DOF unrestrained? (a static "
                                   "solve from a slack line takes pretension=...)")
        _step, (x_try, R_try, K_try) = line_search(residual, x, R, dx)
        converged = shift == 0 and relax == 0 and np.max(np.abs(dx)) < xtol
        x, R, K = x_try, R_try, K_try
        shift = shift * 0.1 if shift * 0.1 >= floor else 0.0
        if relax > 0:
            norm, previous = np.linalg.norm(R), norm
            relax = relax * norm / previous if np.isfinite(norm) else relax
            relax = relax if relax >= relax_floor else 0.0
        if converged:
            return StaticSolution(x, it, float(np.max(np.abs(R))))
    raise ConvergenceError(f"{where}: no convergence in {maxiter} iterations "
                           f"(max |R| = {np.max(np.abs(R)):.3g} N); try more load steps "
                           "(steps=...), a pretension, or a better first guess")


def line_search(residual, x, R, dx, maxeval=10):
    """Step length along dx where the residual's projection R . dx has fallen to half
    its start (the minimum of the potential along dx for a conservative system), by
    the Illinois variant of regula falsi; the full step when it already has."""
    slope0 = R @ dx
    state = residual(x + dx)
    slope1 = state[0] @ dx
    if not np.isfinite(slope1) or slope0 >= 0 or slope1 <= 0.5 * abs(slope0):
        return 1.0, (x + dx,) + state  # NaN is caught by the caller; else still going down
    a, fa, b, fb = 0.0, slope0, 1.0, slope1
    for _ in range(maxeval):
        c = b - fb * (b - a) / (fb - fa)
        state = residual(x + c * dx)
        fc = state[0] @ dx
        if abs(fc) <= 0.5 * abs(slope0):
            break
        if fc * fb < 0:
            a, fa = b, fb
        else:
            fa *= 0.5
        b, fb = c, fc
    return c, (x + c * dx,) + state


def solve_static(system, x0=None, *, steps=1, t=0.0, xtol=1e-9, maxiter=60,
                 pretension=None, held=None, relax=False):
    """Static equilibrium of a :class:`~skmoor.coupling.System` at time t.

    steps > 1 ramps the weight and the body's static load in equal increments (load
    continuation), each solved from the previous one. pretension (N): a temporary
    tension stiffness that lets Newton start from a slack, stress-free line (use about
    the line's weight); it is removed before convergence, so it does not change the
    answer. held: indices of reduced DOFs kept at their x0 values (e.g. free points held
    where they are given, to release them from there). relax: pseudo-transient
    continuation on the system's mass matrix (see :func:`newton`), for networks whose
    plain Newton wanders; it too is gone before convergence.

    The lines' static laws act here (:class:`skmoor.laws.StaticDynamic`: the static
    stiffness); the solution (without held DOFs: the equilibrium of the whole network)
    becomes their mean state, about which the dynamic laws act. Where Newton fails on
    tension-only lines (an iterate with slack elements has no stiffness there), the
    solve is continued from lines that push to tension-only ones (their compression
    let through by 1, 0.1, ... 1e-4, then 0, each stage from the last one's state).
    """
    lines = system.lines
    lines.use_static_laws(True)
    try:
        try:
            solution = _solve_static(system, x0, steps, t, xtol, maxiter, pretension, held,
                                     relax)
        except ConvergenceError:
            if not lines.tension_only:
                raise
            solution = _soft_compression(system, x0, steps, t, xtol, maxiter, pretension,
                                         held)
    finally:
        lines.use_static_laws(False)
    if lines.has_static_laws and held is None:
        lines.set_static_state(system.full_displacement(solution.x, t))
    return solution


COMPRESSION_STAGES = (1.0, 1e-1, 1e-2, 1e-3, 1e-4)


def _soft_compression(system, x0, steps, t, xtol, maxiter, pretension, held):
    """The static solve of tension-only lines by continuation in the compression they
    carry (``COMPRESSION_STAGES``, then none), with a pretension of at least the largest
    unbalanced load at x0 (N; a weightless slack line holding a weight gets none from
    its own weight)."""
    lines, x, total = system.lines, x0, 0
    start = np.zeros(system.n) if x0 is None else np.asarray(x0, float)
    pretension = max(pretension or 0.0, float(np.max(np.abs(system.residual(start, t=t)[0]))))
    try:
        for k, fraction in enumerate(COMPRESSION_STAGES):
            lines.carry_compression(fraction)
            stage = _solve_static(system, x, steps if k == 0 else 1, t, xtol, maxiter,
                                  pretension, held)
            x, total = stage.x, total + stage.iterations
    finally:
        lines.carry_compression(0.0)
    solution = _solve_static(system, x, 1, t, xtol, maxiter, pretension, held)
    solution.iterations += total
    return solution


def _solve_static(system, x0, steps, t, xtol, maxiter, pretension, held, relax=False):
    x = np.zeros(system.n) if x0 is None else np.array(x0, float)
    keep = np.setdiff1d(np.arange(system.n), [] if held is None else held)
    G = None
    if pretension:
        P = system.P(x)
        G = (P.T @ system.lines.unit_tension_stiffness() @ P).tocsr()[keep][:, keep]
    M = system.M.tocsr()[keep][:, keep] if relax else None
    total = 0
    for k in range(1, steps + 1):
        factor = k / steps

        def residual(y, factor=factor):
            full = x.copy()
            full[keep] = y
            R, K, _ = system.residual(full, t=t, load_factor=factor)
            return R[keep], K.tocsr()[keep][:, keep]

        sol = newton(residual, x[keep], xtol=xtol, maxiter=maxiter, shift=pretension,
                     shift_matrix=G, relax_matrix=M,
                     where=f"static solve, load step {k}/{steps}")
        x = x.copy()
        x[keep] = sol.x
        total += sol.iterations
    return StaticSolution(x, total, sol.residual)
