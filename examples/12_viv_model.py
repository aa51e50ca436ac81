"""A VIV model of your own: Thorsen's synchronization against a lift at the Strouhal rate.

skmoor's vortex-induced vibration (MoorDyn v2's cross-flow lift, ``skmoor.sea.viv``) is a
form with a memory on the nodes: each node's lift 1/2 rho d Cl |v_p| cos(phi) (q x v_p)
has a phase phi whose rate synchronizes with the node's own cross-flow motion (its phase
phi_y; Thorsen, Saevik & Larsen 2014):

    dphi/dt = 2 pi (cF + dF sin(phi_y - phi)) |v_p| / d

A researcher's other model is one rule away. Here the phase runs at the Strouhal rate
alone, 2 pi cF |v_p| / d, the classic forcing at a fixed Strouhal number: the built-in
rule with its rate replaced, run by ``VortexLiftForm`` on the same fields and put in place
of the built-in lift with ``Network.viv_lift``. On the compiled path it runs in the
compiled time step like the built-in lift.

The riser: 60 m, vertical, held at both ends under 16 kN, d 0.1 m, 10 kg/m, in a uniform
0.5 m/s current across it (Cl 0.8, cF 0.18, dF 0.08: the Strouhal frequency cF U / d is
0.9 Hz). From its static state, DURATION s of each model; their cross-flow motion after
SETTLE s. Both move at about cF U / d. Thorsen's lift, in step with the motion, takes the
riser into a standing wave of its second cross-flow mode, 0.5 d rms at the antinodes.
The Strouhal forcing keeps the phases as they start, spread along the riser: a wave that
travels along it, 0.13 d rms nearly everywhere.

Run: python examples/12_viv_model.py   (prints each model's cross-flow frequency and
largest rms displacement; writes docs/images/viv_model.png: the cross-flow motion at a
quarter of the riser in time, and its rms along the riser)
"""
import os
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import skmoor
from skmoor.coupling.network import MooringLine, Network, Point
from skmoor.fem import ops
from skmoor.model.model import from_network
from skmoor.sea import viv
from skmoor.sea.waves import Current, Sea
from skmoor.solvers.dynamics import integrate

DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 120.0))
OUT = Path(os.environ.get("SKMOOR_EXAMPLE_OUT", Path(__file__).parents[1] / "docs" / "images"))
SETTLE = 0.5 * DURATION  # s: the motion from here on
U, D, LENGTH, TENSION, EA = 0.5, 0.1, 60.0, 16000.0, 1e9  # m/s, m, m, N, N
CF, DF, CL = 0.18, 0.08, 0.8
ELEMENTS, DT = 30, 0.04  # 2 m each; s


def strouhal_rate(w):
    # the built-in memory's rule with the phase's rate at the Strouhal number alone
    new = viv.vortex_lift_update(w)
    _, _, speed = viv.node_flow(w)
    held = (w.lifting > 0.5) & (w.dt <= 0.0)  # a second commit at the same time
    new["rate"] = ops.where(held, w.rate, 2 * np.pi * w.cF * speed / w.d)
    return new


def strouhal_lift(lines, sea, **options):
    """The lift term of the Strouhal model (``Network.viv_lift``)."""
    return viv.VortexLiftForm(lines, sea, update=strouhal_rate, **options)


def riser(viv_lift=None):
    """The riser's model, its lift the built-in one or ``viv_lift``'s."""
    pipe = skmoor.LineType(EA=EA, mass=10.0, diameter=D, Cd_n=1.2, Ca_n=1.0, Cl=CL,
                           viv_cF=CF, viv_dF=DF)
    points = [Point("bottom", "fixed", [0.0, 0.0, -100.0]),
              Point("top", "fixed", [0.0, 0.0, -100.0 + LENGTH])]
    line = MooringLine("riser", pipe, "bottom", "top", LENGTH / (1 + TENSION / EA), ELEMENTS)
    return from_network(Network(points, [line], depth=100.0, sea=Sea(100.0, current=Current(U)),
                                viv_lift=viv_lift, viv_rms_time=5.0))


def run(model):
    """(t, cross-flow displacement of every node (steps, nodes), the static state)."""
    system = model.system
    eq = skmoor.equilibrium(model)
    dofs = system.lines.nodal_dofs[:, 1]
    t, y = [], []
    for state in integrate(system, eq.x, np.zeros(system.n), DT, DURATION, C=eq.C):
        u, _ = system.full_state(state.x, state.v, state.t)
        t.append(state.t)
        y.append(u[dofs])
    return np.array(t), np.array(y), eq


def frequency(t, y):
    """Mean frequency (Hz) of the upward crossings of y's mean."""
    y = y - y.mean()
    up = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    crossings = t[up] - y[up] * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    return (len(crossings) - 1) / (crossings[-1] - crossings[0])


models = {"Thorsen (built-in)": riser(), "Strouhal rate": riser(strouhal_lift)}
runs = {name: run(model) for name, model in models.items()}
QUARTER = ELEMENTS // 4  # the node a quarter up the riser
stats = {}
for name, (t, y, _) in runs.items():
    late = t > SETTLE
    rms = y[late].std(axis=0) / D
    stats[name] = (frequency(t[late], y[late, QUARTER]), rms)
    print(f"{name:20s} cross-flow frequency {stats[name][0]:.3f} Hz "
          f"(Strouhal cF U / d = {CF * U / D:.3f} Hz), largest rms {rms.max():.2f} d")

figure = Figure(figsize=(10, 4), layout="constrained")
time_axes, along = figure.subplots(1, 2, width_ratios=[2, 1])
z = models["Strouhal rate"].system.lines.points[:, 2] + 100.0
for (name, (t, y, _)), colour in zip(runs.items(), ("C0", "C3")):
    last = t > DURATION - 10.0
    time_axes.plot(t[last], y[last, QUARTER] / D, colour,
                   label=f"{name}: {stats[name][0]:.2f} Hz")
    along.plot(stats[name][1], z, colour, label=name)
time_axes.set(xlabel="t [s]", ylabel="cross-flow y / d, a quarter up the riser",
              title=f"U = {U} m/s, Strouhal frequency {CF * U / D:.2f} Hz")
time_axes.legend(loc="upper right")
along.set(xlabel="rms y / d", ylabel="height above the bottom end [m]",
          title="cross-flow rms along the riser")
OUT.mkdir(parents=True, exist_ok=True)
figure.savefig(OUT / "viv_model.png", dpi=110)
print(f"wrote {OUT / 'viv_model.png'}")
