"""A line with a tension-strain curve in statics, against an independent integration of
the elastic catenary with that curve.

The reference (in this file only): the line's equilibrium as an initial-value problem in
the unstretched arclength s from the anchor, dx/ds = (1 + e(T)) H / T,
dz/ds = (1 + e(T)) V / T, V = V_A + w s, T = hypot(H, V), e(T) the curve's strain at T
(np.interp, the last slope beyond the table), integrated by scipy's solve_ivp (DOP853,
rtol 1e-12) and shot onto the fairlead by a root find on (H, V_A).

Checked against it: skmoor's closed-form catenary with the curve law (piecewise exact),
the FE statics of the forms and kernel started from a stress-free sagging polyline (so
the answer owes nothing to the closed form), and a MoorDyn deck whose EA column is a
curve file (deck -> Curve -> network -> statics). Plausible bugs each catches: a wrong
piece of e(T) (the closed form), a wrong stress resultant or slope in the forms (the FE
statics), a curve file read wrongly or relative to the wrong folder (the deck).
"""
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

import skmoor
from skmoor import laws
from skmoor.lines.line import Line, LineSet, LineType

STRAIN = [0.01, 0.02, 0.03, 0.05]
TENSION = [1.0e5, 2.5e5, 4.5e5, 1.4e6]  # N: slopes 1e7, 1.5e7, 2e7, 4.75e7 N (stiffening)
W = 600.0  # submerged weight, N/m
L = 1000.0  # unstretched length, m
ANCHOR, FAIRLEAD = np.array([0.0, 0.0, -400.0]), np.array([850.0, 0.0, 0.0])


def strain_of(T):
    """The curve's strain at tension T (N), linear beyond its last point."""
    e, t = np.r_[0.0, STRAIN], np.r_[0.0, TENSION]
    slope = (t[-1] - t[-2]) / (e[-1] - e[-2])
    return np.where(T <= t[-1], np.interp(T, t, e), e[-1] + (T - t[-1]) / slope)


def shoot(H, VA, s_eval=None):
    """The line's end (x, z) relative to the anchor (and positions at s_eval)."""
    def rhs(s, y):
        V = VA + W * s
        T = np.hypot(H, V)
        stretch = 1.0 + strain_of(T)
        return [stretch * H / T, stretch * V / T]
    sol = solve_ivp(rhs, (0.0, L), [0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-9,
                    t_eval=s_eval, dense_output=False)
    return sol.y


def shot_line():
    """(H, V_A, T_A, T_B) of the shot line, N."""
    span, rise = FAIRLEAD[0] - ANCHOR[0], FAIRLEAD[2] - ANCHOR[2]

    def miss(p):
        y = shoot(p[0] * 1e5, p[1] * 1e5)
        return [y[0, -1] - span, y[1, -1] - rise]

    H, VA = fsolve(miss, [3.0, 0.5], xtol=1e-13) * 1e5
    assert np.max(np.abs(miss([H / 1e5, VA / 1e5]))) < 1e-7
    VB = VA + W * L
    return H, VA, np.hypot(H, VA), np.hypot(H, VB)


@pytest.fixture(scope="module")
def reference():
    """The shot line, once for the module."""
    return shot_line()


def test_the_reference_line_uses_the_curve(reference):
    """The shot line dips below its anchor (the tension is least, H, where V = 0) and
    strains across a knot of the curve (two of its pieces in use)."""
    H, VA, _TA, TB = reference
    assert VA < 0
    assert STRAIN[1] < strain_of(H) < STRAIN[2] < strain_of(TB) < STRAIN[3]


def test_closed_form_catenary_with_the_curve(reference):
    """skmoor's closed-form catenary with the curve law: H, V_A, end tensions to 1e-9 and
    the profile (positions at 11 arclengths) to 1e-7 m."""
    H, VA, _TA, TB = reference
    cat = skmoor.solve_catenary(ANCHOR, FAIRLEAD, W, 2e7, length=L,
                                law=laws.Curve(STRAIN, TENSION))
    assert cat.H == pytest.approx(H, rel=1e-9)
    assert cat.V_anchor == pytest.approx(VA, rel=1e-9)
    assert cat.T_fairlead == pytest.approx(TB, rel=1e-9)
    s = np.linspace(0.0, L, 11)
    x, z = shoot(H, VA, s)
    X = cat.position(s)
    assert np.abs(X[:, 0] - (ANCHOR[0] + x)).max() < 1e-7
    assert np.abs(X[:, 2] - (ANCHOR[2] + z)).max() < 1e-7
    # stretched length: int (1 + e(T)) ds against the trapezoid on a fine grid
    fine = np.linspace(0.0, L, 20001)
    T = np.hypot(H, VA + W * fine)
    stretched = np.trapezoid(1.0 + strain_of(T), fine)
    assert cat.stretched_arclength(L)[0] == pytest.approx(stretched, rel=1e-8)


def fe_statics(n):
    """End tensions (N) of the FE static solve from a stress-free sagging polyline."""
    lt = LineType(EA=None, mass=W / 9.81 + 1025.0 * np.pi * 0.1**2 / 4, diameter=0.1,
                  law=laws.Curve(STRAIN, TENSION))
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    chord = FAIRLEAD - ANCHOR

    def polyline(d):
        return ANCHOR + t * chord + d * 4 * t * (1 - t) * np.array([0.0, 0.0, -1.0])

    lo, hi = 0.0, 1000.0  # the sag that gives the polyline the length L, by bisection
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        length = np.linalg.norm(np.diff(polyline(mid), axis=0), axis=1).sum()
        lo, hi = (mid, hi) if length < L else (lo, mid)
    line = Line.from_polyline(polyline(hi), lt)
    system = skmoor.System(LineSet([line]), fairleads="fixed")
    x = skmoor.solve_static(system, steps=8, pretension=W * L).x
    fair, anchor = system.reactions(x)
    return np.linalg.norm(anchor[0]), np.linalg.norm(fair[0])


def test_fe_statics_with_the_curve_from_a_stress_free_line(reference):
    """The FE equilibrium (forms and compiled kernel with the curve's tension and slope)
    reached from a stress-free polyline: end tensions within 0.05 % at 40 elements, and
    closer at 80 (the error falls with the element size)."""
    _, _, TA, TB = reference
    errors = []
    for n in (40, 80):
        ta, tb = fe_statics(n)
        errors.append(max(abs(ta / TA - 1), abs(tb / TB - 1)))
    assert errors[0] < 5e-4
    assert errors[1] < 0.5 * errors[0]


def poly_deck(EA, mass=60.0, options=""):
    """A one-line MoorDyn deck's text: 1000 m of line type 'poly' (EA column ``EA``, mass
    kg/m) in 40 segments from an anchor 400 m deep to a fairlead 850 m away at the
    surface; ``options``: the OPTIONS section's rows (none: no section). The line type's
    row is line 5."""
    text = f"""--- MoorDyn input file ---
---------------------- LINE TYPES -----------------------------------
TypeName   Diam    Mass/m    EA          BA/-zeta  EI   Cd   Ca   CdAx  CaAx
(name)     (m)     (kg/m)    (N)         (N-s/-)   (-)  (-)  (-)  (-)   (-)
poly       0.1     {mass!r}  {EA}        -0.8      0.0  1.2  1.0  0.0   0.0
---------------------- POINTS ---------------------------------------
ID  Attachment  X      Y    Z       Mass  Volume  CdA  Ca
(#) (-)         (m)    (m)  (m)     (kg)  (m^3)   (m2) (-)
1   Fixed       0.0    0.0  -400.0  0     0       0    0
2   Coupled     850.0  0.0  0.0     0     0       0    0
---------------------- LINES ----------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  Outputs
(#) (name)    (#)      (#)      (m)       (-)      (-)
1   poly      1        2        1000.0    40       -
"""
    if options:
        text += "---------------------- OPTIONS --------------------------------------\n" + options
    return text + "---------------------- END ------------------------------------------\n"


def test_deck_with_a_curve_file(reference, tmp_path):
    """A MoorDyn deck whose EA column names a curve file (relative to the deck's folder,
    three header lines): its static end tensions against the reference within 0.05 %."""
    _, _, TA, TB = reference
    (tmp_path / "curves").mkdir()
    rows = "\n".join(f"{e} {t}" for e, t in zip(STRAIN, TENSION))
    (tmp_path / "curves" / "poly.txt").write_text(
        f"polyester working curve\nStrain Tension\n(-) (N)\n{rows}\n")
    mass = W / 9.80665 + 1025.0 * np.pi * 0.1**2 / 4
    deck = tmp_path / "curve.dat"
    deck.write_text(poly_deck("curves/poly.txt", mass, "500.0   WtrDpth\n0       kBot\n"))
    parsed = skmoor.read_deck(deck)
    lt = parsed.line_types["poly"]
    assert lt.EA_file == "curves/poly.txt"
    assert lt.EA == pytest.approx(TENSION[-1] / STRAIN[-1])  # MoorDyn's EA of a curve
    static = skmoor.static_results(skmoor.build(deck))
    assert static.fairlead_tension[0, 0] == pytest.approx(TB, rel=5e-4)
    assert static.anchor_tension[0, 0] == pytest.approx(TA, rel=5e-4)
    written = skmoor.write_deck(parsed, tmp_path / "out" / "again.dat")
    assert skmoor.read_deck(written).line_types["poly"].EA_curve == lt.EA_curve


def test_deck_curve_file_errors(tmp_path):
    """A missing curve file or a bad curve is refused with the deck line and the reason."""
    deck = tmp_path / "bad.dat"
    deck.write_text(poly_deck("nowhere.txt"))
    with pytest.raises(ValueError, match=r"^bad.dat line 5: LINE TYPES EA: 'nowhere.txt' is "
                                         r"neither a number nor a curve file"):
        skmoor.read_deck(deck)
    (tmp_path / "flat.txt").write_text("h\nh\nh\n0.01 100\n0.02 100\n")
    deck.write_text(poly_deck("flat.txt"))
    with pytest.raises(ValueError, match=r"^bad.dat line 5: LINE TYPES EA .*flat.txt.*tension "
                                         r"must increase point by point"):
        skmoor.read_deck(deck)
    deck.write_text(poly_deck("1e8|1e8"))
    with pytest.raises(ValueError, match=r"^bad.dat line 5: LINE TYPES EA: EA_d = EA_s"):
        skmoor.read_deck(deck)
