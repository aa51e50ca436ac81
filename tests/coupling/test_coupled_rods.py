"""Coupled rods (MoorDyn v2's rod type Coupled): a coupled body at end A on 6 coupled
DOFs, end A's position and MoorDyn's angles Rx Ry Rz turning the deck's axis; its
reaction (skmoor.coupling.rods.coupled_reaction, MoorDyn's getFnet) is the lines' loads on it
plus its own weight, buoyancy and hydrodynamics less its inertia.

- statics, a rod turned by 40 deg about y by the coupled motion: the reaction less the
  line's pull is the rod's net weight (rho A - m) g L, vertical, with the moment
  (rho A - m) g L^2 / 2 sin(40 deg) about end A (fails on a wrong angle convention, a
  rod that does not turn, or a moment about the wrong point);
- MoorDyn 2.7.2 side by side (a deck written here: a rod carrying a chain to an anchor,
  surged 2 m at 8 s): the rod's reported force x, z and moment y, and the tension of the
  chain's segment at the rod.

Measured: Fx 0.3 %, Fz 0.6 %, My 0.16 % of MoorDyn's range, the segment tension 0.5 % (its
static offset: MoorDyn's lumped segments against the elastic catenary)
(dt 10 ms; MoorDyn coupled every 2 ms, dtM 0.1 ms).
"""
import warnings

import numpy as np
import pytest

import skmoor
from skmoor.coupling.rods import coupled_reaction

DECK = """--------------------- MoorDyn Input File ---------------------------------------
A coupled rod carrying one chain to an anchor (skmoor's coupled-rod test)
----------------------- LINE TYPES ------------------------------------------
TypeName Diam  Mass/m   EA      BA/-zeta EI   Cd  Ca  CdAx CaAx
(name)   (m)   (kg/m)   (N)     (N-s/-)  (N-m^2) (-) (-) (-)  (-)
chain    0.1   50.0     1e8     -0.5     0    0.0 0.0 0.0  0.0
---------------------- ROD TYPES -----------------------------------------------
TypeName      Diam     Mass/m    Cd     Ca      CdEnd    CaEnd
(name)        (m)      (kg/m)    (-)    (-)     (-)      (-)
can           0.5      300.0     0.0    0.0     0.0      0.0
---------------------- RODS ----------------------------------------------------
ID   RodType   Attachment  Xa    Ya    Za    Xb    Yb    Zb   NumSegs RodOutputs
(#)  (name)     (#/key)    (m)   (m)   (m)   (m)   (m)   (m)  (-)     (-)
1    can       Coupled     0     0     -20   0     0     -10  4       -
---------------------- POINTS --------------------------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     -120    0       -100    0      0       0      0
---------------------- LINES ---------------------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     chain      1        R1A       160       30      -
---------------------- OPTIONS -------------------------------------------------
0             writeLog             Write a log file
1e-4          dtM                  time step to use in mooring integration (s)
200           WtrDpth              water depth (m)
0             kBot
60            TmaxIC               max time for ic gen (s)
------------------------- need this line --------------------------------------
"""
A0 = np.array([0.0, 0.0, -20.0])
AMPLITUDE, PERIOD = 2.0, 8.0  # m, s: surge of end A, faded in over one period
RHO, G, D, MASS, LENGTH = 1025.0, 9.80665, 0.5, 300.0, 10.0


def surge(t):
    fade = 0.5 * (1 - np.cos(np.pi * min(t, PERIOD) / PERIOD))
    return AMPLITUDE * fade * np.sin(2 * np.pi * t / PERIOD)


def build(tmp_path, motion):
    path = tmp_path / "coupled_rod.txt"
    path.write_text(DECK)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return path, skmoor.build(path, motion=motion)


def test_turned_coupled_rod_reaction(tmp_path):
    angle = np.radians(40.0)
    _, model = build(tmp_path, lambda t: np.array([0.0, 0.0, 0.0, 0.0, angle, 0.0]))
    assert model.network.body("rod1").kind == "coupled"
    eq = skmoor.equilibrium(model, n_modes=1)
    system = model.system
    ends = model.network.point("rod1.B")
    force, moment = coupled_reaction(model, eq.x, np.zeros(system.n), 0.0, "rod1")
    line_force, _ = system.reactions(eq.x)  # the chain's pull on end A (its end B)
    net = (RHO * np.pi * D ** 2 / 4 - MASS) * G * LENGTH  # N, up
    np.testing.assert_allclose(force - line_force[0], [0.0, 0.0, net], atol=1e-6 * abs(net))
    # Ry(40 deg) turns the axis (0, 0, 1) to (sin, 0, cos): the centre at L/2 of it
    expected = np.cross(LENGTH / 2 * np.array([np.sin(angle), 0.0, np.cos(angle)]),
                        [0.0, 0.0, net])
    np.testing.assert_allclose(moment, expected, atol=1e-6 * abs(net) * LENGTH)
    assert ends.position == pytest.approx([0.0, 0.0, LENGTH])
    saved = skmoor.static_results(model, eq).coupled_loads  # in the Results too
    np.testing.assert_allclose(saved[0, model.network.bodies.index(model.network.body("rod1"))],
                               np.r_[force, moment])


@pytest.mark.slow
def test_surged_coupled_rod_against_moordyn(tmp_path):
    moordyn = pytest.importorskip("moordyn")

    path, model = build(tmp_path, lambda t: np.array([surge(t), 0.0, 0.0, 0.0, 0.0, 0.0]))
    duration = 16.0
    results = skmoor.simulate(model, duration=duration, dt=0.01, output_interval=0.01,
                              progress=False)
    last = int(np.flatnonzero(results.line_of_cell == 0)[-1])  # the segment at the rod
    rod = results.body_names.index("rod1")
    loads = results.coupled_loads[:, rod]
    sk = np.c_[results.t, results.tension[:, last], loads[:, 0], loads[:, 2], loads[:, 4]]

    def velocity(t, h=1e-6):
        return (surge(t + h) - surge(t - h)) / (2 * h)

    instance = moordyn.Create(str(path))
    md, coupling = [], 0.002
    try:
        moordyn.Init(instance, [*A0, 0.0, 0.0, 0.0], [0.0] * 6)
        line = moordyn.GetLine(instance, 1)
        for k in range(round(duration / coupling)):
            tk = k * coupling
            f = moordyn.Step(instance, [surge(tk), 0.0, A0[2], 0.0, 0.0, 0.0],
                             [velocity(tk), 0.0, 0.0, 0.0, 0.0, 0.0], tk, coupling)
            tension = np.linalg.norm(moordyn.GetLineNodeTen(line, moordyn.GetLineN(line)))
            md.append((tk + coupling, tension, f[0], f[2], f[4]))
    finally:
        moordyn.Close(instance)
    md = np.array(md)
    keep = sk[:, 0] >= md[0, 0]
    errors = {}
    for column, name in ((1, "segment tension"), (2, "Fx"), (3, "Fz"), (4, "My")):
        peer = np.interp(sk[keep, 0], md[:, 0], md[:, column])
        errors[name] = np.abs(sk[keep, column] - peer).max() / np.ptp(md[:, column])
    limits = {"segment tension": 0.008, "Fx": 0.006, "Fz": 0.01, "My": 0.004}
    assert all(errors[name] < limit for name, limit in limits.items()), errors


def test_coupled_pinned_rod_passes_its_pin_force(tmp_path):
    """The same rod CoupledPinned (end A on 3 coupled DOFs, free to turn): in statics its
    pin passes the chain's pull and the rod's net weight (rho A - m) g L, no moment."""
    path = tmp_path / "pinned_rod.txt"
    path.write_text(DECK.replace("can       Coupled ", "can       CoupledPinned "))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(path)
    assert model.network.body("rod1").pin == "coupled"
    eq = skmoor.equilibrium(model, n_modes=1)
    force, moment = coupled_reaction(model, eq.x, np.zeros(model.system.n), 0.0, "rod1")
    line_force, _ = model.system.reactions(eq.x)
    net = (RHO * np.pi * D ** 2 / 4 - MASS) * G * LENGTH
    np.testing.assert_allclose(force - line_force[0], [0.0, 0.0, net], atol=1e-5 * abs(net))
    assert not moment.any()
    saved = skmoor.static_results(model, eq).coupled_loads[0, -1]
    np.testing.assert_allclose(saved, np.r_[force, moment])
