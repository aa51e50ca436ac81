"""The Lozon et al. (2025) lazy-wave power cables at 80 m and 200 m (examples/09_lazy_wave.py:
three bending lines joined smoothly) in their static state, against the published OrcaFlex
numbers (hang-off tension 9.32 kN, peak curvature 0.0968 1/m at 80 m; 25.16 kN,
0.0831 1/m at 200 m; CableDyn's VALIDATION.md, case L3-5) and against CableDyn run side
by side on the same deck."""
import importlib.util
import itertools
from pathlib import Path

import numpy as np
import pytest

EXAMPLE = Path(__file__).parents[2] / "examples" / "09_lazy_wave.py"
OPTIONS = """\
9.80665  g
1025.0   rhoW
{depth}    WtrDpth
1.0e5    kBot
1.0e4    cBot
0.05     dtM
0.0      TMax
"""


def load_example(monkeypatch, tmp_path, elements, sites="80m"):
    """examples/09_lazy_wave.py run on ``elements`` at ``sites`` (comma-separated), its
    figure written to ``tmp_path``."""
    monkeypatch.setenv("SKMOOR_EXAMPLE_ELEMENTS", str(elements))
    monkeypatch.setenv("SKMOOR_EXAMPLE_SITES", sites)
    monkeypatch.setenv("SKMOOR_EXAMPLE_OUT", str(tmp_path))
    spec = importlib.util.spec_from_file_location("lazy_wave", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def cabledyn_deck(ex, elements, workdir, options=OPTIONS, coefficients="0 0 0 0", site="80m"):
    """Path of a CableDyn deck of the example's cable at ``site`` (hang-off 'Coupled'), the
    sections meshed as skmoor's; options: the deck's OPTIONS rows ({depth}: the site's);
    coefficients: its line types' Cd_n Cd_t Ca_n Ca_t."""
    site = ex.SITES[site]
    network = ex.lazy_wave(site, elements)
    types = {}
    for line in network.lines:
        types.setdefault((line.line_type.diameter, line.line_type.mass), f"type{len(types) + 1}")
    rows = [f"{name} {d} {m} 4.69e8 0.0 1.99e4 {coefficients}" for (d, m), name in types.items()]
    sections = [f"1 {types[(ln.line_type.diameter, ln.line_type.mass)]} {ln.length} {ln.n_elements}"
                for ln in network.lines]
    deck = "\n".join([
        "--- CableDyn Input File ---",
        f"skmoor side-by-side: the Lozon {site.title} lazy-wave cable",
        "--- LINE TYPES ---", "TypeName Diam MassDenInAir EA BA EI Cd_n Cd_t Ca_n Ca_t",
        "(-) (m) (kg/m) (N) (-) (N-m2) (-) (-) (-) (-)", *rows,
        "--- POINTS ---", "ID Type X Y Z", "(-) (-) (m) (m) (m)",
        "1 Coupled {} {} {}".format(*site.hang_off), "2 Fixed {} {} {}".format(*site.anchor),
        "--- LINES ---", "ID NodeA NodeB Outputs", "(-) (-) (-) (-)", "1 1 2 -",
        "--- SECTIONS ---", "LineID LineType Length NumSegs", "(-) (-) (m) (-)", *sections,
        "--- OPTIONS ---", options.format(depth=site.depth).rstrip(),
        "--- OUTPUTS ---", '"FairTen1"',
        "--- need this line ---", ""])
    path = workdir / "lazy_wave_cabledyn.dat"
    path.write_text(deck)
    return path


def cabledyn_static(ex, elements, workdir, site="80m"):
    """(hang-off tension N, curvature at the nodes 1/m, node positions (n, 3) m) of the
    example's cable at ``site`` in CableDyn (its static initialisation, TMax = 0), the
    sections meshed as skmoor's."""
    cabledyn = pytest.importorskip("cabledyn")
    model = cabledyn.CableDyn(str(cabledyn_deck(ex, elements, workdir, site=site)))
    try:
        line = model.line(1)
        return (float(line.fairlead_tension()), np.asarray(line.curvature()),
                np.asarray(line.node_positions()))
    finally:
        model.close()


def distance_to_polyline(points, polyline):
    """(n,) distance (m) of each point from the polyline (m, 3)."""
    a, b = polyline[:-1], polyline[1:]
    d = points[:, None, :] - a[None]
    t = np.clip(np.einsum("nmc,mc->nm", d, b - a) / np.einsum("mc,mc->m", b - a, b - a), 0, 1)
    gap = d - t[..., None] * (b - a)[None]
    return np.linalg.norm(gap, axis=2).min(axis=1)


def test_lazy_wave_static_against_orcaflex_and_cabledyn(monkeypatch, tmp_path):
    """80 m, 128 elements (the deck's 1024 / 8; from 128 to 1024 the hang-off tension moves
    by 6e-6 and the peak curvature at the element mid-points by 0.25 %): hang-off tension
    within 0.06 % of OrcaFlex's 9.32 kN (its three digits), peak curvature within 0.5 %
    of 0.0968 1/m; CableDyn on the same mesh: tension within 1e-4, peak curvature (at
    its nodes) within 0.5 %, every node within 2 cm of CableDyn's line (its nodes are
    placed differently along the buoyancy section), the touchdown (where the cable first
    reaches the bed's plane) within 2 cm of CableDyn's (measured 7 mm). A hinged joint, a
    dropped buoyancy or a wrong EI moves these by percents."""
    ex = load_example(monkeypatch, tmp_path, 128)
    cable, orcaflex = ex.cables["80m"], ex.SITES["80m"].orcaflex
    assert cable.hang_off_tension == pytest.approx(orcaflex["hang_off_tension"], rel=6e-4)
    assert cable.curvature.max() == pytest.approx(orcaflex["peak_curvature"], rel=5e-3)
    assert 50.0 < cable.arc[np.argmax(cable.curvature)] < 65.0  # the sag bend above the buoyancy
    assert (tmp_path / "lazy_wave.png").stat().st_size > 10_000
    tension, curvature, positions = cabledyn_static(ex, 128, tmp_path)
    assert cable.hang_off_tension == pytest.approx(tension, rel=1e-4)
    assert cable.curvature.max() == pytest.approx(curvature.max(), rel=5e-3)
    assert np.max(distance_to_polyline(cable.nodes, positions)) < 0.02
    assert np.array(cable.touchdown) == pytest.approx(ex.touchdown(positions, 80.0), abs=0.02)


def test_lazy_wave_200m_against_orcaflex_and_cabledyn(monkeypatch, tmp_path):
    """The Gulf of Maine 200 m cable, 476 elements (the deck's 952 / 2): hang-off tension
    within 3e-4 of OrcaFlex's 25.16 kN (its four digits; measured 1e-5), peak curvature
    within 0.3 % of 0.0831 1/m (+0.03 %; at 952 elements +0.05 %, CableDyn's +0.07 %),
    the sag bend 150-170 m down the arc (the bare top's lowest point, above the buoyancy
    from 172 m); CableDyn on the same mesh: tension within 1e-6 (5e-8), peak curvature
    within 1e-3 (1e-5), every node and the touchdown (264.20 m down the arc, x = 115.70 m)
    within 1 cm (0.1 mm). EI 10 % higher moves the peak curvature by -0.6 % and the
    touchdown by 11 cm, a dropped buoyancy all of them by far more; a hinged joint moves
    this peak by 0.16 % only (it is in the bare top, away from the joints: the 80 m test
    catches that)."""
    ex = load_example(monkeypatch, tmp_path, 476, sites="200m")
    cable, orcaflex = ex.cables["200m"], ex.SITES["200m"].orcaflex
    assert cable.hang_off_tension == pytest.approx(orcaflex["hang_off_tension"], rel=3e-4)
    assert cable.curvature.max() == pytest.approx(orcaflex["peak_curvature"], rel=3e-3)
    assert 150.0 < cable.arc[np.argmax(cable.curvature)] < 170.0
    tension, curvature, positions = cabledyn_static(ex, 476, tmp_path, site="200m")
    assert cable.hang_off_tension == pytest.approx(tension, rel=1e-6)
    assert cable.curvature.max() == pytest.approx(curvature.max(), rel=1e-3)
    assert np.max(distance_to_polyline(cable.nodes, positions)) < 0.01
    assert np.array(cable.touchdown) == pytest.approx(ex.touchdown(positions, 200.0), abs=0.01)


@pytest.mark.slow
def test_lazy_wave_mesh_convergence(monkeypatch, tmp_path):
    """80 m, the deck's 1024 elements: hang-off tension within 1e-5 of CableDyn's and the
    peak curvature within 0.05 % (CableDyn: 9320.17 N, 0.096829 1/m; OrcaFlex 9.32 kN,
    0.0968 1/m within 0.1 %); from 256 to 1024 elements both move less than 0.05 %
    (the mid-point peak converges from below: 0.096791, 0.096804, 0.096823)."""
    coarse = load_example(monkeypatch, tmp_path, 256).cables["80m"]
    ex = load_example(monkeypatch, tmp_path, 1024)
    cable = ex.cables["80m"]
    tension, curvature, positions = cabledyn_static(ex, 1024, tmp_path)
    assert cable.hang_off_tension == pytest.approx(tension, rel=1e-5)
    assert cable.curvature.max() == pytest.approx(curvature.max(), rel=5e-4)
    assert cable.curvature.max() == pytest.approx(ex.SITES["80m"].orcaflex["peak_curvature"],
                                                  rel=1e-3)
    assert np.max(distance_to_polyline(cable.nodes, positions)) < 0.005
    assert coarse.hang_off_tension == pytest.approx(cable.hang_off_tension, rel=5e-4)
    assert coarse.curvature.max() == pytest.approx(cable.curvature.max(), rel=5e-4)
    assert coarse.curvature.max() < cable.curvature.max()


@pytest.mark.slow
def test_lazy_wave_200m_mesh_convergence(monkeypatch, tmp_path):
    """200 m, from 238 to 952 elements (the deck's): the hang-off tension moves by 1e-5
    (25159.53, 25159.80, 25159.82 N), the mid-point peak curvature converges from below
    (0.082899, 0.083122, 0.083145 1/m: 0.3 % then 0.03 %), the touchdown up the cable by
    2 dm (264.34, 264.20, 264.13 m down the arc: the polyline of coarser nodes cuts the bed
    plane later); at 952 elements: tension within 1e-6 of CableDyn's, peak curvature
    within 0.05 % of CableDyn's (0.083156) and 0.1 % of OrcaFlex's 0.0831, touchdown and
    nodes within 1 mm of CableDyn's."""
    coarse = load_example(monkeypatch, tmp_path, 238, sites="200m").cables["200m"]
    ex = load_example(monkeypatch, tmp_path, 952, sites="200m")
    cable = ex.cables["200m"]
    tension, curvature, positions = cabledyn_static(ex, 952, tmp_path, site="200m")
    assert cable.hang_off_tension == pytest.approx(tension, rel=1e-6)
    assert cable.curvature.max() == pytest.approx(curvature.max(), rel=5e-4)
    assert cable.curvature.max() == pytest.approx(ex.SITES["200m"].orcaflex["peak_curvature"],
                                                  rel=1e-3)
    assert np.max(distance_to_polyline(cable.nodes, positions)) < 1e-3
    assert np.array(cable.touchdown) == pytest.approx(ex.touchdown(positions, 200.0), abs=1e-3)
    assert coarse.hang_off_tension == pytest.approx(cable.hang_off_tension, rel=2e-5)
    assert cable.curvature.max() * 0.995 < coarse.curvature.max() < cable.curvature.max()
    assert coarse.touchdown[0] == pytest.approx(cable.touchdown[0], abs=0.3)


def test_first_guess_meets_the_joints_with_one_tangent(monkeypatch, tmp_path):
    """The catenary network of the cable (EI = 0; the buoyant section's catenary upside
    down): at a massless junction the two sections pass one tension vector T t, so their
    end tangents agree (to the settling's 1e-6 force balance), and the buoyant section's
    reference is of unit speed (|X'| = 1 at its Gauss points to 1e-3: an elastic
    catenary; a stress-free polyline bent between its nodes is not)."""
    model = load_example(monkeypatch, tmp_path, 128).cables["80m"].model
    lines = model.lines.lines
    for before, after in itertools.pairwise(lines):
        t_b = before.tangent(np.array([before.s[-1]]))[0]
        t_a = after.tangent(np.array([after.s[0]]))[0]
        assert np.degrees(np.arccos(min(1.0, t_b @ t_a))) < 1e-3
    buoyant = model.lines.line_of_cell == 1
    speed = np.linalg.norm(model.lines.fields["Xp"][:, buoyant], axis=0)
    assert np.abs(speed - 1).max() < 1e-3
    assert lines[1].tension(lines[1].s).min() > 0  # a catenary, not a stress-free guess
