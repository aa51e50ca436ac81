"""The Lozon et al. (2025) 80 m lazy-wave power cable (examples/09_lazy_wave.py: three
bending lines joined smoothly) in its static state, against the published OrcaFlex
numbers (hang-off tension 9.32 kN, peak curvature 0.0968 1/m; CableDyn's VALIDATION.md,
case L3-5) and against CableDyn run side by side on the same deck."""
import importlib.util
import itertools
from pathlib import Path

import numpy as np
import pytest

EXAMPLE = Path(__file__).parents[1] / "examples" / "09_lazy_wave.py"
OPTIONS = """\
9.80665  g
1025.0   rhoW
80.0     WtrDpth
1.0e5    kBot
1.0e4    cBot
0.05     dtM
0.0      TMax
"""


def load_example(monkeypatch, tmp_path, elements):
    monkeypatch.setenv("SKMOOR_EXAMPLE_ELEMENTS", str(elements))
    monkeypatch.setenv("SKMOOR_EXAMPLE_OUT", str(tmp_path))
    spec = importlib.util.spec_from_file_location("lazy_wave", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def cabledyn_deck(ex, elements, workdir, options=OPTIONS, coefficients="0 0 0 0"):
    """Path of a CableDyn deck of the example's cable (hang-off 'Coupled'), the sections
    meshed as skmoor's; options: the deck's OPTIONS rows; coefficients: its line types'
    Cd_n Cd_t Ca_n Ca_t."""
    network = ex.lazy_wave(elements)
    types = {}
    for line in network.lines:
        types.setdefault((line.line_type.diameter, line.line_type.mass), f"type{len(types) + 1}")
    rows = [f"{name} {d} {m} 4.69e8 0.0 1.99e4 {coefficients}" for (d, m), name in types.items()]
    sections = [f"1 {types[(ln.line_type.diameter, ln.line_type.mass)]} {ln.length} {ln.n_elements}"
                for ln in network.lines]
    deck = "\n".join([
        "--- CableDyn Input File ---", "skmoor side-by-side: the Lozon 80 m lazy-wave cable",
        "--- LINE TYPES ---", "TypeName Diam MassDenInAir EA BA EI Cd_n Cd_t Ca_n Ca_t",
        "(-) (m) (kg/m) (N) (-) (N-m2) (-) (-) (-) (-)", *rows,
        "--- POINTS ---", "ID Type X Y Z", "(-) (-) (m) (m) (m)",
        "1 Coupled {} {} {}".format(*ex.HANG_OFF), "2 Fixed {} {} {}".format(*ex.ANCHOR),
        "--- LINES ---", "ID NodeA NodeB Outputs", "(-) (-) (-) (-)", "1 1 2 -",
        "--- SECTIONS ---", "LineID LineType Length NumSegs", "(-) (-) (m) (-)", *sections,
        "--- OPTIONS ---", options.rstrip(), "--- OUTPUTS ---", '"FairTen1"',
        "--- need this line ---", ""])
    path = workdir / "lazy_wave_cabledyn.dat"
    path.write_text(deck)
    return path


def cabledyn_static(ex, elements, workdir):
    """(hang-off tension N, curvature at the nodes 1/m, node positions (n, 3) m) of the
    example's cable in CableDyn (its static initialisation, TMax = 0), the sections
    meshed as skmoor's."""
    cabledyn = pytest.importorskip("cabledyn")
    model = cabledyn.CableDyn(str(cabledyn_deck(ex, elements, workdir)))
    try:
        line = model.line(1)
        return (float(line.fairlead_tension()), np.asarray(line.curvature()),
                np.asarray(line.node_positions()))
    finally:
        model.close()


def nodes_along(ex):
    """(n, 3) node positions of the example's solved cable from the hang-off, each joint once."""
    lines = ex.model.lines
    shape = lines.points + ex.u[lines.nodal_dofs]
    parts = [shape[a:b + 1] for a, b in zip(lines.anchor_nodes, lines.fairlead_nodes)]
    return np.concatenate([parts[0]] + [p[1:] for p in parts[1:]])


def distance_to_polyline(points, polyline):
    """(n,) distance (m) of each point from the polyline (m, 3)."""
    a, b = polyline[:-1], polyline[1:]
    d = points[:, None, :] - a[None]
    t = np.clip(np.einsum("nmc,mc->nm", d, b - a) / np.einsum("mc,mc->m", b - a, b - a), 0, 1)
    gap = d - t[..., None] * (b - a)[None]
    return np.linalg.norm(gap, axis=2).min(axis=1)


def test_lazy_wave_static_against_orcaflex_and_cabledyn(monkeypatch, tmp_path):
    """128 elements (the deck's 1024 / 8; from 128 to 1024 the hang-off tension moves by
    6e-6 and the peak curvature at the element mid-points by 0.25 %): hang-off tension
    within 0.06 % of OrcaFlex's 9.32 kN (its three digits), peak curvature within 0.5 %
    of 0.0968 1/m; CableDyn on the same mesh: tension within 1e-4, peak curvature (at
    its nodes) within 0.5 %, every node within 2 cm of CableDyn's line (its nodes are
    placed differently along the buoyancy section). A hinged joint, a
    dropped buoyancy or a wrong EI moves these by percents."""
    ex = load_example(monkeypatch, tmp_path, 128)
    assert ex.hang_off_tension == pytest.approx(ex.ORCAFLEX["hang_off_tension"], rel=6e-4)
    assert ex.curvature.max() == pytest.approx(ex.ORCAFLEX["peak_curvature"], rel=5e-3)
    assert 50.0 < ex.arc[np.argmax(ex.curvature)] < 65.0  # the sag bend above the buoyancy
    assert (tmp_path / "lazy_wave.png").stat().st_size > 10_000
    tension, curvature, positions = cabledyn_static(ex, 128, tmp_path)
    assert ex.hang_off_tension == pytest.approx(tension, rel=1e-4)
    assert ex.curvature.max() == pytest.approx(curvature.max(), rel=5e-3)
    assert np.max(distance_to_polyline(nodes_along(ex), positions)) < 0.02


@pytest.mark.slow
def test_lazy_wave_mesh_convergence(monkeypatch, tmp_path):
    """The deck's 1024 elements: hang-off tension within 1e-5 of CableDyn's and the peak
    curvature within 0.05 % (CableDyn: 9320.17 N, 0.096829 1/m; OrcaFlex 9.32 kN,
    0.0968 1/m within 0.1 %); from 256 to 1024 elements both move less than 0.05 %
    (the mid-point peak converges from below: 0.096791, 0.096804, 0.096823)."""
    coarse = load_example(monkeypatch, tmp_path, 256)
    ex = load_example(monkeypatch, tmp_path, 1024)
    tension, curvature, positions = cabledyn_static(ex, 1024, tmp_path)
    assert ex.hang_off_tension == pytest.approx(tension, rel=1e-5)
    assert ex.curvature.max() == pytest.approx(curvature.max(), rel=5e-4)
    assert ex.curvature.max() == pytest.approx(ex.ORCAFLEX["peak_curvature"], rel=1e-3)
    assert np.max(distance_to_polyline(nodes_along(ex), positions)) < 0.005
    assert coarse.hang_off_tension == pytest.approx(ex.hang_off_tension, rel=5e-4)
    assert coarse.curvature.max() == pytest.approx(ex.curvature.max(), rel=5e-4)
    assert coarse.curvature.max() < ex.curvature.max()


def test_first_guess_meets_the_joints_with_one_tangent(monkeypatch, tmp_path):
    """The catenary network of the cable (EI = 0; the buoyant section's catenary upside
    down): at a massless junction the two sections pass one tension vector T t, so their
    end tangents agree (to the settling's 1e-6 force balance), and the buoyant section's
    reference is of unit speed (|X'| = 1 at its Gauss points to 1e-3: an elastic
    catenary; a stress-free polyline bent between its nodes is not)."""
    ex = load_example(monkeypatch, tmp_path, 128)
    lines = ex.model.lines.lines
    for before, after in itertools.pairwise(lines):
        t_b = before.tangent(np.array([before.s[-1]]))[0]
        t_a = after.tangent(np.array([after.s[0]]))[0]
        assert np.degrees(np.arccos(min(1.0, t_b @ t_a))) < 1e-3
    buoyant = ex.model.lines.line_of_cell == 1
    speed = np.linalg.norm(ex.model.lines.fields["Xp"][:, buoyant], axis=0)
    assert np.abs(speed - 1).max() < 1e-3
    assert lines[1].tension(lines[1].s).min() > 0  # a catenary, not a stress-free guess
