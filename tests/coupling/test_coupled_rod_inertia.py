"""The inertia a Coupled rod's bending line passes to it (skmoor.coupling.rods.coupled_reaction
with the state's accelerations: System.end_forces / end_moments less M_ef a_f + M_ep a_p).

A stiff beam (EI = 1e7 N m2, 10 kg/m, 4 Hermite elements, consistent mass) clamped on a
Coupled rod's end B and pinned at a coupled point 10 m above, both swayed together along
x (g = 0, no drag or added mass; first mode ~150 rad/s, the sway at 1 rad/s): the beam
moves with its supports, a clamped-pinned beam under the inertial load w = -m a. The rod
passes -m_rod a of its own and the clamp's Euler-Bernoulli reaction, 5/8 w L and the
fixed-end moment w L^2 / 8, so about end A

    F_x = -(m_rod + 5/8 m L) a,   M_y = -(m_rod L/2 + 5/8 m L^2 + m L^2 / 8) a.

The end node's lumped diagonal alone (the element's 156/420 m h of the consistent mass,
not the 54/420 m h it shares with its free neighbour) makes F_x 4.4 % low; leaving the
tangent rows' inertia out of the clamp moment makes M_y 0.6 % low. Measured: 1e-3 of the
peaks (the start-up's beam vibration).
"""
import warnings

import numpy as np

import skmoor

DECK = """--------------------- MoorDyn Input File ---------------------------------------
A stiff beam clamped on a Coupled rod and pinned at a coupled point (skmoor's test)
----------------------- LINE TYPES ------------------------------------------
TypeName Diam  Mass/m   EA      BA/-zeta EI   Cd  Ca  CdAx CaAx
(name)   (m)   (kg/m)   (N)     (N-s/-)  (N-m^2) (-) (-) (-)  (-)
beam     0.1   10.0     1e9     0      1e7    0.0 0.0 0.0  0.0
---------------------- ROD TYPES -----------------------------------------------
TypeName      Diam     Mass/m    Cd     Ca      CdEnd    CaEnd
(name)        (m)      (kg/m)    (-)    (-)     (-)      (-)
can           0.5      1.0       0.0    0.0     0.0      0.0
---------------------- RODS ----------------------------------------------------
ID   RodType   Attachment  Xa    Ya    Za    Xb    Yb    Zb   NumSegs RodOutputs
(#)  (name)     (#/key)    (m)   (m)   (m)   (m)   (m)   (m)  (-)     (-)
1    can       Coupled     0     0     -30   0     0     -20  2       -
---------------------- POINTS --------------------------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Coupled   0       0       -10     0      0       0      0
---------------------- LINES ---------------------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     beam       R1B      1        10       4       -
---------------------- OPTIONS -------------------------------------------------
0             writeLog             Write a log file
100           WtrDpth              water depth (m)
0             g
------------------------- need this line --------------------------------------
"""
AMPLITUDE, OMEGA = 0.5, 1.0  # m, rad/s
M_ROD, M_LINE, L = 10.0, 10.0, 10.0  # kg, kg/m, m: the rod's mass, the beam's, its length


def sway(t):
    """x (m): starts from rest with no acceleration (no jolt for the stiff beam)."""
    return AMPLITUDE * (1 - np.cos(OMEGA * t)) ** 2 / 4


def sway_acceleration(t):
    wt = OMEGA * t
    return AMPLITUDE * OMEGA ** 2 / 2 * (np.sin(wt) ** 2 + np.cos(wt) - np.cos(wt) ** 2)


def test_bending_line_inertia_on_an_accelerated_coupled_rod(tmp_path):
    path = tmp_path / "beam_on_rod.txt"
    path.write_text(DECK)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(path, motion=lambda t: np.array(
            [sway(t), 0.0, 0.0, 0.0, 0.0, 0.0, sway(t), 0.0, 0.0]))
    assert model.lines.hermite and model.network.body("rod1").kind == "coupled"
    model.solver.update(scheme="generalized-alpha", rho_inf=0.5)  # damps the start-up
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = skmoor.simulate(model, duration=4.0, dt=0.01, output_interval=0.05,
                                  progress=False, start="given")
    loads = results.coupled_loads[:, results.body_names.index("rod1")]
    a = sway_acceleration(results.t)
    force = -(M_ROD + 5 / 8 * M_LINE * L) * a
    moment = -(M_ROD * L / 2 + 5 / 8 * M_LINE * L ** 2 + M_LINE * L ** 2 / 8) * a
    assert np.abs(loads[:, 0] - force).max() < 3e-3 * np.abs(force).max()
    assert np.abs(loads[:, 4] - moment).max() < 3e-3 * np.abs(moment).max()
    assert np.abs(loads[:, [1, 3, 5]]).max() < 1e-9 * np.abs(moment).max()
