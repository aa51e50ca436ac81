"""Static equilibrium: Newton with load continuation, line search and a vanishing
regularization (needed to start from a slack, stress-free line whose tangent is singular).
"""
from __future__ import annotations

import numpy as np

from .newton import ConvergenceError, StaticSolution, newton


def solve_static(system, x0=None, *, steps=1, t=0.0, xtol=1e-9, maxiter=60,
                 pretension=None, held=None, relax=False):
    """Static equilibrium of a :class:`~skmoor.coupling.system.System` at time t.

    steps > 1 ramps the weight and the body's static load in equal increments (load
    continuation), each solved from the previous one. pretension (N): a temporary
    tension stiffness that lets Newton start from a slack, stress-free line (use about
    the line's weight); it is removed before convergence, so it does not change the
    answer. held: indices of reduced DOFs kept at their x0 values (e.g. free points held
    where they are given, to release them from there). relax: pseudo-transient
    continuation on the system's mass matrix (see :func:`newton`), for networks whose
    plain Newton wanders; it too is gone before convergence.

    The lines' static laws act here (:class:`skmoor.lines.laws.StaticDynamic`: the static
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
