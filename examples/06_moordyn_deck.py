"""A MoorDyn v2 deck in skmoor: the 50 m chain of the set MoorDyn validates against
OrcaFlex, its fairlead heaved 2 m with a 10 s period, with the sea bed, Morison drag and
added mass the deck asks for. With MoorDyn installed (pip install moordyn) the same deck
runs in MoorDyn too and both fairlead tensions are plotted.

Run: python examples/06_moordyn_deck.py   (writes chain_heave.png)
"""
import os
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import skmoor  # noqa: E402
from skmoor.model.from_deck import heave_motion

DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 40.0))  # s
OUT = Path(os.environ.get("SKMOOR_EXAMPLE_OUT", "."))
DECK = Path(__file__).parent / "decks" / "chain_50m.dat"
AMPLITUDE, PERIOD = 2.0, 10.0  # m, s

deck = skmoor.read_deck(DECK)
motion, velocity = heave_motion(deck, AMPLITUDE, PERIOD)  # faded in over one period
results = skmoor.simulate(skmoor.build(deck, motion=motion), duration=DURATION,
                          dt=0.05, output_interval=0.05, progress=False)
tension = results.fairlead_tension[:, 0]


def moordyn_tension():
    """MoorDyn's fairlead tension on the same deck (s, N), or None without MoorDyn."""
    try:
        import moordyn
    except ImportError:
        return None
    step = 0.01  # s between MoorDyn Step() calls; it sub-steps at the deck's dtM
    with tempfile.TemporaryDirectory() as work:
        path = skmoor.write_deck(deck, Path(work) / "chain.dat")
        md = moordyn.Create(str(path))
        moordyn.Init(md, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])  # the fairlead sits at the origin
        t, force = [], []
        for k in range(int(round(DURATION / step))):
            f = moordyn.Step(md, list(motion(k * step)), list(velocity(k * step)), k * step, step)
            t.append((k + 1) * step)
            force.append(np.linalg.norm(f))
        moordyn.Close(md)
    return np.array(t), np.array(force)


peer = moordyn_tension()
fig, ax = plt.subplots(figsize=(8, 4))
ax.plot(results.t, tension / 1e3, label="skmoor (implicit, dt = 50 ms)")
if peer is not None:
    ax.plot(peer[0], peer[1] / 1e3, "--", label="MoorDyn v2 (explicit, dtM = 1 ms)")
ax.set(xlabel="t [s]", ylabel="fairlead tension [kN]",
       title=f"{DECK.name}: fairlead heave {AMPLITUDE:g} m, period {PERIOD:g} s")
ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=2, frameon=False)
fig.tight_layout()
fig.savefig(OUT / "chain_heave.png", dpi=110)

if __name__ == "__main__":
    print(f"static fairlead tension {tension[0] / 1e3:.1f} kN (OrcaFlex: 991.6 kN)")
    print(f"tension range over the last period {np.ptp(tension[results.t >= DURATION - PERIOD]) / 1e3:.1f} kN")
    if peer is not None:
        late = results.t >= 2 * PERIOD
        diff = tension[late] - np.interp(results.t[late], *peer)
        print(f"max |skmoor - MoorDyn| after 2 periods: {np.abs(diff).max() / 1e3:.1f} kN "
              f"({np.abs(diff).max() / np.ptp(peer[1][peer[0] >= 2 * PERIOD]):.1%} of the range)")
    print(f"wrote {OUT / 'chain_heave.png'}")
