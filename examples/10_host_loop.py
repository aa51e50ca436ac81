"""skmoor inside a host: a floating body integrated in Python, its mooring stepped
through MoorDyn's interface. The same loop runs on MoorDyn by changing one import
(``import moordyn``); here it runs on skmoor and, when MoorDyn is installed, on MoorDyn
too, and the fairlead tensions are compared.

The body (5e6 kg, a heave spring of 1e6 N/m) hangs on a chain in 200 m of water
(decks/buoy_chain.dat: its fairlead is the deck's coupled point); a 10 s force of 2 MN
pushes it in surge and heave. Each coupling step of 0.05 s the host passes the fairlead's
position and velocity to Step and integrates its body with the force Step returns.
Half-way the host saves the mooring's state (SaveState), runs on, goes back (LoadState)
and runs the second half again: the same tensions.

Run: python examples/10_host_loop.py
"""
import os
from pathlib import Path

import numpy as np

from skmoor import moordyn  # a host written for MoorDyn: `import moordyn` on MoorDyn

DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 20.0))  # s
DECK = Path(__file__).parent / "decks" / "buoy_chain.dat"
DT = 0.05  # s, the coupling step
MASS, K_HEAVE, FORCE, PERIOD = 5e6, 1e6, np.array([2e6, 0.0, 2e6]), 10.0


def host(lib, md, t0, x, v, f0, steps):
    """The host's loop: (t, x, v, fairlead tensions) after ``steps`` coupling steps."""
    line, start, t, tension = lib.GetLine(md, 1), np.array([0.0, 0.0, -10.0]), t0, []
    for _ in range(steps):
        f = np.asarray(lib.Step(md, x, v, t, DT), float)  # the mooring's force at t + DT
        load = (f - f0 + min(t / PERIOD, 1.0) * FORCE * np.sin(2 * np.pi * t / PERIOD)
                - np.array([0.0, 0.0, K_HEAVE]) * (x - start))
        v = v + DT * load / MASS  # symplectic Euler, as many hosts step
        x = x + DT * v
        t += DT
        tension.append(lib.GetLineFairTen(line))
    return t, x, v, np.array(tension)


def run(lib, checkpoint=False, deck=DECK):
    md = lib.Create(str(deck))
    x, v = np.array([0.0, 0.0, -10.0]), np.zeros(3)
    lib.Init(md, x, v)
    f0 = np.asarray(lib.GetPointForce(lib.GetPoint(md, 2)), float)  # the static pull
    static = lib.GetLineFairTen(lib.GetLine(md, 1))
    half = int(round(DURATION / DT)) // 2
    t, x, v, first = host(lib, md, 0.0, x, v, f0, half)
    saved = lib.SaveState(md) if checkpoint else None
    _, _, _, second = host(lib, md, t, x, v, f0, half)
    again = None
    if checkpoint:
        lib.LoadState(md, saved)
        again = host(lib, md, t, x, v, f0, half)[3]
    lib.Close(md)
    return static, np.concatenate([first, second]), second, again


static, tension, second, again = run(moordyn, checkpoint=True)
print(f"skmoor: static fairlead tension {static / 1e3:.1f} kN, swing "
      f"{np.ptp(tension) / 1e3:.1f} kN over {DURATION:g} s")
print(f"  the second half again from the checkpoint: max |difference| "
      f"{np.max(np.abs(again - second)):.3g} N")
try:
    import moordyn as moordyn_itself
except ImportError:
    moordyn_itself = None
if moordyn_itself is not None:
    here = os.getcwd()
    import tempfile

    os.chdir(tempfile.mkdtemp())  # MoorDyn writes its outputs next to its deck: a copy here
    try:
        copy = Path.cwd() / DECK.name
        copy.write_text(DECK.read_text())
        static_md, tension_md, _, _ = run(moordyn_itself, deck=copy)
    finally:
        os.chdir(here)
    swing = np.max(np.abs((tension - static) - (tension_md - static_md))) / np.ptp(tension_md)
    print(f"MoorDyn: static {static_md / 1e3:.1f} kN; the swings differ by {swing:.2%} of "
          f"MoorDyn's range (one implicit step per coupling step: substeps=5 in "
          f"moordyn.Create brings it to 0.5 %)")
