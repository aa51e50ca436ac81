"""Weak-form experimentation: add Morison normal drag to the cable as a scikit-fem form
and run the paper's coupled model with it.

The drag on a line moving with velocity udot through still water is
f = -1/2 rho Cd D |v_n| v_n, v_n the velocity normal to the line. As a residual term
(internal - external) it is the LinearForm below; its derivative with respect to the
velocity (a BilinearForm) goes into Newton's matrix. Nothing in the solver changes.

Run: python examples/03_weak_form_drag.py
"""
import os

import numpy as np
from skfem import BilinearForm, LinearForm
from skfem.helpers import dot

import skmoor

DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 60.0))


def normal_part(vec, t):
    """Component of vec normal to the unit tangent t (both (3, nel, nqp))."""
    return vec - dot(vec, t) * t


@LinearForm
def morison_drag(v, w):
    # + int 1/2 rho Cd D |v_n| v_n . du ds  (drag is external, so it enters the residual with +)
    vn = normal_part(w.du, w.Xp)
    return w.k * np.sqrt(dot(vn, vn)) * dot(vn, v)


@BilinearForm
def morison_drag_rate(dv, v, w):
    # d/d(udot) of the term above: k (|v_n| P + v_n v_n^T / |v_n|), P = I - t t^T
    vn = normal_part(w.du, w.Xp)
    speed = np.sqrt(dot(vn, vn)) + 1e-12
    dvn = normal_part(dv, w.Xp)
    return w.k * (speed * dot(dvn, v) + dot(vn, dvn) * dot(vn, v) / speed)


def surge_and_tension(with_drag: bool):
    case = skmoor.paper_case()
    model = skmoor.build(case)
    if with_drag:
        k = 0.5 * case.water["density"] * 1.2 * 0.1  # 1/2 rho Cd D, Cd = 1.2, D = 0.1 m
        model.system.terms.append(skmoor.Term(morison_drag, damping=morison_drag_rate,
                                              fields={"k": k}))
    results = skmoor.simulate(model, duration=DURATION, progress=False)
    period = 2 * np.pi / case.load["omega"]
    return (results.amplitude(results.body_series("surge"), period, 3),
            results.amplitude(results.fairlead_tension[:, 0], period, 3))


plain = surge_and_tension(False)
drag = surge_and_tension(True)

if __name__ == "__main__":
    print(f"{'':12s}{'surge amplitude [m]':>22s}{'fairlead tension amplitude [kN]':>34s}")
    print(f"{'paper model':12s}{plain[0]:22.4f}{plain[1] / 1e3:34.2f}")
    print(f"{'with drag':12s}{drag[0]:22.4f}{drag[1] / 1e3:34.2f}")
