"""A mooring network: a spar buoy (10 m x 10 m x 20 m, 16 m draft, 1585 t) on three
chain-polyester-chain legs 120 deg apart in 160 m of water, a 3 t clump weight at the
upper junction of leg 1 (the case file, explicit tables: examples/network_buoy.toml).

Static equilibrium of the whole network (the free junctions found with the buoy), the
buoy's 6x6 mooring stiffness and the natural periods, then 300 s under a wave-frequency
surge force (400 kN, 10 s period) from static rest; outputs, ParaView files (lines, buoy,
network points), a static picture, an animation and the time histories.

Run: python examples/07_network.py   (writes network-out/, and the pictures into
docs/images/network_static.png and docs/images/network_history.png)
"""
import os
import shutil
from pathlib import Path

import imageio.v3 as iio
import numpy as np

import skmoor
from skmoor.post.export import export
from skmoor.post.plots import plot_body_and_tensions
from skmoor.post.render import animate, snapshot

DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 300.0))  # s
OUT = Path(os.environ.get("SKMOOR_EXAMPLE_OUT", "network-out"))
CASE = Path(__file__).parent / "network_buoy.toml"
IMAGES = Path(__file__).parents[1] / "docs" / "images"
LEGS = ("leg1", "leg2", "leg3")
DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")

model = skmoor.build(CASE)
eq = skmoor.equilibrium(model)
static = skmoor.static_results(model, eq)
stiffness = skmoor.mooring_stiffness(model, eq, body="buoy")  # (6, 6), N/m, N/rad, N m/rad
positions = dict(zip(static.point_names, static.point_positions(0)))

# which body DOF each mode moves: the share of the mode's kinetic energy in each of the
# buoy's six DOFs (the rest is in the lines and the junctions)
system = model.system
body = slice(system.nf, system.nf + 6)
shapes = eq.modes.shapes
energy = shapes * (system.M @ shapes)
share = energy[body] / energy.sum(axis=0)  # (6, nmodes)
surge_mode = int(np.argmax(share[0]))

results = skmoor.simulate(model, duration=DURATION, eq=eq, progress=False)
info = skmoor.write_outputs(results, OUT)
xdmf, pvd = export(results, OUT)

# the static state: the whole network, and the buoy with leg 1 from the side (legs 2
# and 3 are mirror images and coincide), side by side
views = [snapshot(static, 0, OUT / "static_iso.png", window_size=(800, 600)),
         snapshot(static, 0, OUT / "static_side.png", camera="side", zoom=4.0,
                  focus=(20.0, 0.0, -60.0), window_size=(800, 600), colorbar=False)]
static_png = OUT / "network_static.png"
iio.imwrite(static_png, np.hstack([iio.imread(v)[..., :3] for v in views]))
# the first 100 s (the start-up: the buoy surges 3 m and back), one frame per second, the
# buoy, the top chains and the clump weight close up
every = max(1, round(1.0 / float(np.median(np.diff(results.t)))))
frames = animate(results.truncated(int(np.searchsorted(results.t, 100.0, side="right"))),
                 OUT / "network.gif", fps=10, every=every, camera="side", zoom=6.0,
                 focus=(10.0, 0.0, -40.0), window_size=(480, 360), progress=False)
history_png = plot_body_and_tensions(results, OUT / "network_history.png", body="buoy",
                                     lines=[f"{leg}.top" for leg in LEGS])

if __name__ == "__main__":
    print(model.name)
    print("static tensions [kN]   end A (lower)   end B (upper)")
    for name, a, b in zip(static.line_names, static.anchor_tension[0], static.fairlead_tension[0]):
        print(f"  {name:12s} {a / 1e3:12.2f} {b / 1e3:14.2f}")
    print("junctions [m]:")
    for name, kind in zip(static.point_names, static.meta["point_kinds"]):
        if kind == "free":
            print(f"  {name:12s}", np.array2string(positions[name], precision=2,
                                                   suppress_small=True))
    print("buoy offset from its given position [m, rad]:", np.round(static.bodies[0, 0], 4))
    print("mooring stiffness at the buoy's reference point [kN/m, kN/rad, kN m/rad]:")
    print(np.array2string(stiffness / 1e3, precision=1, suppress_small=True))
    print("natural periods [s] (the buoy DOF with most of the mode's kinetic energy, and "
          "its share; the rest is in the lines):")
    for j, period in enumerate(eq.modes.periods):
        k = int(np.argmax(share[:, j]))
        print(f"  {period:7.2f}  {DOFS[k]:5s} {share[k, j]:.0%}")
    buoy = model.network.body("buoy").rigid
    print(f"surge mode {eq.modes.periods[surge_mode]:.2f} s; 2 pi sqrt((m + a11) / K11) = "
          f"{2 * np.pi * np.sqrt((buoy.mass + buoy.added_mass[0, 0]) / stiffness[0, 0]):.2f} s")
    print(f"run: {results.t[-1]:g} s in {results.meta['wall_time']:.1f} s wall, "
          f"stopped: {results.meta['stopped']}, max tension {info['max_tension'] / 1e3:.1f} kN")
    IMAGES.mkdir(parents=True, exist_ok=True)
    for path in (static_png, history_png):
        shutil.copy(path, IMAGES / path.name)
        print("wrote", IMAGES / path.name)
    for path in (xdmf, pvd, OUT / "network.gif", OUT / "summary.json"):
        print("wrote", path)
