"""Nonlinear bending of a flexible riser: a moment-curvature law written as a form.

An unbonded flexible pipe bends stiffly while the friction between its armour layers
holds them together, and more softly once they slip. A simple nonlinear-elastic law of
the curvature kappa = X'' + u'' (1/m): the pipe's own EI_slip (the line type's EI, in
skmoor's bending kernel) plus the layers' friction moment, which grows with the
curvature at the slope EI_stick - EI_slip and saturates at (EI_stick - EI_slip)
kappa_slip past the slip curvature kappa_slip:

    M = EI_slip kappa + (EI_stick - EI_slip) kappa_slip tanh(|kappa| / kappa_slip) kappa / |kappa|

The friction part is a user's LineForm on the riser's bending (Hermite) elements,
int M_friction . v'' ds, which reads the curvature (``w.u.hess``, ``w.Xpp``) and acts on
v'' (``v.hess``). skmoor generates its kernel with the cubics' second derivatives, and
it runs in the compiled time step like the built-in bending.

The riser: 240 m from a fairlead 5 m deep to an anchor 150 m down and 150 m away, EA
2e8 N, 150 kg/m, D 0.3 m, Morison drag. Its fairlead heaves and surges 2 m over a 10 s
period, from rest. Three runs of DURATION s: the law, and the pipe as a linear beam of
EI_stick and of EI_slip throughout.

Run: python examples/11_nonlinear_bending.py   (prints each run's largest curvature
and fairlead tension, writes docs/images/nonlinear_bending.png: the moment-curvature law
and the curvature along the riser's top 40 m when the fairlead is highest)
"""
import os
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from skfem import LinearForm

import skmoor
from skmoor.fem import ops
from skmoor.fem.ops import dot
from skmoor.solvers.dynamics import integrate

DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 30.0))
OUT = Path(os.environ.get("SKMOOR_EXAMPLE_OUT", Path(__file__).parents[1] / "docs" / "images"))
EI_STICK, EI_SLIP = 2.0e6, 2.0e5  # N m2: the layers held together, and slipping
KAPPA_SLIP = 0.02  # 1/m: where the layers start to slip
PERIOD, AMPLITUDE, DT = 10.0, 2.0, 0.05  # s, m, s
ELEMENTS = 240  # 1 m each: the bending boundary layer under the hang-off is 2 to 5 m long


@LinearForm
def armour_friction(v, w):
    # + int M_friction(kappa) . v'' ds, kappa = X'' + u'': the layers' friction moment
    kappa = w.Xpp + w.u.hess[:, 0, 0]
    x = ops.norm(kappa) / w.kappa_slip
    grows = ops.where(x > 1e-6, ops.tanh(x) / ops.where(x > 1e-6, x, 1.0), 1.0)
    return w.friction * grows * dot(kappa, v.hess[:, 0, 0])


def riser(EI, friction=None):
    """The riser of bending stiffness EI (N m2) with, when given, the friction law's
    slope ``friction`` = EI_stick - EI_slip (N m2) as a form: its model."""
    pipe = skmoor.LineType(EA=2e8, mass=80.0, diameter=0.25, EI=EI, Cd_n=1.0, Ca_n=1.0)
    points = [skmoor.Point("fairlead", "coupled", (0.0, 0.0, -5.0)),
              skmoor.Point("anchor", "fixed", (-150.0, 0.0, -150.0))]
    lines = [skmoor.MooringLine("riser", pipe, "fairlead", "anchor", 240.0, ELEMENTS,
                                clamp_a=(0.0, 0.0, -1.0))]  # hung off vertically

    def heave(t):  # from rest: 1 - cos
        return AMPLITUDE * 0.5 * (1.0 - np.cos(2 * np.pi * t / PERIOD)) * np.array([1.0, 0.0, 1.0])

    network = skmoor.Network(points, lines, depth=300.0, motion=heave,
                             strain_law=skmoor.Engineering(tension_only=False))
    model = skmoor.from_network(network)
    if friction is not None:
        model.add(skmoor.LineForm(armour_friction, path="compiled", name="armour_friction",
                                  fields={"friction": friction, "kappa_slip": KAPPA_SLIP}))
    return model


def run(model, compiled=True):
    """(times, largest curvature along the riser at each step (1/m), fairlead tension
    (N), the curvature along it when the fairlead is highest)."""
    system, lines = model.system, model.lines
    x0 = skmoor.solve_static(system).x
    times, peaks, tensions, highest = [], [], [], None
    for state in integrate(system, x0, np.zeros(system.n), DT, DURATION, compiled=compiled,
                           report_every=1):
        u = system.full_displacement(state.x, state.t)
        curvature = lines.curvature(u)
        times.append(state.t)
        peaks.append(curvature.max())
        tensions.append(np.linalg.norm(state.reactions[1][0]))
        if abs((state.t / PERIOD) % 1.0 - 0.5) < 0.5 * DT / PERIOD:  # the fairlead highest
            highest = curvature
    return np.array(times), np.array(peaks), np.array(tensions), highest


models = {"law": riser(EI_SLIP, EI_STICK - EI_SLIP), "stick": riser(EI_STICK),
          "slip": riser(EI_SLIP)}
runs = {name: run(model) for name, model in models.items()}
arc = np.concatenate([0.5 * (line.s[1:] + line.s[:-1]) for line in models["law"].lines.lines])

print(f"{DURATION:g} s, fairlead moved {AMPLITUDE:g} m over {PERIOD:g} s")
print(f"{'run':>6} {'largest curvature (1/m)':>24} {'largest fairlead tension (kN)':>30}")
for name, (t, peaks, tensions, _) in runs.items():
    print(f"{name:>6} {peaks.max():24.5f} {tensions.max() / 1e3:30.1f}")

fig = Figure(figsize=(10, 4), layout="constrained")
law_axes, along = fig.subplots(1, 2)
kappa = np.linspace(0.0, runs["law"][1].max(), 200)
moment = EI_SLIP * kappa + (EI_STICK - EI_SLIP) * KAPPA_SLIP * np.tanh(kappa / KAPPA_SLIP)
law_axes.plot(kappa, moment / 1e3, label="the law")
law_axes.plot(kappa, EI_STICK * kappa / 1e3, "--", label="EI_stick")
law_axes.plot(kappa, EI_SLIP * kappa / 1e3, ":", label="EI_slip")
law_axes.set(xlabel="curvature (1/m)", ylabel="bending moment (kN m)",
             ylim=(0, 2 * moment.max() / 1e3), title="moment-curvature law")
law_axes.legend()
for name, style in (("law", "-"), ("stick", "--"), ("slip", ":")):
    highest = runs[name][3]
    if highest is not None:
        along.plot(arc, highest, style, label=name)
along.axhline(KAPPA_SLIP, color="grey", lw=0.8)
along.set(xlabel="arclength from the hang-off (m)", ylabel="curvature (1/m)",
          xlim=(0, 40),
          title="the riser when the fairlead is highest")
along.legend()
OUT.mkdir(parents=True, exist_ok=True)
figure = OUT / "nonlinear_bending.png"  # docs/images/nonlinear_bending.png
fig.savefig(figure)
print(f"wrote {figure}")
