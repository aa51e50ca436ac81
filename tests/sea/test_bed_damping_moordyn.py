"""The deck's bed damping (MoorDyn's cBot times the line's diameter) against MoorDyn v2
and the closed form, on nodes dropping onto the bed.

tests/decks/seabed/bed_drop.dat: a 10 m line (20 kg/m, d = 0.1 m, EA 1e8 N, no drag, no
added mass, no internal damping) lies straight and stress-free on the bed (20 m of water)
between two fixed points, at zero penetration, at rest. Both codes start there: MoorDyn
with TmaxIC = 0 (its catenary profile fails for a line along the bed, so it starts
linear, on the bed), skmoor from the deck's reference state (straight on the bed,
stress-free) with zero displacement and velocity, integrated by Newmark from that state
(skmoor.simulate would start from the static state, already sunk). Every inner node then
sinks into the bed on its own: with MoorDyn's B_z = (kBot g - cBot dg/dt) d l per node
(g the penetration, l the node's length) and the node's weight w l, per unit length

    m g'' + cBot d g' + kBot d g = w,   g(0) = g'(0) = 0,

w = (m - rho pi d^2 / 4) g0 = 117.18 N/m, so g settles at g_s = w / (kBot d) = 0.39 mm
(kBot = 3e6 Pa/m) with omega = sqrt(kBot d / m) = 122.5 rad/s and
zeta = cBot d / (2 sqrt(kBot d m)). The neighbours sink alike, so the segments between
them stay level and unstretched (only the two end segments tilt, by g / l = 4e-4: a
strain of 8e-8, 8 N along the segment, 3e-3 N vertically, against 117 N of weight per
node). The closed form is the step response of that oscillator, written here.

Cases: cBot = 7.5e3 Pa s/m (zeta = 0.153, ringing for ~0.3 s), and MoorDyn's default
3e5 (zeta = 6.1: the node creeps in with time constant ~ cBot / kBot = 0.1 s).

skmoor's bed fades its damping in over the first tenth of g_s (Seabed.damping_onset, so
that the implicit step has a solution at touchdown); MoorDyn's jumps. skmoor is held to
the same oscillator with that fade-in (integrated here by solve_ivp), MoorDyn to the
oscillator without it, and the two codes to each other.

Measured (max difference over the run / g_s, middle node; the fade-in's own effect is
the faded oscillator - the closed form):

    cBot      MoorDyn - closed   skmoor - faded   fade-in effect   skmoor - MoorDyn
    7.5e3     6e-6               8e-4             1.2e-2           1.2e-2
    3e5       2e-5               6e-4             4.8e-2           4.8e-2

and skmoor - MoorDyn - (fade-in effect): 8e-4 and 6e-4, alike on every inner node.
(skmoor at dt = 0.5 ms, Newmark: ~100 steps per bed period; MoorDyn RK4 at 0.1 ms.)
Tolerances: 1 % of g_s against the closed forms and beyond the fade-in; outright, 2 %
(7.5e3) and 6 % (3e5). Against the right closed form, damping cBot without the
diameter moves it by 99 % / 70 % of g_s, doubled by 26 % / 25 %, dropped by
100 % / 178 % (checked below on the closed form).
"""
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

import skmoor  # noqa: E402
from skmoor.solvers.dynamics import Scheme, integrate

DECK = Path(__file__).parents[1] / "decks" / "seabed" / "bed_drop.dat"
G0, RHO = 9.80665, 1025.0
MASS, DIAMETER, KBOT = 20.0, 0.1, 3.0e6  # the deck's
WEIGHT = (MASS - RHO * np.pi * DIAMETER ** 2 / 4) * G0  # N/m, submerged
G_STATIC = WEIGHT / (KBOT * DIAMETER)  # m
DURATION, DT, SAMPLE = 0.3, 5e-4, 1e-3  # s
MIDDLE = 5  # node index (of 0..10)
TOLERANCE_FORMULA, TOLERANCE_CODES = 0.01, 0.02  # of G_STATIC


def deck_with(workdir, cBot):
    path = Path(workdir) / "bed_drop.dat"
    text, n = re.subn(r"(?m)^\S+(\s+cBot\b)", rf"{cBot!r}\g<1>", DECK.read_text())
    assert n == 1
    path.write_text(text)
    return path


def closed_form(t, cBot, kBot=KBOT, diameter=DIAMETER):
    """Penetration (m) of the node: the step response of m g'' + c g' + k g = w from rest,
    c = cBot d, k = kBot d (per unit length)."""
    k, c = kBot * diameter, cBot * diameter
    omega = np.sqrt(k / MASS)
    zeta = c / (2 * np.sqrt(k * MASS))
    g_s = WEIGHT / k
    if zeta < 1:
        wd = omega * np.sqrt(1 - zeta ** 2)
        return g_s * (1 - np.exp(-zeta * omega * t) * (np.cos(wd * t)
                                                       + zeta * omega / wd * np.sin(wd * t)))
    r1, r2 = omega * (-zeta + np.sqrt(zeta ** 2 - 1)), omega * (-zeta - np.sqrt(zeta ** 2 - 1))
    return g_s * (1 + (r2 * np.exp(r1 * t) - r1 * np.exp(r2 * t)) / (r1 - r2))


def faded_oscillator(t, cBot, onset):
    """The same with the damping faded in over the first ``onset`` m of penetration,
    c min(g / onset, 1) (skmoor's bed), by solve_ivp to 1e-10."""
    k, c = KBOT * DIAMETER, cBot * DIAMETER

    def rhs(_, y):
        g, rate = y
        fade = min(max(g / onset, 0.0), 1.0)
        return [rate, (WEIGHT - k * g - c * fade * rate) / MASS]

    sol = solve_ivp(rhs, (0.0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-14,
                    method="DOP853")
    return sol.y[0]


def run_moordyn(path):
    """(t, penetration (nt, 11)) of the line's nodes, every SAMPLE s."""
    md = moordyn.Create(str(path))
    try:
        assert moordyn.Init(md, [], []) == 0
        line = moordyn.GetLine(md, 1)
        n = moordyn.GetLineN(line)
        t, g = [0.0], [[-20.0 - moordyn.GetLineNodePos(line, i)[2] for i in range(n + 1)]]
        for k in range(int(round(DURATION / SAMPLE))):
            moordyn.Step(md, [], [], k * SAMPLE, SAMPLE)
            t.append((k + 1) * SAMPLE)
            g.append([-20.0 - moordyn.GetLineNodePos(line, i)[2] for i in range(n + 1)])
    finally:
        moordyn.Close(md)
    return np.array(t), np.array(g)


def run_skmoor(path):
    """(t, penetration (nt, 11), the bed's damping onset (m)) from the deck's reference
    state at rest."""
    model = skmoor.build(str(path))
    system, lines = model.system, model.lines
    assert np.allclose(lines.points[:, 2], -20.0, atol=1e-12)  # straight on the bed
    assert np.abs(lines.fields["T"]).max() < 1e-6  # stress-free
    beds = [term for term in system.terms if hasattr(term, "onset")]
    assert len(beds) == 1
    x0 = np.zeros(system.n)
    t, g = [], []
    for state in integrate(system, x0, np.zeros(system.n), DT, DURATION, C=None,
                           scheme=Scheme.newmark()):
        u = system.full_displacement(state.x)[lines.nodal_dofs]
        t.append(state.t)
        g.append(-(lines.points[:, 2] + u[:, 2]) - 20.0)
    return np.array(t), np.array(g), float(np.max(beds[0].onset))


@pytest.fixture(scope="module", params=[7.5e3, 3.0e5], ids=["cBot=7.5e3", "cBot=3e5"])
def drop(request, tmp_path_factory):
    """cBot, MoorDyn's (t, g), skmoor's (t, g, onset), and on skmoor's times the closed
    form and the faded oscillator."""
    workdir = tmp_path_factory.mktemp("bed")
    path = deck_with(workdir, request.param)
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(workdir)
        md = run_moordyn(path)
    sk = run_skmoor(path)
    assert sk[0][0] == 0.0  # integrate yields the initial state first
    return request.param, md, sk, closed_form(sk[0], request.param), faded_oscillator(
        sk[0], request.param, sk[2])


def test_moordyn_is_the_oscillator(drop):
    """MoorDyn's middle node follows the closed form with c = cBot d within 1 % of g_s
    (this pins down MoorDyn's convention, which skmoor's deck reader copies)."""
    cBot, (t, g), _, _, _ = drop
    error = np.abs(g[:, MIDDLE] - closed_form(t, cBot)).max() / G_STATIC
    assert error < TOLERANCE_FORMULA, f"MoorDyn vs closed form: {error:.2e} g_s"


def test_skmoor_is_the_oscillator(drop):
    """skmoor's middle node follows the same oscillator with its fade-in (onset g_s / 10,
    as the bed reports it) within 1 % of g_s."""
    _, _, (_, g, onset), _, faded = drop
    assert onset == pytest.approx(0.1 * G_STATIC, rel=1e-6)
    error = np.abs(g[:, MIDDLE] - faded).max() / G_STATIC
    assert error < TOLERANCE_FORMULA, f"skmoor vs closed form: {error:.2e} g_s"


def test_skmoor_against_moordyn(drop):
    """Every inner node (the two next to the fixed ends included): skmoor - MoorDyn is the
    fade-in's effect (faded oscillator - closed form) within 1 % of g_s, and within 2 %
    (cBot = 7.5e3) or 6 % (3e5, where the creeping node spends longer in the fade-in)
    outright; both settle at g_s (the bed's stiffness kBot d: 0.39 mm) when ringing."""
    cBot, (t_md, g_md), (t, g, _), closed, faded = drop
    explained = np.interp(t_md, t, faded - closed)
    outright = TOLERANCE_CODES if cBot < 1e4 else 3 * TOLERANCE_CODES
    for node in range(1, g.shape[1] - 1):
        ours = np.interp(t_md, t, g[:, node])
        error = np.abs(ours - g_md[:, node] - explained).max() / G_STATIC
        assert error < TOLERANCE_FORMULA, f"node {node}: {error:.2e} g_s beyond the fade-in"
        error = np.abs(ours - g_md[:, node]).max() / G_STATIC
        assert error < outright, f"node {node}: {error:.2e} g_s"
    if cBot < 1e4:  # the ringing case has settled by the end
        assert g[-1, MIDDLE] == pytest.approx(G_STATIC, rel=0.02)
        assert g_md[-1, MIDDLE] == pytest.approx(G_STATIC, rel=0.02)


@pytest.mark.parametrize("cBot", [7.5e3, 3.0e5])
def test_the_comparison_tells_a_wrong_damping(cBot):
    """The closed forms above are far apart, beyond the tolerances, for the plausible
    mistakes: damping cBot without the diameter, doubled, or dropped."""
    t = np.arange(0.0, DURATION + 1e-12, SAMPLE)
    right = closed_form(t, cBot)
    for label, wrong in (("no diameter", closed_form(t, cBot / DIAMETER)),
                         ("doubled", closed_form(t, 2 * cBot)),
                         ("dropped", closed_form(t, 1e-9))):
        gap = np.abs(wrong - right).max() / G_STATIC
        assert gap > 5 * TOLERANCE_CODES, f"{label}: only {gap:.2%} of g_s"
