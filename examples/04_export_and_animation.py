"""Export a run for ParaView and render it off-screen (no display needed).

Writes into paraview-demo/: lines.xdmf + lines.h5 (open the .xdmf in ParaView, apply
"Warp By Vector" on displacement), motion.pvd (moving lines and body), a snapshot PNG,
an MP4 and a GIF, and the first mode shape as a one-period series and GIF.

Run: python examples/04_export_and_animation.py
"""
import os
from pathlib import Path

import skmoor
from skmoor.post.export import export, write_mode_series
from skmoor.post.render import animate, animate_mode, default_scale, snapshot

DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 40.0))
OUT = Path(os.environ.get("SKMOOR_EXAMPLE_OUT", "paraview-demo"))

model = skmoor.build(skmoor.paper_case())
eq = skmoor.equilibrium(model)
results = skmoor.simulate(model, duration=DURATION, eq=eq, progress=False)
xdmf, pvd = export(results, OUT)
scale = default_scale(results)
png = snapshot(results, len(results.t) - 1, OUT / "snapshot.png", scale=scale)
frames = animate(results, OUT / "run.gif", every=max(1, len(results.t) // 40), scale=scale,
                 window_size=(480, 360), progress=False)

# the first mode of the coupled system, drawn on the lines (body DOFs move the fairleads)
system = model.system
shape = system.full_displacement(eq.modes.shapes[:, 0])[model.lines.nodal_dofs]
cells = model.lines.mesh.t.T
mode_pvd = write_mode_series(model.lines.points, cells, shape, eq.modes.periods[0], OUT,
                             name="mode1")
mode_frames = animate_mode(model.lines.points, cells, shape, eq.modes.periods[0],
                           OUT / "mode1.gif", window_size=(480, 360), progress=False)

if __name__ == "__main__":
    for path in (xdmf, pvd, png, OUT / "run.gif", mode_pvd, OUT / "mode1.gif"):
        print("wrote", path)
