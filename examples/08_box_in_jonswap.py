"""The paper's box on its four lines in a JONSWAP sea (Hs 2 m, Tp 8 s, head waves).

The body's wave loads come from potential flow (Capytaine's coefficients of
meshes/box_hull.stl, in meshes/box_hull_bem.npz: meshes/make_box_bem.py writes them, or
``skmoor.bodies.bem.from_mesh`` computes and caches them), through Cummins' equation in the
same implicit step as the lines. Shown: body motions, fairlead tension statistics and
spectra, and an animation with the free surface; the surge, heave and pitch records
against the linear frequency-domain response of the whole linearized network to the same
wave components.

Run: python examples/08_box_in_jonswap.py [duration_s]   (default 150 s; 3600 for an hour)
Writes into box-in-jonswap/: motions.png, tension_spectra.png, run.gif.
"""
import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import skmoor
from skmoor.post.render import animate

DURATION = float(sys.argv[1]) if len(sys.argv) > 1 and __name__ == "__main__" else float(
    os.environ.get("SKMOOR_EXAMPLE_DURATION", "150"))
OUT = Path(os.environ.get("SKMOOR_EXAMPLE_OUT", "box-in-jonswap"))
DT, RAMP = 0.1, 20.0  # s
OUT.mkdir(parents=True, exist_ok=True)

hydro = skmoor.Hydrodynamics.load(Path(__file__).parents[1] / "meshes" / "box_hull_bem.npz")
# the wave components inside the computed frequencies (0.05-3 rad/s): 0.02-0.45 Hz
wave = skmoor.JonswapWave(Hs=2.0, Tp=8.0, depth=100.0, seed=1, n_components=200,
                          f_range=(0.02, 0.45))
sea = skmoor.Sea(depth=100.0, waves=[wave])
model = skmoor.build(skmoor.paper_case())
model.system.body_load = None  # the paper's sine off: the sea drives the box
flow = model.add(skmoor.PotentialFlow(hydro, sea, body="body", ramp=RAMP))
eq = skmoor.equilibrium(model)
results = skmoor.simulate(model, duration=DURATION, dt=DT, output_interval=DT, eq=eq,
                          progress=__name__ == "__main__")
t, q = results.t, results.body

# the linear frequency-domain response of the same linearized network, component by
# component: (-w^2 M - i w C + K) X = F_exc on the body (lines with their inertia)
system = model.system
_, K, Kv = system.residual(eq.x, layout="dense")
C = eq.C.toarray() + (0.0 if Kv is None else Kv)
body = slice(system.nf, system.nf + 6)
X = np.zeros((len(wave.omega), 6), complex)
for j, (w, a, phi) in enumerate(zip(wave.omega, wave.a, wave.phi)):
    A, B = hydro.coefficients(w)
    Z = -w**2 * system.M.toarray() - 1j * w * C + K
    Z[body, body] += -w**2 * (A - flow.added_mass_inf) - 1j * w * B
    load = np.zeros(system.n, complex)
    load[body] = a * np.exp(1j * phi) * hydro.excitation_force(w)[0]
    X[j] = np.linalg.solve(Z, load)[body]
linear = (X.T[:, :, None] * np.exp(-1j * wave.omega[None, :, None] * t[None, None, :])).sum(1).real.T
settled = t >= min(RAMP + 60.0, 0.6 * DURATION)  # after the fade-in and its transient
dofs = {"surge (m)": 0, "heave (m)": 2, "pitch (deg)": 4}
unit = {name: np.degrees(1.0) if "deg" in name else 1.0 for name in dofs}
std_time = {name: unit[name] * np.std(q[settled, k]) for name, k in dofs.items()}
std_linear = {name: unit[name] * np.std(linear[settled, k]) for name, k in dofs.items()}
correlation = {name: np.corrcoef(q[settled, k], linear[settled, k])[0, 1]
               for name, k in dofs.items()}

tension = results.fairlead_tension  # (nt, 4) N
stats = {name: {"mean_kN": float(np.mean(tension[settled, i]) / 1e3),
                "std_kN": float(np.std(tension[settled, i]) / 1e3),
                "max_kN": float(np.max(tension[settled, i]) / 1e3)}
         for i, name in enumerate(results.line_names)}

fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
eta = sea.elevation(system.bodies[0].reference_point[:2], t)
for ax, (name, k) in zip(axes, dofs.items()):
    ax.plot(t, unit[name] * q[:, k], label="time domain (Cummins)")
    ax.plot(t, unit[name] * linear[:, k], "--", label="linear frequency domain")
    ax.set_ylabel(name)
axes[1].plot(t, eta, color="0.7", lw=0.8, label="wave at the CoM (m)")
axes[0].legend(loc="upper right", fontsize=8)
axes[1].legend(loc="upper right", fontsize=8)
axes[-1].set_xlabel("t (s)")
fig.tight_layout()
fig.savefig(OUT / "motions.png", dpi=110)

fig, ax = plt.subplots(figsize=(7, 4))
frequency = np.fft.rfftfreq(settled.sum(), DT)
for i, name in enumerate(results.line_names):
    series = tension[settled, i] - tension[settled, i].mean()
    ax.semilogy(frequency[1:], (np.abs(np.fft.rfft(series)) ** 2 * 2 * DT / settled.sum())[1:],
                label=name)
ax.set_xlim(0, 0.5)
ax.set_xlabel("f (Hz)")
ax.set_ylabel("fairlead tension PSD (N$^2$/Hz)")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(OUT / "tension_spectra.png", dpi=110)
plt.close("all")

frames = animate(results, OUT / "run.gif", every=max(1, len(t) // 20), window_size=(480, 360),
                 progress=False, surface=sea.elevation)  # the same sea's free surface

if __name__ == "__main__":
    for name in dofs:
        print(f"{name}: std {std_time[name]:.4g} (time domain), "
              f"{std_linear[name]:.4g} (linear), correlation {correlation[name]:.3f}")
    for name, s in stats.items():
        print(f"{name}: mean {s['mean_kN']:.1f} kN, std {s['std_kN']:.2f} kN, "
              f"max {s['max_kN']:.1f} kN")
    print("wrote", OUT / "motions.png", OUT / "tension_spectra.png", OUT / "run.gif")
