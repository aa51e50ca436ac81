"""Lazy-wave power cables: the Lozon et al. (2025) dynamic cables of the Gulf of Mexico
(80 m) and the Gulf of Maine (200 m), with the data of CableDyn's
examples/lozon_gomex80_power_cable.dat and lozon_gomaine200_power_cable.dat. Each runs
from the hang-off at (5, 0, -14) m: bare cable (D = 0.16 m, 36.70 kg/m), a section with
buoyancy modules (buoyant), bare cable to the anchor on the bed; EA = 4.69e8 N,
EI = 1.99e4 N m2 throughout; rho = 1025 kg/m3, g = 9.80665 m/s2, penalty bed
kBot = 1e5 Pa/m, cBot = 1e4 Pa s/m:

- 80 m: 68.114 m bare, 50 m buoyant (D = 0.29 m, 59.53 kg/m), 52.101 m bare to (125, 0, -80) m;
- 200 m: 171.978 m bare, 60 m buoyant (D = 0.30 m, 60.85 kg/m), 121.527 m bare to
  (205, 0, -200) m.

The three sections are three bending lines joined at two smooth free points (C1: the
joint carries the bending moment). The first guess is the catenary network (EI = 0,
the buoyant section's catenary upside down: the junctions settled where the three
balance), from which the static solve finds the lazy wave directly. Published (OrcaFlex
11.6d, Lozon et al. 2025; CableDyn's VALIDATION.md, case L3-5): hang-off tension 9.32 kN
and peak curvature 0.0968 1/m at 80 m, 25.16 kN and 0.0831 1/m at 200 m.
Heaved at the hang-off (a "coupled" point), start the motion from rest with
``skmoor.fade_in``: a sinusoid from t = 0 is a velocity jump (docs/bending.md,
tests/lines/test_lazy_wave_dynamics.py).

Run: python examples/09_lazy_wave.py   (prints the mesh convergence of both numbers and
the touchdown at both sites, writes docs/images/lazy_wave.png: the shapes and the
curvature along the arc)
"""
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import skmoor
from skmoor.run.equilibrium import static_state

G, RHO = 9.80665, 1025.0


@dataclass(frozen=True)
class Site:
    """One cable: water depth (m), hang-off and anchor (m), sections from the hang-off
    (name, outer diameter m, mass kg/m, length m, the deck's segments), first guesses of
    the two junctions (m), OrcaFlex's hang-off tension (N) and peak curvature (1/m)."""
    title: str
    depth: float
    hang_off: tuple
    anchor: tuple
    sections: tuple
    junctions: tuple
    orcaflex: dict


SITES = {
    "80m": Site("Gulf of Mexico, 80 m", 80.0, (5.0, 0.0, -14.0), (125.0, 0.0, -80.0),
                (("bare_top", 0.16, 36.70, 68.114, 448),
                 ("buoyancy", 0.29, 59.53, 50.0, 320),
                 ("bare_bottom", 0.16, 36.70, 52.101, 256)),
                ((35.0, 0.0, -60.0), (75.0, 0.0, -70.0)),
                {"hang_off_tension": 9.32e3, "peak_curvature": 0.0968}),
    "200m": Site("Gulf of Maine, 200 m", 200.0, (5.0, 0.0, -14.0), (205.0, 0.0, -200.0),
                 (("bare_top", 0.16, 36.70, 171.978, 464),
                  ("buoyancy", 0.30, 60.85, 60.0, 160),
                  ("bare_bottom", 0.16, 36.70, 121.527, 328)),
                 ((60.0, 0.0, -170.0), (110.0, 0.0, -170.0)),
                 {"hang_off_tension": 25.16e3, "peak_curvature": 0.0831}),
}
# elements per cable (unset: the decks' 1024 at 80 m, 952 at 200 m)
ELEMENTS = int(os.environ["SKMOOR_EXAMPLE_ELEMENTS"]) if "SKMOOR_EXAMPLE_ELEMENTS" in os.environ \
    else None
# the sites to solve and draw (names of SITES, comma-separated)
RUN = os.environ.get("SKMOOR_EXAMPLE_SITES", ",".join(SITES)).split(",")
if unknown := sorted(set(RUN) - set(SITES)):
    raise ValueError(f"SKMOOR_EXAMPLE_SITES: unknown site(s) {unknown}; the sites are "
                     f"{', '.join(SITES)}")
IMAGES = Path(__file__).parents[1] / "docs" / "images"
OUT = Path(os.environ.get("SKMOOR_EXAMPLE_OUT", str(IMAGES)))


def lazy_wave(site: Site, elements=ELEMENTS) -> skmoor.Network:
    """The cable as a network of three bending lines, ``elements`` in all (shared out
    between the sections as the deck's segments; None: the deck's)."""
    deck = sum(section[-1] for section in site.sections)
    elements = deck if elements is None else elements
    # the junctions' positions: first guesses, which the catenary network settles
    points = [skmoor.Point("hang_off", "fixed", site.hang_off),
              skmoor.Point("buoyancy_start", "free", site.junctions[0], smooth=True),
              skmoor.Point("buoyancy_end", "free", site.junctions[1], smooth=True),
              skmoor.Point("anchor", "fixed", site.anchor)]
    lines = []
    for k, (name, diameter, mass, length, segments) in enumerate(site.sections):
        cable = skmoor.LineType(EA=4.69e8, mass=mass, diameter=diameter, EI=1.99e4,
                                g=G, rho_water=RHO)
        lines.append(skmoor.MooringLine(name, cable, points[k].name, points[k + 1].name,
                                        length, max(2, round(segments * elements / deck))))
    seabed = skmoor.Seabed(site.depth, stiffness=1e5, damping=1e4, per_diameter=True)
    # a bending cable carries compression, as a beam does (a tension-only law gives the
    # same statics here; docs/bending.md)
    return skmoor.Network(points, lines, depth=site.depth, rho=RHO, g=G, hydro=False,
                          seabed=seabed, strain_law=skmoor.Engineering(tension_only=False))


@dataclass
class StaticCable:
    """A solved cable: its model and full displacement u, the hang-off tension (N), the
    curvature at the element mid-points (1/m) and their arclength from the hang-off (m),
    the node positions from the hang-off (n, 3) and the touchdown (arclength, x; m)."""
    model: object
    u: np.ndarray
    hang_off_tension: float
    curvature: np.ndarray
    arc: np.ndarray
    nodes: np.ndarray
    touchdown: tuple


def nodes_along(model, u):
    """(n, 3) node positions of a solved cable from the hang-off, each joint once."""
    lines = model.lines
    shape = lines.points + u[lines.nodal_dofs]
    parts = [shape[a:b + 1] for a, b in zip(lines.anchor_nodes, lines.fairlead_nodes)]
    return np.concatenate([parts[0]] + [p[1:] for p in parts[1:]])


def touchdown(nodes, depth):
    """(arclength m, x m) along the polyline of ``nodes`` (from the hang-off) where it first
    reaches the bed z = -depth (linear between the nodes around it)."""
    k = int(np.flatnonzero(nodes[:, 2] <= -depth)[0])
    a, b = nodes[k - 1], nodes[k]
    share = (a[2] + depth) / (a[2] - b[2])
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(nodes, axis=0), axis=1))])
    return float(arc[k - 1] + share * (arc[k] - arc[k - 1])), float(a[0] + share * (b[0] - a[0]))


def static_cable(site: Site, elements=ELEMENTS) -> StaticCable:
    """The static lazy wave of ``site`` on ``elements``."""
    model = skmoor.from_network(lazy_wave(site, elements))
    system, lines = model.system, model.lines
    x = static_state(system).x
    u = system.full_displacement(x)
    _, on_a = system.reactions(x)  # forces of the lines on their A ends
    start = np.cumsum([0.0] + [line.length for line in lines.lines[:-1]])
    s = np.concatenate([start[k] + 0.5 * (line.s[1:] + line.s[:-1]) - line.s[0]
                        for k, line in enumerate(lines.lines)])
    nodes = nodes_along(model, u)
    return StaticCable(model, u, float(np.linalg.norm(on_a[0])), lines.curvature(u), s,
                       nodes, touchdown(nodes, site.depth))


cables = {name: static_cable(SITES[name]) for name in RUN}

fig = Figure(figsize=(5.5 * len(RUN) + 0.5, 6.5), dpi=120, layout="constrained")
axes = fig.subplots(2, len(RUN), squeeze=False)
for name, (top, bottom) in zip(RUN, axes.T):
    site, cable = SITES[name], cables[name]
    lines = cable.model.lines
    shape = lines.points + cable.u[lines.nodal_dofs]
    for k, line in enumerate(lines.lines):
        nodes = slice(lines.anchor_nodes[k], lines.fairlead_nodes[k] + 1)
        top.plot(shape[nodes, 0], shape[nodes, 2], lw=2.5 if "buoy" in line.name else 1.5,
                 label=line.name)
        cells = lines.line_of_cell == k
        bottom.plot(cable.arc[cells], cable.curvature[cells], lw=1.5, label=line.name)
    top.axhline(-site.depth, color="0.4", lw=1.0)
    top.plot(cable.touchdown[1], -site.depth, "kv", label="touchdown")
    top.set_xlabel("x [m]")
    top.set_ylabel("z [m]")
    top.set_aspect("equal")
    top.legend(loc="upper right", fontsize="small")
    top.set_title(f"{site.title}, {lines.mesh.t.shape[1]} elements: hang-off tension "
                  f"{cable.hang_off_tension / 1e3:.3f} kN", fontsize="medium")
    kappa = site.orcaflex["peak_curvature"]
    bottom.axhline(kappa, color="k", ls="--", lw=1.0, label=f"OrcaFlex peak {kappa} 1/m")
    peak = int(np.argmax(cable.curvature))
    bottom.plot(cable.arc[peak], cable.curvature[peak], "kx")
    bottom.set_xlabel("arclength from the hang-off [m]")
    bottom.set_ylabel("curvature [1/m]")
    bottom.legend(fontsize="small")
    bottom.grid(alpha=0.3)
fig.suptitle("Lozon et al. (2025) lazy-wave power cables", fontsize="medium")
OUT.mkdir(parents=True, exist_ok=True)
figure = OUT / "lazy_wave.png"
fig.savefig(figure)

if __name__ == "__main__":
    for name in RUN:
        site = SITES[name]
        print(site.title)
        print(f"{'elements':>8} {'hang-off T [kN]':>16} {'peak curvature [1/m]':>21} "
              f"{'at s [m]':>9} {'touchdown s, x [m]':>19}")
        deck = sum(section[-1] for section in site.sections)
        for n in (deck // 8, deck // 4, deck // 2, deck):
            c = static_cable(site, n)
            print(f"{n:8d} {c.hang_off_tension / 1e3:16.5f} {c.curvature.max():21.6f} "
                  f"{c.arc[np.argmax(c.curvature)]:9.2f} {c.touchdown[0]:9.2f} "
                  f"{c.touchdown[1]:9.2f}")
        print(f"OrcaFlex (Lozon et al. 2025): {site.orcaflex['hang_off_tension'] / 1e3:.2f} "
              f"kN, {site.orcaflex['peak_curvature']} 1/m")
    print("wrote", figure)
