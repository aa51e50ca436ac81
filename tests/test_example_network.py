"""Example 07 (a spar buoy on three chain-polyester-chain legs, a clump weight on leg 1)
run shortened to 20 s, as tests/test_examples.py runs the others.

The checks use numbers the solver does not produce: the case file's masses, volumes and
box (read here with tomllib), water density and gravity. The static state balances the
buoy (box buoyancy at its draft = weight + the legs' pull) and every junction (the clump
weight's submerged weight against its two lines), legs 2 and 3 are mirror images, the
buoy's rigid-body periods follow from its mass over the mooring plus hydrostatic
stiffness, a static push agrees with that stiffness, and the files are written. The end
tensions and the mooring stiffness are also held to MoorPy's (a different code: analytic
elastic catenaries with frictionless touchdown), written out below.
"""
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np
import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

EXAMPLES = Path(__file__).parents[1] / "examples"
CASE = tomllib.loads((EXAMPLES / "network_buoy.toml").read_text())
RHO, G = CASE["water"]["density"], CASE["water"]["gravity"]
BUOY = CASE["bodies"][0]
POINTS = {p["name"]: p for p in CASE["points"]}
DURATION = 20.0  # s

# MoorPy 1.3 on the same network written as a MoorDyn deck (the line types, points and
# lines of network_buoy.toml; the buoy a coupled body held where skmoor's statics put it:
# (1.33006, 0, -5.96032) m, pitch -0.011744 deg), solved by tests/moorpy_network.py's
# moorpy_reference (its sanity checks: catenaries, point and body balance to 1e-10).
MOORPY_TENSION_A = {"bottom": (187541.8, 186874.0), "rope": (206910.6, 207500.8),
                    "top": (224246.6, 212012.9)}    # N, (leg 1, legs 2 and 3), end A
MOORPY_TENSION_B = {"bottom": (206910.6, 207500.8), "rope": (211304.2, 212012.9),
                    "top": (261151.8, 245319.5)}    # N, end B
MOORPY_PULL_Z = -499603.6      # N, the lines' vertical force on the buoy
MOORPY_STIFFNESS = [29198.9, 31847.2, 13812.6, 6614442.0, 6464890.4, 3126513.0]  # diag


@pytest.fixture(scope="module")
def ex(tmp_path_factory):
    out = tmp_path_factory.mktemp("network")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("SKMOOR_EXAMPLE_DURATION", str(DURATION))
        mp.setenv("SKMOOR_EXAMPLE_OUT", str(out))
        spec = importlib.util.spec_from_file_location("network_example",
                                                      EXAMPLES / "07_network.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    module.out = out
    return module


def end_forces(ex):
    """{(line, 'a' | 'b'): force (3,) N the line exerts on that end} at the static state,
    checked against the end tensions the static Results report."""
    fb, fa = ex.model.system.reactions(ex.eq.x)
    st = ex.static
    np.testing.assert_allclose(np.linalg.norm(fb, axis=1), st.fairlead_tension[0], rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(fa, axis=1), st.anchor_tension[0], rtol=1e-12)
    forces = {}
    for k, line in enumerate(CASE["lines"]):
        assert st.line_names[k] == line["name"]
        forces[line["name"], "a"], forces[line["name"], "b"] = fa[k], fb[k]
    return forces


def test_buoy_balances_its_weight_buoyancy_and_the_legs_pull(ex):
    """Box buoyancy rho g L W (draft - heave) = weight + the downward pull of the three
    top chains at the fairleads, and their horizontal pulls cancel (no current, no load
    at t = 0)."""
    forces = end_forces(ex)
    pull = sum(forces[f"{leg}.top", "b"] for leg in ex.LEGS)
    length, width, height = BUOY["size"]
    draft = height / 2 - BUOY["position"][2]               # 16 m at the given position
    heave = ex.static.bodies[0, 0, 2]                       # m, from the given position
    buoyancy = RHO * G * length * width * (draft - heave)
    weight = BUOY["mass"] * G
    assert abs(heave) < 0.1                                 # the case floats it near its draft
    assert buoyancy - weight + pull[2] == pytest.approx(0.0, abs=1e-6 * weight)
    np.testing.assert_allclose(pull[:2], 0.0, atol=1e-6 * np.linalg.norm(pull))
    assert pull[2] == pytest.approx(MOORPY_PULL_Z, rel=1e-3)


def test_static_tensions_and_stiffness_against_moorpy(ex):
    """End tensions of every line within 0.1 % of MoorPy's; the diagonal of the buoy's
    mooring stiffness within 5 % (the FE bed is node-wise: the stiffness moves by a few
    % with the bottom chain's mesh as nodes at the touchdown touch or not)."""
    st = ex.static
    names = list(st.line_names)
    for leg in ex.LEGS:
        column = 0 if leg == "leg1" else 1
        for part in ("bottom", "rope", "top"):
            k = names.index(f"{leg}.{part}")
            assert st.anchor_tension[0][k] == pytest.approx(MOORPY_TENSION_A[part][column],
                                                            rel=1e-3), (leg, part)
            assert st.fairlead_tension[0][k] == pytest.approx(MOORPY_TENSION_B[part][column],
                                                              rel=1e-3), (leg, part)
    np.testing.assert_allclose(np.diag(ex.stiffness), MOORPY_STIFFNESS, rtol=0.05)


def test_every_junction_balances_its_lines(ex):
    """At the clump weight the two lines hold up (m - rho V) g; at the bare junctions
    the two lines' end forces cancel."""
    forces = end_forces(ex)
    clump = POINTS["leg1.upper"]
    submerged = (clump["mass"] - RHO * clump["volume"]) * G  # 25.6 kN
    for leg in ex.LEGS:
        lower = forces[f"{leg}.bottom", "b"] + forces[f"{leg}.rope", "a"]
        upper = forces[f"{leg}.rope", "b"] + forces[f"{leg}.top", "a"]
        scale = np.linalg.norm(forces[f"{leg}.top", "a"])
        np.testing.assert_allclose(lower, 0.0, atol=1e-8 * scale)
        expected = [0.0, 0.0, submerged if leg == "leg1" else 0.0]
        np.testing.assert_allclose(upper, expected, atol=1e-8 * scale)
    # the clump pulls leg 1 down: its upper junction hangs lower than the other legs'
    z = dict(zip(ex.static.point_names, ex.static.point_positions(0)[:, 2]))
    assert z["leg1.upper"] < z["leg2.upper"] - 2.0


def test_legs_2_and_3_are_mirror_images(ex):
    """The layout is symmetric about the x-z plane (the clump on leg 1 lies in it): legs
    2 and 3 carry the same tensions, their junctions mirror, the buoy neither sways nor
    rolls nor yaws."""
    st = ex.static
    names = list(st.line_names)
    for part in ("bottom", "rope", "top"):
        i, j = names.index(f"leg2.{part}"), names.index(f"leg3.{part}")
        for tension in (st.fairlead_tension[0], st.anchor_tension[0]):
            assert tension[i] == pytest.approx(tension[j], rel=1e-6)
    where = dict(zip(st.point_names, st.point_positions(0)))
    for point in ("lower", "upper", "fairlead"):
        np.testing.assert_allclose(where[f"leg3.{point}"] * [1, -1, 1], where[f"leg2.{point}"],
                                   atol=1e-6)
    np.testing.assert_allclose(st.bodies[0, 0, [1, 3, 5]], 0.0, atol=1e-9)
    # and the clump makes leg 1 the tautest at the fairlead, so the buoy sits off towards it
    assert st.fairlead_tension[0][names.index("leg1.top")] > st.fairlead_tension[0][
        names.index("leg2.top")]
    assert st.bodies[0, 0, 0] > 0.5


def test_rigid_body_periods_follow_from_mass_over_stiffness(ex):
    """Each of the buoy's surge, sway, heave and yaw modes (the mode with the largest
    share of its kinetic energy in that DOF) within 5 % of 2 pi sqrt(M / K): M the buoy's
    mass (inertia) plus added mass from the case, K the mooring stiffness plus, in heave,
    the waterplane's rho g L W. The lines' own inertia makes the modes a little slower."""
    system, eq, K = ex.model.system, ex.eq, ex.stiffness
    shapes = eq.modes.shapes
    energy = shapes * (system.M @ shapes)
    share = energy[system.nf:system.nf + 6] / energy.sum(axis=0)
    length, width, _ = BUOY["size"]
    added = BUOY["added_mass"]
    assert BUOY["center_of_mass"][:2] == [0.0, 0.0]  # so yaw inertia about the reference = Izz
    expected = {
        0: (BUOY["mass"] + added[0], K[0, 0]),                                     # surge
        1: (BUOY["mass"] + added[1], K[1, 1]),                                     # sway
        2: (BUOY["mass"] + added[2], K[2, 2] + RHO * G * length * width),          # heave
        5: (BUOY["inertia"][2] + added[5], K[5, 5]),                               # yaw
    }
    for dof, (mass, stiffness) in expected.items():
        mode = int(np.argmax(share[dof]))
        assert share[dof, mode] > 0.85, f"DOF {dof}: no mode dominated by the buoy"
        period = 2 * np.pi * np.sqrt(mass / stiffness)
        assert eq.modes.periods[mode] == pytest.approx(period, rel=0.05), f"DOF {dof}"
        assert eq.modes.periods[mode] >= period * 0.995      # lines add inertia, not stiffness
    assert ex.surge_mode == int(np.argmax(share[0]))


def test_a_static_push_moves_the_buoy_as_its_stiffness_says(ex):
    """A static surge force +-5 kN on the buoy (offsets +-0.18 m): its offset over 2F
    equals the surge entry of the inverse of (mooring stiffness + the buoy's own
    hydrostatic stiffness) within 1 % (the legs' nonlinearity: 2 % at +-20 kN)."""
    from skmoor.run.equilibrium import static_state

    system, eq = ex.model.system, ex.eq
    F = 5e3  # N
    offsets = []
    try:
        for sign in (1.0, -1.0):
            system.body_loads[0] = lambda t, q, qdot, f=sign * F: np.array([f, 0, 0, 0, 0, 0])
            x = static_state(system, eq.x).x
            offsets.append(system.q(x, 0)[0])
    finally:
        system.body_loads[0] = ex.model.network.body("buoy").load
    compliance = np.linalg.inv(ex.stiffness + system.K_bodies[0])[0, 0]
    assert (offsets[0] - offsets[1]) / (2 * F) == pytest.approx(compliance, rel=1e-2)


def test_run_and_files(ex):
    """The 20 s run completes and the outputs, ParaView files and pictures exist; the
    points' VTU series holds the network's 12 points with the clump's mass."""
    import imageio.v3 as iio
    import pyvista as pv

    out = ex.out
    info = json.loads((out / "summary.json").read_text())
    assert info["simulated_time"] == pytest.approx(DURATION) and info["stopped"] is None
    assert info["body_names"] == ["buoy"]
    header = (out / "timeseries.csv").read_text().splitlines()[0].split(",")
    for column in ("buoy.surge", "buoy.heave", "buoy.pitch", "fairlead_tension_leg1.top",
                   "leg1.upper.z"):
        assert column in header
    surge = ex.results.bodies[:, 0, 0]
    assert np.ptp(surge) > 0.5                                   # the load moves the buoy
    assert (out / "results.npz").is_file() and ex.xdmf.with_suffix(".h5").is_file()
    reader = pv.PVDReader(ex.pvd)
    np.testing.assert_allclose(reader.time_values, ex.results.t)
    reader.set_active_time_point(len(reader.time_values) - 1)
    _lines, box, points = reader.read()
    assert box.n_points == 8 and points.n_points == len(POINTS) == 12
    np.testing.assert_allclose(points.points, ex.results.point_positions(-1), atol=1e-9)
    mass = dict(zip(ex.results.point_names, points.point_data["mass"]))
    assert mass["leg1.upper"] == 3000.0 and mass["leg2.upper"] == 0.0
    for name in ("network_static.png", "network_history.png"):
        assert (out / name).stat().st_size > 20_000
    assert iio.imread(out / "network_static.png").shape[:2] == (600, 1600)
    assert len(iio.imread(out / "network.gif", index=None)) == ex.frames > 10


def test_free_points_are_drawn_as_spheres(ex, tmp_path):
    """The renderer draws the six junctions (not the anchors or fairleads) as spheres,
    the 3 t clump twice the size of a bare junction; hiding them changes the picture."""
    import imageio.v3 as iio

    from skmoor.post import render

    st = ex.static
    radii = render.point_radii(st)
    assert [r > 0 for r in radii] == [k == "free" for k in st.meta["point_kinds"]]
    names = list(st.point_names)
    assert radii[names.index("leg1.upper")] == pytest.approx(2 * radii[names.index("leg2.upper")])
    kw = dict(camera="side", zoom=4.0, focus=(20.0, 0.0, -60.0), window_size=(320, 240))
    shown = iio.imread(render.snapshot(st, 0, tmp_path / "a.png", **kw))[..., :3].astype(float)
    hidden = iio.imread(render.snapshot(st, 0, tmp_path / "b.png", point_radius=0, **kw)
                        )[..., :3].astype(float)
    changed = np.abs(shown - hidden).max(axis=-1) > 60
    assert changed.sum() > 30
    assert shown[changed].mean() < hidden[changed].mean()     # dark spheres over the scene
