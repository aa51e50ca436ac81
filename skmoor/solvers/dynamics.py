"""Implicit time integration of  M a + C v + R(x, v, t) = 0  (Eq. 35).

Generalized-alpha (Chung & Hulbert 1993) with a selectable spectral radius at infinite
frequency, and Newmark's average acceleration as the special case alpha_m = alpha_f = 0,
beta = 1/4, gamma = 1/2. Each step solves the alpha-level balance with Newton:

    (1-am) M a1 + am M a0 + (1-af) [C v1 + R(x1, v1, t1)] + af [C v0 + R(x0, v0, t0)] = 0

A system with a state-dependent inertia (``system.nonlinear_inertia``: rigid bodies with
exact rotations) gives it beside the constant M (``system.inertia``): M a becomes M a + G
at each level, G1 computed from the step's start (x0, v0, a0, G0, h, gamma) so that the
momenta follow the scheme's own velocity rule, and G's derivatives in a, v and x join the
Newton matrix. Such a system may re-base its state after a step (``system.rebase(x, v)``
-> new (x, v) or None: a body's angles counted from its present attitude, away from the
gimbal lock); the integration then restarts from the new state as from t0.

The integrator is a generator of states, so a caller decides what to record and when
to stop; a Newton failure raises :class:`DivergenceError` with the time, the step and a
hint instead of carrying NaN on.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..numerics.banded import as_layout
from .newton import DivergenceError, _IterationMatrix, _newton, matrix_layout


@dataclass(frozen=True)
class Scheme:
    """Time-integration parameters (alpha_m, alpha_f, beta, gamma)."""

    alpha_m: float
    alpha_f: float
    beta: float
    gamma: float

    @classmethod
    def newmark(cls):
        """Average acceleration (trapezoidal rule): energy-conserving, no numerical damping."""
        return cls(0.0, 0.0, 0.25, 0.5)

    @classmethod
    def generalized_alpha(cls, rho_inf: float = 0.8):
        """Chung-Hulbert generalized-alpha; rho_inf in [0, 1] is the spectral radius at
        infinite frequency (1: no numerical damping, 0: asymptotic annihilation)."""
        if not 0.0 <= rho_inf <= 1.0:
            raise ValueError(f"Scheme rho_inf: must lie in [0, 1], got {rho_inf}")
        am = (2 * rho_inf - 1) / (rho_inf + 1)
        af = rho_inf / (rho_inf + 1)
        return cls(am, af, 0.25 * (1 - am + af) ** 2, 0.5 - am + af)

    @classmethod
    def named(cls, name: str, rho_inf: float = 0.8):
        if name in ("newmark", "average-acceleration"):
            return cls.newmark()
        if name in ("generalized-alpha", "alpha"):
            return cls.generalized_alpha(rho_inf)
        raise ValueError(f"scheme: unknown {name!r}, use 'newmark' or 'generalized-alpha'")


@dataclass
class State:
    """One time level: t (s), step number, x (m / rad), v, a, Newton iterations used,
    steps subdivided so far; at the steps :func:`integrate` reports (``report_every``),
    the lines' full state (u m, ud m/s: ``System.full_state``) and end forces (fairlead,
    anchor: (nlines, 3) N each, ``System.end_forces``), else None."""

    t: float
    step: int
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray
    iterations: int = 0
    subdivided: int = 0  # steps split so far (a failed Newton retried in halves)
    full_state: tuple | None = None
    reactions: tuple | None = None


def rayleigh_coefficients(zeta: float, omega1: float, omega2: float):
    """(a0, a1) of C = a0 M + a1 K giving damping ratio zeta at omega1 and omega2 (rad/s)."""
    if omega1 <= 0 or omega2 <= 0:
        raise ValueError(f"rayleigh: frequencies must be positive, got {omega1}, {omega2}")
    return 2 * zeta * omega1 * omega2 / (omega1 + omega2), 2 * zeta / (omega1 + omega2)


COMPILED_BATCH = 32  # steps per call of the compiled step (its call costs ~30 us)
SUBDIVIDE = 6  # levels of halving a step whose Newton fails (down to dt / 64)


def integrate(system, x0, v0, dt, t_end, *, C=None, t0=0.0, scheme=None, tol=1e-5,
              maxiter=20, subdivide=SUBDIVIDE, compiled=True, report_every=0):
    """Yield a :class:`State` per step from (x0, v0) at t0 until t_end.

    system: anything with ``M`` (sparse) and ``residual(x, v, t, tangent=..., layout=...)
    -> (R, K, Kv)`` (layouts: :func:`matrix_layout`). C: constant damping matrix (e.g. Rayleigh). tol: Newton stops when
    the largest correction, or the error it leaves (estimated from the rate at which the
    corrections shrink, :func:`~skmoor.solvers.newton.error_below`), is below tol times
    the largest change over the step (as it stands after the first correction; plus
    1e-12 m). Newton is modified: the factorized
    matrix is kept over iterations and steps, its corrections within a step Broyden's
    (:func:`~skmoor.solvers.newton.broyden`), and refreshed when a correction is larger
    than ``BROYDEN_CONTRACTION`` times the one before; a step that does not converge so (or
    whose refreshed matrices stop shrinking the correction twice in a row, ``STALL``:
    Newton cycling across a kink such as a node touching the bed) is retried at once with
    a backtracking line search on the balance residual (a new matrix at its start and
    where it slows).
    A step that still fails is split in two halves, each half split again when it fails,
    up to ``subdivide`` levels (0: none); the run then goes on at dt, on the full step's
    own matrix. States come at the full steps only; ``State.subdivided`` counts the steps
    that were split so far. compiled: run each step's modified Newton as one compiled
    function where :mod:`skmoor.solvers.compiled_step` covers the system (the same iteration; a
    step it does not converge goes on in Python as above). A system with ``commit(t, x, v)`` has it called with the
    initial state and after every accepted step, the halves of a split step included (the
    compiled step advances the memories it covers itself, ``step_commit``)
    (terms with a memory of the past, :mod:`skmoor.bodies.radiation`, keep their history so).
    report_every: every that many steps (and at the start) the State carries the lines'
    full state and end forces (a :class:`~skmoor.coupling.system.System`; 0: never), computed
    in the compiled step where it runs: what a recorder of tensions needs, without a
    residual in Python per output.
    """
    if not dt > 0:
        raise ValueError(f"integrate dt: must be positive, got {dt}")
    layout, fast, stepper = _steppers(system, C, scheme, tol, maxiter, subdivide, compiled)
    if hasattr(system, "acceleration_step"):  # driven ends' accelerations over the step
        system.acceleration_step = dt
    x, v, t = np.array(x0, float), np.array(v0, float), float(t0)
    rebase = getattr(system, "rebase", None) if stepper.nonlinear else None
    a, force_old, G = stepper.start(x, v, t)
    commit = stepper.commit
    commit(t, x, v)
    reports = report_every > 0 and hasattr(system, "end_forces")
    # a reported tension that reads a memory (a creep state) needs the memory of its own
    # step: the compiled step leaves the memories as at its batch's last step, so its
    # batches end at a report
    memory_reported = getattr(system, "memory_in_tension", False)

    def report(x, v, a, t):
        """(full state, end forces) of the lines at (x, v, a, t), computed here."""
        u, ud = system.full_state(x, v, t)
        return (u, ud), system.end_forces(u, ud, t, a)

    yield State(t, 0, x, v, a, 0, 0, *(report(x, v, a, t) if reports else (None, None)))
    matrix = _IterationMatrix(layout)
    ahead, failed = [], None  # steps the compiled step made, not yet yielded; its failure
    n_steps = int(np.ceil((t_end - t0) / dt - 1e-9))
    subdivided = 0
    for step in range(1, n_steps + 1):
        t1 = t0 + step * dt
        if fast is not None and not ahead and failed is None:  # the next steps compiled
            numbers = np.arange(step, min(step + COMPILED_BATCH, n_steps + 1))
            if reports and memory_reported:  # the batch ends at a report (see above)
                first = np.flatnonzero(numbers % report_every == 0)
                numbers = numbers[:first[0] + 1] if first.size else numbers
            ahead, failed = fast.steps(x, v, a, force_old, t0 + dt * numbers, dt,
                                       report=numbers % report_every == 0 if reports else None,
                                       trend=stepper.trend)
            ahead.reverse()
        reported, committed = None, bool(ahead)  # (the compiled step commits its own)
        if ahead:
            out, it, reported = ahead.pop()
        elif failed is not None and failed != fast.handed_back:  # failed as advance would
            out, it, failed = None, failed, None
        else:
            failed = None
            out, it = stepper.advance(x, v, a, force_old, G, t1, dt, matrix)
        if out is None:
            why = it
            if subdivide > 0:
                out, it = stepper.split((x, v, a, force_old, G), t, t1, 1, dt)
            if out is None:
                tried = (f" (and in steps down to dt / {2**subdivide:g})" if subdivide > 0
                         else "")
                raise DivergenceError(_hint(t1, step, dt, f"{why}{tried}"), t1, step)
            subdivided += 1  # (the split left its last half's trend)
        else:
            if not committed:
                commit(t1, out[0], out[1])
            stepper.accepted(a, dt)
        x, v, a, force_old, G = out
        t = t1
        turned = rebase(x, v) if rebase is not None else None
        if turned is not None:  # a body's angles counted from a new frame: restart there
            x, v = turned
            a, force_old, G = stepper.start(x, v, t1)
            matrix = _IterationMatrix(layout)
            stepper.halves.clear()
            stepper.trend = None
        if reports and step % report_every == 0 and reported is None:
            reported = report(x, v, a, t1)
        yield State(t1, step, x, v, a, it, subdivided, *(reported or (None, None)))


def _steppers(system, C, scheme, tol, maxiter, subdivide, compiled):
    """(matrix layout, the compiled step or None, the Python :class:`_Stepper`) of a
    system with constant damping C (None: none) under ``scheme`` (None: Newmark)."""
    scheme = scheme or Scheme.newmark()
    layout = matrix_layout(system)
    bandwidth = getattr(system, "bandwidth", None)
    M = as_layout(system.M, layout, bandwidth)
    C = sp.csr_matrix(M.shape) if C is None else sp.csr_matrix(C)
    damped = C.count_nonzero() > 0  # skip C v in the loop when there is no C
    fast = (_compiled_step(system, C if damped else None, scheme, tol, maxiter) if compiled
            else None)
    stepper = _Stepper(system, M, as_layout(C, layout, bandwidth), damped, layout, scheme,
                       tol, maxiter, subdivide)
    return layout, fast, stepper


class Stepping:
    """:func:`integrate`'s step one call at a time, for a host that gives the prescribed
    motion step by step (:mod:`skmoor.moordyn`): ``step(h)`` advances (x, v, a) by h (s)
    to ``t + h`` with the same Newton (compiled where it covers the system, else in
    Python, a failed step split in halves) and returns the new :class:`State`.
    ``checkpoint()`` -> an opaque copy of everything the next steps depend on (the state,
    the kept Newton matrices, the memory terms' history); ``restore(checkpoint)`` goes
    back to it, so that the steps after it repeat to round-off."""

    def __init__(self, system, x0, v0, *, t0=0.0, C=None, scheme=None, tol=1e-5, maxiter=20,
                 subdivide=SUBDIVIDE, compiled=True):
        self.system, self.subdivide = system, subdivide
        self.layout, self.fast, self.stepper = _steppers(system, C, scheme, tol, maxiter,
                                                         subdivide, compiled)
        self.matrix = _IterationMatrix(self.layout)
        self.x, self.v, self.t = np.array(x0, float), np.array(v0, float), float(t0)
        self.a, self.force, self.G = self.stepper.start(self.x, self.v, self.t)
        self.stepper.commit(self.t, self.x, self.v)
        self.steps = self.subdivided = self.iterations = 0

    def restart(self):
        """The acceleration and forces again from the balance at the present (x, v, t)
        (after the prescribed motion was changed at t: a host's Init)."""
        self.a, self.force, self.G = self.stepper.start(self.x, self.v, self.t)
        self.stepper.trend = None

    def step(self, h, report=False, to=None) -> State:
        """One step of h (s) (to the time ``to`` when given: t0 + k dt, as :func:`integrate`
        counts it, rather than a sum of steps); with ``report`` the State carries the
        lines' full state and end forces as :func:`integrate`'s reports (computed in the
        compiled step where it runs)."""
        system, stepper = self.system, self.stepper
        if not h > 0:
            raise ValueError(f"Stepping.step h: must be positive, got {h}")
        if hasattr(system, "acceleration_step"):
            system.acceleration_step = h
        t1 = self.t + h if to is None else float(to)
        level = (self.x, self.v, self.a, self.force, self.G)
        out = reported = None
        if self.fast is not None:
            done, _ = self.fast.steps(*level[:4], np.array([t1]), h,
                                      report=[True] if report else None, trend=stepper.trend)
            if done:  # (the compiled step committed it)
                out, it, reported = done[0]
                stepper.accepted(self.a, h)
        if out is None:
            out, it = stepper.advance(*level, t1, h, self.matrix)
            if out is not None:
                stepper.commit(t1, out[0], out[1])
                stepper.accepted(self.a, h)
            elif self.subdivide > 0:
                why = it
                out, it = stepper.split(level, self.t, t1, 1, h)
                if out is None:
                    raise DivergenceError(_hint(t1, self.steps + 1, h, why), t1, self.steps + 1)
                self.subdivided += 1
            else:
                raise DivergenceError(_hint(t1, self.steps + 1, h, it), t1, self.steps + 1)
        self.x, self.v, self.a, self.force, self.G = out
        self.t, self.steps, self.iterations = t1, self.steps + 1, it
        rebase = getattr(system, "rebase", None) if stepper.nonlinear else None
        turned = rebase(self.x, self.v) if rebase is not None else None
        if turned is not None:
            self.x, self.v = turned
            self.restart()
            self.matrix = _IterationMatrix(self.layout)
            stepper.halves.clear()
        if report and reported is None:
            u, ud = system.full_state(self.x, self.v, self.t)
            reported = (u, ud), system.end_forces(u, ud, self.t, self.a)
        return State(self.t, self.steps, self.x, self.v, self.a, it, self.subdivided,
                     *(reported or (None, None)))

    def advance(self, h, count, report=False) -> State:
        """``count`` steps of h (s) (in one call of the compiled step where it runs: its
        call costs more than a small system's step); the last State, with the report
        of :meth:`step` when asked."""
        done = []
        if self.fast is not None and count > 1 and not self.stepper.nonlinear:
            if hasattr(self.system, "acceleration_step"):
                self.system.acceleration_step = h
            times = self.t + h * np.arange(1, count + 1)
            flags = [False] * (count - 1) + [bool(report)]
            done, _ = self.fast.steps(self.x, self.v, self.a, self.force, times, h,
                                      report=flags, trend=self.stepper.trend)
            before = self.a
            for out, it, reported in done:  # (committed by the compiled step)
                self.stepper.accepted(before, h)
                before = out[2]
            if done:
                out, it, reported = done[-1]
                self.x, self.v, self.a, self.force, self.G = out
                self.t, self.iterations = float(times[len(done) - 1]), it
                self.steps += len(done)
                if len(done) == count:
                    return State(self.t, self.steps, self.x, self.v, self.a, it,
                                 self.subdivided, *(reported or (None, None)))
        state = None
        for k in range(len(done), count):
            state = self.step(h, report=report and k == count - 1)
        return state

    def checkpoint(self):
        """A copy of the stepping state (see the class)."""
        import copy

        fast = None if self.fast is None else (
            [np.array(f, copy=True) for f in self.fast.factors], self.fast.state.copy())
        memory = [{k: copy.deepcopy(v) for k, v in term.__dict__.items() if _plain(v)}
                  for term in getattr(self.system, "committing", [])]
        frames = (None if not hasattr(self.system, "frames") else
                  copy.deepcopy((self.system.frames, self.system.frame_r_local,
                                 self.system._end_offsets)))
        return {"t": self.t, "steps": self.steps, "subdivided": self.subdivided,
                "frames": frames,
                "state": copy.deepcopy((self.x, self.v, self.a, self.force, self.G)),
                "matrix": copy.copy(self.matrix),  # a factor is replaced, never changed
                "halves": {k: copy.copy(m) for k, m in self.stepper.halves.items()},
                "trend": copy.deepcopy(self.stepper.trend),
                "fast": fast,
                "memory": memory}

    def restore(self, saved):
        """Back to a :meth:`checkpoint` (kept unchanged: it may be restored again)."""
        import copy

        self.t, self.steps, self.subdivided = saved["t"], saved["steps"], saved["subdivided"]
        self.x, self.v, self.a, self.force, self.G = copy.deepcopy(saved["state"])
        self.matrix = copy.copy(saved["matrix"])
        self.stepper.halves = {k: copy.copy(m) for k, m in saved["halves"].items()}
        self.stepper.trend = copy.deepcopy(saved.get("trend"))
        if saved["fast"] is not None and self.fast is not None:
            for kept, value in zip(self.fast.factors, saved["fast"][0]):
                kept[...] = value
            self.fast.state[...] = saved["fast"][1]
        for term, memory in zip(getattr(self.system, "committing", []), saved["memory"]):
            term.__dict__.update(copy.deepcopy(memory))
        if saved.get("frames") is not None:  # bodies re-based away from the gimbal lock
            system = self.system
            system.frames, system.frame_r_local, system._end_offsets = copy.deepcopy(
                saved["frames"])
            system._attachment_cache = (None, None, None)
        if hasattr(self.system, "forget_prescribed"):
            self.system.forget_prescribed()


def checkpoint_bytes(saved) -> bytes:
    """A :meth:`Stepping.checkpoint` (or a dict holding one under "stepping") as bytes; a
    kept Newton factor that cannot be pickled (a sparse LU) is left out: the first step
    after loading factorizes again (equal to Newton's tolerance, not to round-off)."""
    import pickle

    step = saved.get("stepping", saved)
    matrices = [step["matrix"], *step["halves"].values()]
    kept = [m.factor for m in matrices]
    try:
        return pickle.dumps(saved)
    except (TypeError, pickle.PicklingError, AttributeError):
        for m in matrices:
            m.factor = None
        try:
            return pickle.dumps(saved)
        finally:
            for m, factor in zip(matrices, kept):
                m.factor = factor


class _Stepper:
    """One implicit step of :func:`integrate` in Python: the start's acceleration, a step
    of h by Newton on the alpha-level balance, a failed step split in halves."""

    def __init__(self, system, M, C, damped, layout, scheme, tol, maxiter, subdivide):
        self.system, self.M, self.C, self.damped, self.layout = system, M, C, damped, layout
        self.am, self.af = scheme.alpha_m, scheme.alpha_f
        self.beta, self.gamma = scheme.beta, scheme.gamma
        self.tol, self.maxiter, self.subdivide = tol, maxiter, subdivide
        self.nonlinear = getattr(system, "nonlinear_inertia", False)
        self.driven = getattr(system, "driven_inertia", None) or (lambda t: None)
        self.commit = getattr(system, "commit", None) or (lambda t, x, v: None)
        self.halves = {}  # level -> the iteration matrix of steps dt / 2**level, kept
        self.trend = None  # (the acceleration a step back, that step's h): first_guess's

    def first_guess(self, x, v, a, h):
        """Newton's first iterate for a step of h from (x, v, a): constant acceleration,
        plus h^3 / 6 times the jerk (a - a_prev) / h_prev of the last step when ``trend``
        holds it (a smooth motion's step then starts an iteration or so nearer)."""
        guess = x + h * v + 0.5 * h**2 * a
        if self.trend is not None:
            a_prev, h_prev = self.trend
            guess += h**3 / (6.0 * h_prev) * (a - a_prev)
        return guess

    def accepted(self, a_old, h):
        """A step of h from a level with acceleration a_old (m/s2) was taken."""
        self.trend = (a_old, h)

    def loads(self, R, t):
        """R plus the prescribed ends' inertia on the free DOFs (M_fp a_p(t), a load given
        in time: at the alpha_f level like the others), when the system has one."""
        extra = self.driven(t)
        return R if extra is None else R + extra

    def start(self, x, v, t):
        """(a, C v + R, G) at a start (x, v, t): a from the balance, G the state-dependent
        inertia (None: the system has none)."""
        system, layout = self.system, self.layout
        R, _, _ = system.residual(x, v, t, tangent=False)
        force = self.C @ v + self.loads(R, t)
        mass = _IterationMatrix(layout)

        def balance(A, b):  # A a = b; least squares (MoorDyn's QR) when A is singular
            mass.update(A)  # (a body's masses on one line: its spin held by a spring)
            a = mass.solve(b)
            if np.all(np.isfinite(a)):
                return a
            return np.linalg.lstsq(A.toarray() if sp.issparse(A) else A, b, rcond=None)[0]
        if not self.nonlinear:
            return balance(self.M, -force), force, None
        # G is affine in a: (M + dG/da) a = -(C v + R + G(x, v, 0))
        G0, d_acc, _, _ = system.inertia(x, v, np.zeros_like(v), tangent=True, layout=layout)
        a = balance(self.M + d_acc, -(force + G0))
        return a, force, system.inertia(x, v, a)[0]

    def advance(self, x, v, a, force_old, G_old, t1, h, matrix):
        """One step of h from (x, v, a) to t1: ((x1, v1, a1, C v1 + R1, G1), iterations),
        or (None, why) when Newton fails."""
        system, M, C, layout = self.system, self.M, self.C, self.layout
        am, af, beta, gamma, damped = self.am, self.af, self.beta, self.gamma, self.damped
        c_x = (1 - am) / (beta * h**2)
        c_v = gamma / (beta * h)
        x_pred = x + h * v + h**2 * (0.5 - beta) * a  # part of x1 known from level 0
        v_pred = v + h * (1 - gamma) * a
        inertia_old = am * (M @ a if G_old is None else M @ a + G_old) + af * force_old
        previous = (x, v, a, G_old, h, gamma)
        extra = self.driven(t1)
        # the sea bed's Newton matrix and landing (a System's; a bare system has neither)
        limit = getattr(system, "limit_correction", None)
        newton = {"newton": True} if limit is not None else {}

        def inertia(y, v1, a1, tangent=False):
            """M a1 plus the system's state-dependent inertia G1 (momentum-consistent over
            the step from level 0) and its derivatives d/da, d/dv, d/dx when it has one."""
            if G_old is None:
                return M @ a1, None, None
            G1, *slopes = system.inertia(y, v1, a1, tangent=tangent, layout=layout,
                                         previous=previous)
            return M @ a1 + G1, (slopes if tangent else None), G1

        def balance(y, tangent):
            """alpha-level balance at x1 = y, and (when asked) its tangent."""
            a1 = (y - x_pred) / (beta * h**2)
            v1 = v_pred + gamma * h * a1
            R1, K1, Kv1 = system.residual(y, v1, t1, tangent=tangent, layout=layout,
                                          **newton)
            if extra is not None:
                R1 = R1 + extra
            inertia1, slopes, _ = inertia(y, v1, a1, tangent)
            B = (1 - am) * inertia1 + (1 - af) * (C @ v1 + R1 if damped else R1) + inertia_old
            if not tangent:
                return B, None
            Cv = C if Kv1 is None else C + Kv1
            A = c_x * M + (1 - af) * (c_v * Cv + K1)
            if slopes is not None:  # d/dy of (1 - am) G(y, v1(y), a1(y))
                d_acc, d_rate, d_pose = slopes
                A = A + (1 - am) * (d_acc / (beta * h**2) + gamma / (beta * h) * d_rate
                                    + d_pose)
            return B, A

        # first guess: constant acceleration and the last step's jerk; should modified Newton
        # stall from it, the step again from constant velocity (robust on stiff axial
        # modes) with a line search
        guess = self.first_guess(x, v, a, h)
        x1, it = _newton(balance, guess, x, matrix, self.tol, self.maxiter, full=False,
                         limit=limit)
        if x1 is None or x1 is False:
            x1, more = _newton(balance, x + h * v, x, matrix, self.tol, self.maxiter, full=True,
                               limit=limit)
            it += more
        if x1 is None:
            return None, f"Newton did not converge in {self.maxiter} iterations"
        if x1 is False:
            return None, "the Newton step is not finite"
        a1 = (x1 - x_pred) / (beta * h**2)
        v1 = v_pred + gamma * h * a1
        # C v1 + R(x1) from the converged balance (saves a residual evaluation per step)
        inertia1, _, G1 = inertia(x1, v1, a1)
        force1 = -((1 - am) * inertia1 + inertia_old) / (1 - af)
        return (x1, v1, a1, force1, G1), it

    def split(self, level_state, t, t1, level, dt):
        """(x, v, a, force, G) at t1 through two halves of [t, t1], each split again when it
        fails (down to ``subdivide`` levels); (None, why) if the smallest fails too."""
        matrix = self.halves.setdefault(level, _IterationMatrix(self.layout))
        total, h, mid = 0, dt / 2**level, t + 0.5 * (t1 - t)
        for start, end in ((t, mid), (mid, t1)):
            out, it = self.advance(*level_state, end, h, matrix)
            if out is None and level < self.subdivide:
                out, it = self.split(level_state, start, end, level + 1, dt)
            elif out is not None:
                self.commit(end, out[0], out[1])
                self.accepted(level_state[2], h)
            if out is None:
                return None, it
            level_state, total = out, total + it
        return level_state, total


def _plain(value) -> bool:
    """Whether ``value`` is state a memory term keeps (arrays, numbers, None, and tuples,
    lists or dicts of them), not a reference to the model (lines, sea, laws)."""
    if value is None or isinstance(value, (np.ndarray, float, int, bool, str, np.number)):
        return True
    if isinstance(value, (tuple, list)):
        return all(_plain(v) for v in value)
    if isinstance(value, dict):
        return all(_plain(v) for v in value.values())
    return False


def _compiled_step(system, C, scheme, tol, maxiter):
    """The compiled Newton step of a :class:`~skmoor.coupling.system.System` it covers, or None
    (another kind of system, or one with physics the compiled step leaves to Python)."""
    from ..coupling.system import System

    if type(system) is not System:
        return None
    from .compiled_step import build

    return build(system, C, scheme, tol, maxiter)


def _hint(t, step, dt, what):
    return (f"time integration stopped at t = {t:.6g} s (step {step}): {what}. "
            f"Try a smaller time step (dt = {dt:g} s now), more damping "
            "(generalized-alpha with rho_inf < 1), or check the loads for a blow-up.")
