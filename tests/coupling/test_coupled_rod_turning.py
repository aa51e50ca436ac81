"""A Coupled rod turned in pitch and yaw together (MoorDyn's 6 coupled DOFs: end A's
position, then the angles of R = Rx Ry Rz applied to the deck's axis, Rod.cpp's
fromVec6 / Euler2Quat), its reaction (skmoor.coupling.rods.coupled_reaction) in dynamics.

- fast: the rod alone (g = 0, no lines), horizontal, pitched and yawed by sines: its
  reaction is minus the rate of its momentum, F = -m (alpha x r_c + omega x (omega x
  r_c)), M_A = -(I_A alpha + omega x I_A omega) about end A, with omega and alpha of
  the rotation differenced here from scipy's intrinsic XYZ angles (fails on another
  angle order, rates taken for the angular velocity, a dropped centripetal or
  gyroscopic term, an inertia about the centre instead of end A);
- slow: MoorDyn 2.7.2 side by side, a chain on end A, a sagging cable on end B, the rod
  turned 6 deg in pitch and 8 deg in yaw (faded in over 8 s): the coupled loads and the
  cable's tension at the rod.

MoorDyn reads a coupled rod's velocity entries 4-6 as its angular velocity vector (it
moves end B by omega x r) and its getFnet subtracts M6 acc6 only, with no centripetal or
gyroscopic term (Rod.cpp: commented out): the test passes MoorDyn the angular velocity
and adds to its loads those terms of the rod and of the end node masses it carries (a
rigid body's -m omega x (omega x r), -omega x I omega). Without them Fx is off by 14 %
of its range, Mz by 1 %. Measured after: Fx 5 %, Fz 1 %, Mx 0.1 %, My 1.1 %, Mz 0.7 % of
MoorDyn's ranges (Fx's is 0.9 kN on a mean of 23.5 kN: 0.2 % of it), the cable tension at
the rod 6.5 % of its range (1.8 % of its mean; a slack cable, MoorDyn's lumped segment
against the element's mid-point) (dt 10 ms; MoorDyn coupled every 2 ms, dtM 0.1 ms).
"""
import os
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import skmoor
from skmoor.coupling.rods import coupled_reaction

ROD = """---------------------- ROD TYPES -----------------------------------------------
TypeName      Diam     Mass/m    Cd     Ca      CdEnd    CaEnd
(name)        (m)      (kg/m)    (-)    (-)     (-)      (-)
can           0.5      300.0     0.0    0.0     0.0      0.0
---------------------- RODS ----------------------------------------------------
ID   RodType   Attachment  Xa    Ya    Za    Xb    Yb    Zb   NumSegs RodOutputs
(#)  (name)     (#/key)    (m)   (m)   (m)   (m)   (m)   (m)  (-)     (-)
1    can       Coupled     0     0     -40   10    0     -40  10       -
"""
ALONE = f"""--------------------- MoorDyn Input File ---------------------------------------
A coupled rod alone, weightless (skmoor's turning-rod test)
{ROD}---------------------- OPTIONS -------------------------------------------------
0             writeLog             Write a log file
200           WtrDpth              water depth (m)
0             g
------------------------- need this line --------------------------------------
"""
MOORED = f"""--------------------- MoorDyn Input File ---------------------------------------
A turning coupled rod with a chain on end A and a cable on end B (skmoor's test)
----------------------- LINE TYPES ------------------------------------------
TypeName Diam  Mass/m   EA      BA/-zeta EI   Cd  Ca  CdAx CaAx
(name)   (m)   (kg/m)   (N)     (N-s/-)  (N-m^2) (-) (-) (-)  (-)
chain    0.1   50.0     1e8     -0.5     0    0.0 0.0 0.0  0.0
cable    0.2   40.0     1e8     -0.5     0    0.0 0.0 0.0  0.0
{ROD}---------------------- POINTS --------------------------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     -120    0       -120    0      0       0      0
2     Fixed     60      0       -15     0      0       0      0
---------------------- LINES ---------------------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     chain      1        R1A       160       30      -
2     cable      R1B      2         60        30      -
---------------------- OPTIONS -------------------------------------------------
0             writeLog             Write a log file
1e-4          dtM                  time step to use in mooring integration (s)
200           WtrDpth              water depth (m)
0             kBot
60            TmaxIC               max time for ic gen (s)
------------------------- need this line --------------------------------------
"""
A0 = np.array([0.0, 0.0, -40.0])
AXIS, LENGTH, RADIUS, MASS = np.array([1.0, 0.0, 0.0]), 10.0, 0.25, 300.0 * 10.0


def rotation(angles):
    """R = Rx Ry Rz of MoorDyn's angles (rad): scipy's intrinsic XYZ."""
    return Rotation.from_euler("XYZ", angles).as_matrix()


def spin(angles_of, t, h=1e-4):
    """(omega, alpha) (rad/s, rad/s2, global) of R(angles_of(t)), central differences."""
    def omega(time):
        W = (rotation(angles_of(time + h)) - rotation(angles_of(time - h))) / (2 * h)
        W = W @ rotation(angles_of(time)).T
        return np.array([W[2, 1], W[0, 2], W[1, 0]])
    return omega(t), (omega(t + h) - omega(t - h)) / (2 * h)


def inertia_about_a(R):
    """The rod's inertia (kg m2, global) about end A at attitude R: a uniform cylinder."""
    t = R @ AXIS
    across = MASS * (LENGTH ** 2 / 3 + RADIUS ** 2 / 4)
    return across * (np.eye(3) - np.outer(t, t)) + MASS * RADIUS ** 2 / 2 * np.outer(t, t)


def build(tmp_path, deck, angles_of):
    path = tmp_path / "turning_rod.txt"
    path.write_text(deck)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return path, skmoor.build(path, motion=lambda t: np.r_[0.0, 0.0, 0.0, angles_of(t)])


def test_turning_coupled_rod_passes_minus_its_momentum_rate(tmp_path):
    def angles(t):
        return np.array([0.0, 0.3 * np.sin(0.8 * t), 0.5 * np.sin(0.6 * t)])

    _, model = build(tmp_path, ALONE, angles)
    none = np.zeros(model.system.n)
    for t in (0.7, 2.0, 3.9):
        force, moment = coupled_reaction(model, none, none, t, "rod1")
        R = rotation(angles(t))
        omega, alpha = spin(angles, t)
        centre = LENGTH / 2 * R @ AXIS
        I_A = inertia_about_a(R)
        expected_force = -MASS * (np.cross(alpha, centre)
                                  + np.cross(omega, np.cross(omega, centre)))
        expected_moment = -(I_A @ alpha + np.cross(omega, I_A @ omega))
        np.testing.assert_allclose(force, expected_force, atol=1e-5 * np.abs(expected_force).max())
        np.testing.assert_allclose(moment, expected_moment,
                                   atol=1e-5 * np.abs(expected_moment).max())


PITCH, YAW, PITCH_PERIOD, YAW_PERIOD = np.radians(6.0), np.radians(8.0), 8.0, 10.0


def turning(t):
    """MoorDyn's angles (rad): pitch and yaw sines faded in (C2) over PITCH_PERIOD."""
    x = min(t, PITCH_PERIOD) / PITCH_PERIOD
    fade = x ** 3 * (10 - 15 * x + 6 * x * x)
    return fade * np.array([0.0, PITCH * np.sin(2 * np.pi * t / PITCH_PERIOD),
                            YAW * np.sin(2 * np.pi * t / YAW_PERIOD)])


def moordyn_run(moordyn, path, duration, coupling):
    """(t, cable tension at the rod, 6 loads) rows of MoorDyn 2.7.2 (its console quiet),
    given the angular velocity and with its loads completed by the quadratic velocity
    terms its getFnet leaves out: the rod's and its end B's line node masses'."""
    end_b_mass = 40.0 * 60.0 / 30 / 2  # kg: the cable's end node (MoorDyn's lumped half segment)
    quiet, saved = os.open(os.devnull, os.O_WRONLY), os.dup(1)
    os.dup2(quiet, 1)
    instance = moordyn.Create(str(path))
    rows = []
    try:
        moordyn.Init(instance, [*A0, 0.0, 0.0, 0.0], [0.0] * 6)
        cable = moordyn.GetLine(instance, 2)
        for k in range(round(duration / coupling)):
            t = k * coupling
            omega = spin(turning, t)[0]
            f = np.array(moordyn.Step(instance, [*A0, *turning(t)], [0.0, 0.0, 0.0, *omega],
                                      t, coupling))
            t += coupling
            R, omega = rotation(turning(t)), spin(turning, t)[0]
            centre, end_b = LENGTH / 2 * R @ AXIS, LENGTH * R @ AXIS
            centripetal = -end_b_mass * np.cross(omega, np.cross(omega, end_b))
            f[:3] += -MASS * np.cross(omega, np.cross(omega, centre)) + centripetal
            f[3:] += -np.cross(omega, inertia_about_a(R) @ omega) + np.cross(end_b, centripetal)
            rows.append((t, np.linalg.norm(moordyn.GetLineNodeTen(cable, 0)), *f))
    finally:
        moordyn.Close(instance)
        os.dup2(saved, 1)
        os.close(quiet)
        os.close(saved)
    return np.array(rows)


@pytest.mark.slow
def test_turning_coupled_rod_against_moordyn(tmp_path):
    moordyn = pytest.importorskip("moordyn")

    path, model = build(tmp_path, MOORED, turning)
    duration = 8.0
    results = skmoor.simulate(model, duration=duration, dt=0.01, output_interval=0.01,
                              progress=False)
    first = int(np.flatnonzero(results.line_of_cell == 1)[0])  # the cable's element at the rod
    loads = results.coupled_loads[:, results.body_names.index("rod1")]
    sk = np.c_[results.t, results.tension[:, first], loads]
    md = moordyn_run(moordyn, path, duration, 0.002)
    keep = sk[:, 0] >= md[0, 0]
    names = ("cable tension", "Fx", "Fy", "Fz", "Mx", "My", "Mz")
    errors = {}
    for column, name in enumerate(names, start=1):
        peer = np.interp(sk[keep, 0], md[:, 0], md[:, column])
        errors[name] = np.abs(sk[keep, column] - peer).max() / np.ptp(md[:, column])
    limits = {"cable tension": 0.1, "Fx": 0.08, "Fy": 0.01, "Fz": 0.02, "Mx": 0.005,
              "My": 0.02, "Mz": 0.015}
    assert all(errors[name] < limit for name, limit in limits.items()), errors
