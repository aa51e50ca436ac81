"""Newton iteration shared by statics and the time step: the static Newton with its line
search, the time step's modified Newton, its iteration matrix and the divergence errors.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.linalg import lapack


@dataclass
class StaticSolution:
    x: np.ndarray  # reduced state, m / rad
    iterations: int
    residual: float  # final max |R|, N


class DivergenceError(RuntimeError):
    """The time integration could not continue; the message says when and what to try."""

    def __init__(self, message, t, step):
        super().__init__(message)
        self.t, self.step = t, step


DENSE_BELOW = 200  # unknowns: below this, dense LAPACK beats sparse overhead (measured)


CONTRACTION = 0.2  # the line search's Newton refreshes the tangent when |dx| shrinks slower
BROYDEN_CONTRACTION = 0.3  # the same for the time step's modified (Broyden) Newton
BROYDEN_HISTORY = 8  # Broyden corrections on one matrix before it is made new
BROYDEN_SCALING = 2.0  # a secant update scaling the correction more than this either way
# (past a kink of the residual: a node touching the bed) makes a new matrix instead
STALL = 0.5  # fresh tangents whose |dx| shrinks slower than this, twice: cycling at a kink


def matrix_layout(system):
    """'band' for a system with a narrow band (``system.bandwidth``, lines without a
    body: banded LAPACK, O(n)), else 'dense' below ``DENSE_BELOW`` unknowns, else 'sparse'."""
    n = system.M.shape[0]
    bandwidth = getattr(system, "bandwidth", None)
    if bandwidth is not None and 8 * bandwidth <= n:
        return "band"
    return "dense" if n < DENSE_BELOW else "sparse"


class _IterationMatrix:
    """The Newton matrix A = c_x M + (1 - af)(c_v (C + Kv) + K), factorized once and reused
    across iterations and steps (modified Newton) until convergence slows down."""

    def __init__(self, layout):
        self.layout, self.factor = layout, None

    def update(self, A):
        if self.layout == "dense":  # LAPACK directly: scipy's wrappers cost more here
            lu, piv, info = lapack.dgetrf(A)
            self.factor = None if info > 0 else (lu, piv)  # info > 0: singular
        elif self.layout == "band":
            self.factor = A.factorize()
        else:
            try:
                self.factor = spla.splu(sp.csc_matrix(A))
            except RuntimeError:  # exactly singular, or not finite (a blown-up iterate)
                self.factor = None

    def solve(self, b):
        """A^-1 b, NaN (caught by the caller) when A is singular."""
        if self.factor is None:
            return np.full_like(b, np.nan)
        if self.layout == "dense":
            return lapack.dgetrs(*self.factor, b)[0]
        if self.layout == "band":
            return self.factor(b)
        return self.factor.solve(b)


LINE_SEARCH = 6  # halvings of a full-Newton correction that does not lower the residual


def _newton(balance, x1, x0, matrix, tol, maxiter, full, limit=None):
    """Solve balance(x1) = 0 from x1 with the factorized ``matrix`` (refreshed when
    convergence slows: a correction shrinking by less than ``CONTRACTION``, and with
    ``full`` where the line search ran out of halvings too). Returns (x1, iterations),
    (None, k) when it does not converge in maxiter or (modified) when two refreshed
    matrices in a row shrink the correction by less than ``STALL`` (cycling across a kink
    of the residual: a node touching the bed), (False, k) on a non-finite step.

    Modified (not ``full``), the kept matrix's corrections are Broyden's: each new one
    corrected by the earlier ones since the matrix was made (:func:`broyden`), so the
    matrix follows a changing tangent (a line's end rotating) without a new factorization;
    it stops when the error a correction leaves is below the tolerance too
    (:func:`error_below`). With ``full`` it backtracks, the matrix made new at the start: a correction that does
    not lower the residual's norm is halved (up to ``LINE_SEARCH`` times) until it does
    (Armijo, 1e-4), which breaks the two-cycles Newton falls into across such a kink.
    limit(x1, dx): changes a correction in place before it is taken, True when it did (the
    sea bed's landing, ``System.limit_correction``); such a correction does not end the
    iteration, and modified Newton makes its matrix new after it."""
    B, A = balance(x1, tangent=full or matrix.factor is None)
    previous = before = scale = np.inf
    norm = np.linalg.norm(B) if full else 0.0
    stalls = 0
    steps = []  # the corrections made on the current matrix (Broyden's history)
    for it in range(1, maxiter + 1):
        if A is not None:
            matrix.update(A)
            steps = []
        dx = matrix.solve(-B)
        if not full and np.all(np.isfinite(dx)):  # (one that is not: a failed step below)
            dx = broyden(dx, steps)
            if dx is None:  # a degenerate secant update: a new matrix here
                B, A = balance(x1, tangent=True)
                continue
        size = np.max(np.abs(dx), initial=0.0)
        if not math.isfinite(size):
            return False, it
        landed = not full and limit is not None and limit(x1, dx)
        x_new = x1 + dx
        if it == 1:  # the step's change, to scale the tolerance
            scale = np.max(np.abs(x_new - x0), initial=0.0)
        if not landed and size <= tol * scale + 1e-12:
            return x_new, it
        if not full and not landed and error_below(size, previous, before, tol * scale):
            return x_new, it
        if not full:
            stalls = stalls + 1 if A is not None and it > 1 and size > STALL * previous else 0
            if stalls == 2:
                return None, it  # cycling across a kink (a node at the bed): the line search
            steps.append(dx)
            x1 = x_new
            slow = (size > BROYDEN_CONTRACTION * previous or len(steps) == BROYDEN_HISTORY
                    or landed)
            before, previous = previous, size
            B, A = balance(x1, tangent=slow)
            continue
        length = 1.0  # of the correction
        for halving in range(LINE_SEARCH + 1):
            B_try, A_try = balance(x_new, tangent=False)
            norm_try = np.linalg.norm(B_try)
            if (norm_try <= (1 - 1e-4 * length) * norm or not math.isfinite(norm_try)
                    or halving == LINE_SEARCH):
                break
            length *= 0.5
            x_new = x1 + length * dx
        x1 = x_new
        slow = halving == LINE_SEARCH or size > CONTRACTION * previous
        previous = size
        if slow and math.isfinite(norm_try):  # a new matrix where the search stopped
            B_try, A_try = balance(x1, tangent=True)
        B, A, norm = B_try, A_try, norm_try
    return None, maxiter


def error_below(size, previous, before, bound):
    """Whether the error a modified-Newton correction of ``size`` leaves is below ``bound``:
    estimated from the rate theta at which the corrections shrink as theta / (1 - theta)
    size (a geometric tail; Hairer & Wanner, Solving ODEs II, IV.8), theta the larger of
    the last two rates, size / previous and previous / ``before`` (one rate alone can be
    a chance: a correction that happens to be small). No estimate before the third
    correction (``before`` inf) or while they do not shrink."""
    theta = max(size / previous, previous / before)
    return math.isfinite(before) and 0.0 < theta < 1.0 and size * theta <= (1.0 - theta) * bound


def broyden(dx, steps):
    """Broyden's ("good") correction from the kept matrix's one, dx = -A0^-1 B, and the
    corrections s_0 ... s_k made since A0 was factorized (Kelley 1995, Alg. brsol):
    dx <- dx + s_{j+1} (s_j . dx) / |s_j|^2 for j < k, then dx / (1 - s_k . dx / |s_k|^2).
    The secant updates of A0 make it match the balance's change along each step taken.
    None when the last factor would scale dx by more than ``BROYDEN_SCALING`` either way."""
    if not steps:
        return dx
    for before, after in zip(steps[:-1], steps[1:]):
        dx = dx + after * (before @ dx) / (before @ before)
    last = steps[-1]
    scale = 1.0 / (1.0 - (last @ dx) / (last @ last))
    if not 1.0 / BROYDEN_SCALING <= abs(scale) <= BROYDEN_SCALING:
        return None
    return scale * dx


class ConvergenceError(RuntimeError):
    """A Newton solve did not converge; the message says where and what to try."""


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
        if not (np.all(np.isfinite(R)) and np.all(np.isfinite(A.data if hasattr(A, "data")
                                                               else A))):
            raise ConvergenceError(f"{where}: the residual or its tangent is not finite (NaN "
                                   f"or inf) at iteration {it}; some term gives NaN or inf there")
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
