"""Weak-form experimentation: a user's Morison drag on the lines, its residual alone,
added to the paper's coupled model.

A line moving with velocity udot through still water feels, per unit unstretched length,
f = -1/2 rho Cd d |v_n| v_n, with v_n = udot - (udot . tau) tau the velocity normal to
the line's CURRENT unit tangent tau = (X' + u') / |X' + u'|: a follower load that turns
with the line. As a residual (internal - external forces) it is the LinearForm below,
written with skmoor.fem.ops so that JAX can trace it. Nothing else is written: skmoor
differentiates it (d/du through tau, d/dudot) and compiles the integrand and its
derivatives into an element kernel (``path='compiled'``; needs ``pip install
"skmoor[autodiff]"``; ``path='fd'`` is the fallback without JAX).

skmoor integrates over the reference (static) arclength, so a load per unstretched
length is scaled by w.m / mass (the reference stretch's inverse, 1 - 2e-4 here), as the
built-in drag does. That built-in drag (skmoor.sea.hydro, a hand-written numba kernel, on when
a line type has Cd_n) is an independent implementation of the same physics: the script
runs both and prints how far apart they are, their speed ratio and the Taylor test of the
user form's automatic tangents.

Run: python examples/03_weak_form_drag.py
"""
import os
import time
import timeit

import numpy as np
from skfem import LinearForm

import skmoor
from skmoor.fem import ops
from skmoor.fem.ops import d_ds, dot

DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 60.0))
CD = 1.2  # normal drag coefficient (MoorDyn's Cd)


@LinearForm
def morison_drag(v, w):
    # + int 1/2 rho Cd d |v_n| v_n . du ds  (drag is external: + in the residual)
    rp = w.Xp + d_ds(w.u)                 # current tangent r' = X' + u'
    tau = rp / ops.norm(rp)
    vn = w.du - dot(w.du, tau) * tau       # normal part of the line's velocity
    return w.k * (w.m / w.mass) * ops.norm(vn) * dot(vn, v)


case = skmoor.paper_case()


def run(model):
    """(results, wall time of the time loop, s): 'DURATION' s from the static state."""
    eq = skmoor.equilibrium(model)
    started = time.perf_counter()
    results = skmoor.simulate(model, duration=DURATION, eq=eq, progress=False)
    return results, time.perf_counter() - started


def amplitudes(results):
    """(surge amplitude, m; fairlead tension amplitude, N) over the last 3 periods."""
    period = 2 * np.pi / case.load["omega"]
    return (results.amplitude(results.body_series("surge"), period, 3),
            results.amplitude(results.fairlead_tension[:, 0], period, 3))


user_model = skmoor.build(case)
steel = user_model.lines.lines[0].line_type
k = 0.5 * case.water["density"] * CD * steel.diameter  # 1/2 rho Cd d, N s2/m3
drag_term = user_model.add(skmoor.LineForm(morison_drag, fields={"k": k, "mass": steel.mass}))
tangent = skmoor.check_tangent(user_model, drag_term)

builtin_model = skmoor.build(case.replace("line_types.steel.Cd_n", CD))
builtin_term, = builtin_model.system.terms  # the built-in drag: skmoor.sea.hydro.LineHydroKernel

plain_run, _ = run(skmoor.build(case))
builtin_run, builtin_wall = run(builtin_model)
user_run, user_wall = run(user_model)
plain, builtin, drag = (amplitudes(r) for r in (plain_run, builtin_run, user_run))


def relative_difference(series, reference):
    return float(np.max(np.abs(series - reference)) / np.max(np.abs(reference)))


difference = {"surge": relative_difference(user_run.body_series("surge"),
                                           builtin_run.body_series("surge")),
              "fairlead tension": relative_difference(user_run.fairlead_tension,
                                                      builtin_run.fairlead_tension)}
speed_ratio = user_wall / builtin_wall


def per_call(term, lines):
    """Best time of one residual + tangent evaluation of a line term, s (at 0.5 m/s)."""
    rng = np.random.default_rng(0)
    u, v = 1e-3 * rng.standard_normal(lines.ndofs), 0.5 * rng.standard_normal(lines.ndofs)
    R, K, C = np.zeros(lines.ndofs), *np.zeros((2, lines.mesh.t.shape[1], 6, 6))
    return min(timeit.repeat(lambda: term.add_to(u, v, 0.0, R, K, C), number=200, repeat=5)) / 200


term_ratio = per_call(drag_term, user_model.lines) / per_call(builtin_term, builtin_model.lines)

if __name__ == "__main__":
    print(f"user form: {drag_term!r}, backend {getattr(drag_term, 'backend', drag_term.path)}")
    print(tangent)
    print(f"\n{DURATION:g} s of the paper's case")
    print(f"{'':24s}{'surge amplitude [m]':>22s}{'fairlead tension amplitude [kN]':>34s}")
    for name, (surge, tension) in (("paper model (no drag)", plain),
                                   (f"built-in drag, Cd {CD}", builtin),
                                   ("user form drag", drag)):
        print(f"{name:24s}{surge:22.4f}{tension / 1e3:34.2f}")
    print(f"\nuser form vs built-in drag, largest difference / largest value: surge "
          f"{difference['surge']:.1e}, fairlead tensions {difference['fairlead tension']:.1e}")
    print(f"speed, user form / built-in drag ({type(builtin_term).__name__}): "
          f"{term_ratio:.2f} per residual + tangent, {speed_ratio:.2f} for the time loop")
