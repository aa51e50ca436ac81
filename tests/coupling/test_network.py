"""The network model: points, lines and bodies reduced to one System.

Independent numbers: central differences of the residual (the tangents), the analytic
elastic catenary of a whole line (a line cut in two at a massless free junction must hang
as the uncut one), conservation of mass, the box's draft from Eq. 1 in closed form (a hull
mesh must give it), and the rigid-body map of a coupled body."""
import numpy as np
import pytest

import skmoor
from skmoor import Body, MooringLine, Network, Point
from skmoor.bodies.body import RigidBody
from skmoor.lines.catenary import solve_catenary
from skmoor.sea.waves import Current, Sea

CHAIN = skmoor.LineType(EA=5e8, mass=120.0, diameter=0.12, BA=2e5)
ROPE = skmoor.LineType(EA=8e7, mass=20.0, diameter=0.15)


def buoy(name, position, mass=4e4, volume=60.0):
    """A submerged buoy (its buoyancy at the reference point, the CoM 1 m below)."""
    position = np.asarray(position, float)
    rigid = RigidBody(mass, position + [0, 0, -1.0], np.diag([3e5, 3e5, 2e5]),
                      reference_point=position,
                      hydrostatics=skmoor.bodies.body.Hydrostatics.submerged(volume, position, position))
    return Body(name, "dynamic", position, rigid=rigid)


def network_two_bodies(sea=None):
    """Two free buoys, each on two legs, joined by a shared rope; a free clump point with
    drag on one leg; one leg ends on a coupled point."""
    points = [Point("A1", "fixed", [-300.0, 0.0, -150.0]),
              Point("A2", "fixed", [-250.0, -150.0, -150.0]),
              Point("A3", "fixed", [300.0, 0.0, -150.0]),
              Point("C", "coupled", [120.0, 120.0, -20.0]),
              Point("J", "free", [-160.0, 0.0, -95.0], mass=2000.0, volume=0.3, CdA=2.0, Ca=1.0),
              Point("B1a", "body", [-1.0, 0.0, -1.5], body="west"),
              Point("B1b", "body", [1.0, 0.0, -1.5], body="west"),
              Point("B2a", "body", [1.0, 0.0, -1.5], body="east"),
              Point("B2b", "body", [-1.0, 0.5, -1.5], body="east")]
    lines = [MooringLine("leg1", CHAIN, "A1", "J", 160.0, 8),
             MooringLine("leg1top", CHAIN, "J", "B1a", 80.0, 6),
             MooringLine("leg2", CHAIN, "A2", "B1a", 230.0, 8),
             MooringLine("leg3", CHAIN, "A3", "B2a", 250.0, 8),
             MooringLine("tie", CHAIN, "C", "B2b", 120.0, 5),
             MooringLine("shared", ROPE, "B1b", "B2b", 230.0, 10)]
    bodies = [buoy("west", [-100.0, 0.0, -40.0]), buoy("east", [100.0, 0.0, -40.0])]
    return Network(points, lines, bodies, depth=150.0, sea=sea,
                   motion=lambda t: [0.3 * np.sin(t), 0.0, 0.1 * t])


def central_differences(f, x, h=1e-6):
    cols = []
    for k in range(len(x)):
        e = np.zeros_like(x)
        e[k] = h
        cols.append((f(x + e) - f(x - e)) / (2 * h))
    return np.array(cols).T


@pytest.mark.parametrize("layout", ["dense", "sparse"])
def test_network_tangents_are_the_residual_derivatives(layout):
    """K = dR/dx and Kv = dR/dv of a network with two rotated bodies, a shared line, a
    free point with drag in a current and a prescribed point, against central
    differences (a dropped Hessian term, a point column summed twice or the drag's
    velocity sign would fail it)."""
    sea = Sea(150.0, current=Current(0.8, heading_deg=30.0))
    model = skmoor.from_network(network_two_bodies(sea))
    system = model.system
    assert system.nb == 12 and len(system.point_masses) == 1
    rng = np.random.default_rng(7)
    x = 0.02 * rng.standard_normal(system.n)
    x[system.nf + 3: system.nf + 6] = [0.1, -0.05, 0.2]
    x[system.nf + 9:] = [-0.08, 0.12, 0.05]
    v = 0.3 * rng.standard_normal(system.n)
    v[system.nf + 3: system.nf + 6] = [0.05, -0.03, 0.04]  # rotating bodies: J(q) v moves
    v[system.nf + 9:] = [-0.02, 0.06, 0.03]
    t = 0.7
    _R, K, Kv = system.residual(x, v, t, layout=layout)
    dense = (lambda A: A) if layout == "dense" else (lambda A: A.toarray())
    K_fd = central_differences(lambda y: system.residual(y, v, t, tangent=False)[0], x)
    Kv_fd = central_differences(lambda w: system.residual(x, w, t, tangent=False)[0], v)
    scale = np.abs(K_fd).max()
    assert np.abs(dense(K) - K_fd).max() < 1e-6 * scale
    assert np.abs(dense(Kv) - Kv_fd).max() < 1e-6 * np.abs(Kv_fd).max()


def test_mass_is_conserved_through_the_network():
    """The reduced mass matrix carries every line's mass, the point's mass and added mass
    and both bodies' masses: its translational sum in x is the total (a point column
    counted twice or a dropped line end would change it)."""
    network = network_two_bodies()
    model = skmoor.from_network(network)
    system = model.system
    ex = np.zeros(system.n)  # a rigid unit translation in x of everything that moves
    columns = system.dofs.position[model.lines.nodal_dofs[:, 0]]
    ex[columns[columns >= 0]] = 1.0
    for k in range(2):
        ex[system.nf + 6 * k] = 1.0
    lines = sum(ln.line_type.mass * ln.length for ln in network.lines)
    point = 2000.0 + 1025.0 * 0.3 * 1.0
    bodies = 2 * 4e4
    # the ends on fixed and prescribed points do not move: their half-element masses drop
    held = 0.0
    for ln, line in zip(network.lines, model.lines.lines):
        h = np.diff(line.s)
        m = ln.line_type.mass * ln.length / line.length
        for end, first in ((ln.a, True), (ln.b, False)):
            if network.point(end).kind in ("fixed", "coupled"):
                held += 0.5 * m * (h[0] if first else h[-1])
    total = ex @ (system.M @ ex)
    assert total == pytest.approx(lines + point + bodies - held, rel=1e-3)


def test_a_line_cut_at_a_massless_junction_hangs_as_the_whole_line():
    """Anchor -> free massless point -> fixed fairlead: the two pieces hang as the uncut
    line's analytic catenary (end tensions to 0.1 %, the junction on the curve to 0.1 %
    of the span)."""
    lt = skmoor.LineType(EA=1e9, mass=150.0, diameter=0.15)
    anchor, fairlead = np.array([-400.0, 0.0, -100.0]), np.array([0.0, 0.0, -5.0])
    whole = solve_catenary(anchor, fairlead, lt.weight, lt.EA, length=430.0, seabed_z=-100.0)
    points = [Point("anchor", "fixed", anchor), Point("fair", "fixed", fairlead),
              Point("joint", "free", [-250.0, 20.0, -80.0])]  # off the curve on purpose
    network = Network(points, [MooringLine("bottom", lt, "anchor", "joint", 280.0, 112),
                               MooringLine("top", lt, "joint", "fair", 150.0, 60)],
                      depth=100.0, seabed=skmoor.Seabed(100.0, stiffness=3e6 * 0.15,
                                                        damping=0.0))
    model = skmoor.from_network(network)
    st = skmoor.static_results(model)
    assert st.fairlead_tension[0, 1] == pytest.approx(whole.T_fairlead, rel=1e-3)
    assert st.anchor_tension[0, 0] == pytest.approx(whole.H, rel=1e-3)  # laid part: H
    joint = st.point_positions(0)[2]
    on_curve = whole.position(np.array([280.0]))[0]
    assert np.linalg.norm(joint - on_curve) < 1e-3 * 400.0


def test_coupled_body_moves_its_points_rigidly():
    """A coupled body's points follow x + R(attitude + angles) r - R(attitude) r (MoorDyn's
    rotation order), checked with an independent rotation."""
    lt = skmoor.LineType(EA=1e9, mass=150.0, diameter=0.15)
    attitude = np.radians([5.0, -3.0, 30.0])
    points = [Point("anchor", "fixed", [-300.0, 0.0, -100.0]),
              Point("fair", "body", [4.0, 1.0, -2.0], body="ship")]
    y = np.array([1.0, -0.5, 0.2, 0.03, -0.02, 0.1])
    network = Network(points, [MooringLine("leg", lt, "anchor", "fair", 320.0, 20)],
                      [Body("ship", "coupled", [0.0, 0.0, 0.0], attitude)], depth=100.0,
                      motion=lambda t: y)
    model = skmoor.from_network(network)

    def R(a):
        c, s = np.cos(a), np.sin(a)
        rx = np.array([[1, 0, 0], [0, c[0], -s[0]], [0, s[0], c[0]]])
        ry = np.array([[c[1], 0, s[1]], [0, 1, 0], [-s[1], 0, c[1]]])
        rz = np.array([[c[2], -s[2], 0], [s[2], c[2], 0], [0, 0, 1]])
        return rx @ ry @ rz

    r = np.array([4.0, 1.0, -2.0])
    start = R(attitude) @ r
    lines = model.lines
    assert np.allclose(lines.points[lines.fairlead_nodes[0]], start, atol=1e-9)
    u = model.system.full_displacement(np.zeros(model.system.n), 1.0)
    moved = lines.points[lines.fairlead_nodes[0]] + u[lines.nodal_dofs[lines.fairlead_nodes[0]]]
    assert np.allclose(moved, y[:3] + R(attitude + y[3:]) @ r, atol=1e-9)


def test_released_pendulum_swings_from_where_it_is_given():
    """start='given' releases a free mass from its position: it first moves towards the
    bottom of the swing (x decreases), start='equilibrium' leaves it hanging still."""
    lt = skmoor.LineType(EA=1e9, mass=7.854, diameter=0.1, rho_water=1000.0)  # weightless
    network = Network([Point("pivot", "fixed", [0.0, 0.0, 0.0]),
                       Point("bob", "free", [10.0, 0.0, -100.0], mass=1e5)],
                      [MooringLine("rod", lt, "pivot", "bob", 100.5, 10)], depth=500.0,
                      rho=1000.0)
    model = skmoor.from_network(network, settings={"solver": {"scheme": "newmark"}})
    given = skmoor.simulate(model, duration=2.0, dt=0.02, progress=False, start="given")
    x = given.point_positions(-1)[1, 0]
    assert 8.0 < x < 10.0 - 0.5 * 9.81 * (10 / 100.5) * 2.0**2 * 0.5
    still = skmoor.simulate(model, duration=2.0, dt=0.02, progress=False)
    bob = still.point_positions(-1)[1]
    assert abs(bob[0]) < 1e-2 and bob[2] < -100.0  # a swing would be metres


@pytest.mark.parametrize("change, message", [
    (lambda n: n.points.append(Point("lonely", "free", [0, 0, -50])), "free point with no line"),
    (lambda n: n.lines.append(MooringLine("x", CHAIN, "A1", "nowhere", 10.0, 2)),
     "point 'nowhere' is not defined"),
    (lambda n: n.points.append(Point("A1", "fixed", [0, 0, -150])), "'A1' is used more than once"),
])
def test_network_refuses_what_cannot_be_built(change, message):
    network = network_two_bodies()
    change(network)
    with pytest.raises(ValueError, match=message):
        network.__post_init__()


def test_hull_mesh_is_read_for_the_draft(tmp_path):
    """body.hull is read: the box's own mesh gives the box's draft; the same box mesh
    stretched 1.2 times in y gives the draft Eq. 1 gives a 12 m wide box (the lines'
    pull solved with it), not the 10 m box's."""
    pv = pytest.importorskip("pyvista")
    mesh = pv.read(str(skmoor.__path__[0] + "/../meshes/box_hull.stl"))
    base = skmoor.paper_case()
    box = skmoor.model.from_case.equilibrium_draft(base)
    path = tmp_path / "box.stl"
    mesh.save(path)
    hull = skmoor.model.from_case.equilibrium_draft(base.replace("body.hull", str(path)))
    assert hull == pytest.approx(box, abs=1e-9)
    wide = mesh.copy()
    wide.points = wide.points * [1.0, 1.2, 1.0]
    wide.save(tmp_path / "wide.stl")
    draft = skmoor.model.from_case.equilibrium_draft(base.replace("body.hull", str(tmp_path / "wide.stl")))
    wide_box = skmoor.model.from_case.equilibrium_draft(base.replace("body.size", [26.0, 12.0, 5.0]))
    assert draft == pytest.approx(wide_box, abs=1e-9) and abs(draft - box) > 0.05
    missing = base.replace("body.hull", str(tmp_path / "none.stl"))
    with pytest.raises(ValueError, match="body.hull: no such mesh file"):
        skmoor.build(missing)


def test_relaxed_static_solve_reaches_the_networks_equilibrium():
    """Pseudo-transient continuation from the given positions of the two-buoy network
    (where plain Newton wanders): the residual vanishes, the static tangent there is
    positive definite (a stable equilibrium, not a saddle Newton may land on)."""
    model = skmoor.from_network(network_two_bodies())
    system = model.system
    from skmoor.solvers.statics import solve_static

    static = solve_static(system, relax=True, maxiter=300)
    R, K, _ = system.residual(static.x, layout="dense")
    assert np.max(np.abs(R)) < 1e-3
    assert np.linalg.eigvalsh(0.5 * (K + K.T)).min() > 0
