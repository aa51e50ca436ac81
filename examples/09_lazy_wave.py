"""A lazy-wave power cable: the Lozon et al. (2025) Gulf of Mexico 80 m dynamic cable
(the data of CableDyn's examples/lozon_gomex80_power_cable.dat): from the hang-off at
(5, 0, -14) m, 68.114 m of bare cable (D = 0.16 m, 36.70 kg/m), 50 m with buoyancy
modules (D = 0.29 m, 59.53 kg/m: buoyant), 52.101 m of bare cable to the anchor on the
bed at (125, 0, -80) m; EA = 4.69e8 N, EI = 1.99e4 N m2 throughout; 80 m of water
(rho = 1025 kg/m3, g = 9.80665 m/s2), penalty bed kBot = 1e5 Pa/m, cBot = 1e4 Pa s/m.

The three sections are three bending lines joined at two smooth free points (C1: the
joint carries the bending moment). The first guess is the catenary network (EI = 0,
the buoyant section's catenary upside down: the junctions settled where the three
balance), from which the static solve finds the lazy wave directly. Published: hang-off tension 9.32 kN, peak curvature
0.0968 1/m (OrcaFlex 11.6d, Lozon et al. 2025; CableDyn's VALIDATION.md, case L3-5).
Heaved at the hang-off (a "coupled" point), start the motion from rest with
``skmoor.fade_in``: a sinusoid from t = 0 is a velocity jump (docs/bending.md,
tests/test_lazy_wave_dynamics.py).

Run: python examples/09_lazy_wave.py   (prints the mesh convergence of both numbers,
writes docs/images/lazy_wave.png: the shape and the curvature along the arc)
"""
import os
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import skmoor
from skmoor.run import static_state

G, RHO, DEPTH = 9.80665, 1025.0, 80.0
HANG_OFF, ANCHOR = (5.0, 0.0, -14.0), (125.0, 0.0, -80.0)
# (name, outer diameter m, mass kg/m, length m, the deck's segments)
SECTIONS = (("bare_top", 0.16, 36.70, 68.114, 448),
            ("buoyancy", 0.29, 59.53, 50.0, 320),
            ("bare_bottom", 0.16, 36.70, 52.101, 256))
ELEMENTS = int(os.environ.get("SKMOOR_EXAMPLE_ELEMENTS", "1024"))  # the deck's: 1024
ORCAFLEX = {"hang_off_tension": 9.32e3, "peak_curvature": 0.0968}  # N, 1/m
IMAGES = Path(__file__).parents[1] / "docs" / "images"
OUT = Path(os.environ.get("SKMOOR_EXAMPLE_OUT", str(IMAGES)))


def lazy_wave(elements=ELEMENTS) -> skmoor.Network:
    """The cable as a network of three bending lines, ``elements`` in all (shared out
    between the sections as the deck's 448 / 320 / 256)."""
    deck = sum(section[-1] for section in SECTIONS)
    # the junctions' positions: first guesses, which the catenary network settles
    points = [skmoor.Point("hang_off", "fixed", HANG_OFF),
              skmoor.Point("buoyancy_start", "free", (35.0, 0.0, -60.0), smooth=True),
              skmoor.Point("buoyancy_end", "free", (75.0, 0.0, -70.0), smooth=True),
              skmoor.Point("anchor", "fixed", ANCHOR)]
    lines = []
    for k, (name, diameter, mass, length, segments) in enumerate(SECTIONS):
        cable = skmoor.LineType(EA=4.69e8, mass=mass, diameter=diameter, EI=1.99e4,
                                g=G, rho_water=RHO)
        lines.append(skmoor.MooringLine(name, cable, points[k].name, points[k + 1].name,
                                        length, max(2, round(segments * elements / deck))))
    seabed = skmoor.Seabed(DEPTH, stiffness=1e5, damping=1e4, per_diameter=True)
    # a bending cable carries compression, as a beam does (a tension-only law gives the
    # same statics here; docs/bending.md)
    return skmoor.Network(points, lines, depth=DEPTH, rho=RHO, g=G, hydro=False,
                          seabed=seabed, strain_law=skmoor.Engineering(tension_only=False))


def static_cable(elements=ELEMENTS):
    """(model, full displacement u, hang-off tension N, curvature at the element
    mid-points 1/m, their arclength from the hang-off m) of the static lazy wave."""
    model = skmoor.from_network(lazy_wave(elements))
    system, lines = model.system, model.lines
    x = static_state(system).x
    u = system.full_displacement(x)
    _, on_a = system.reactions(x)  # forces of the lines on their A ends
    start = np.cumsum([0.0] + [line.length for line in lines.lines[:-1]])
    s = np.concatenate([start[k] + 0.5 * (line.s[1:] + line.s[:-1]) - line.s[0]
                        for k, line in enumerate(lines.lines)])
    return model, u, float(np.linalg.norm(on_a[0])), lines.curvature(u), s


model, u, hang_off_tension, curvature, arc = static_cable()
peak = int(np.argmax(curvature))
lines = model.lines
shape = lines.points + u[lines.nodal_dofs]

fig = Figure(figsize=(8.0, 6.5), dpi=120, layout="constrained")
top, bottom = fig.subplots(2, 1)
for k, line in enumerate(lines.lines):
    nodes = slice(lines.anchor_nodes[k], lines.fairlead_nodes[k] + 1)
    top.plot(shape[nodes, 0], shape[nodes, 2], lw=2.5 if "buoy" in line.name else 1.5,
             label=line.name)
    cells = lines.line_of_cell == k
    bottom.plot(arc[cells], curvature[cells], lw=1.5, label=line.name)
top.axhline(-DEPTH, color="0.4", lw=1.0)
top.set_xlabel("x [m]")
top.set_ylabel("z [m]")
top.set_aspect("equal")
top.legend(loc="upper right", fontsize="small")
top.set_title(f"Lozon et al. (2025) 80 m lazy-wave cable, {lines.mesh.t.shape[1]} elements: "
              f"hang-off tension {hang_off_tension / 1e3:.3f} kN", fontsize="medium")
bottom.axhline(ORCAFLEX["peak_curvature"], color="k", ls="--", lw=1.0,
               label="OrcaFlex peak 0.0968 1/m")
bottom.plot(arc[peak], curvature[peak], "kx")
bottom.set_xlabel("arclength from the hang-off [m]")
bottom.set_ylabel("curvature [1/m]")
bottom.legend(fontsize="small")
bottom.grid(alpha=0.3)
OUT.mkdir(parents=True, exist_ok=True)
figure = OUT / "lazy_wave.png"
fig.savefig(figure)

if __name__ == "__main__":
    print(f"{'elements':>8} {'hang-off T [kN]':>16} {'peak curvature [1/m]':>21} {'at s [m]':>9}")
    for n in (64, 128, 256, 512, 1024):
        *_, T, kappa, s = static_cable(n)
        print(f"{n:8d} {T / 1e3:16.5f} {kappa.max():21.6f} {s[np.argmax(kappa)]:9.2f}")
    print(f"OrcaFlex (Lozon et al. 2025): {ORCAFLEX['hang_off_tension'] / 1e3:.2f} kN, "
          f"{ORCAFLEX['peak_curvature']} 1/m")
    print("wrote", figure)
