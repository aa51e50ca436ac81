"""A single mooring line: static finite-element solve from the unstretched line against
the analytic elastic catenary (Irvine), and the order of convergence in element size.

Run: python examples/01_static_line.py   (prints a table, writes static_line.png)
"""
import numpy as np

import skmoor

steel = skmoor.LineType.steel_rod(diameter=0.1)          # E = 2e11 Pa, 8000 kg/m3
anchor, fairlead = np.array([85.0, 0.0, -100.0]), np.array([0.0, 0.0, -1.0])
exact = skmoor.solve_catenary(anchor, fairlead, steel.weight, steel.EA, sag_ratio=1 / 60)


def unstretched_start(n_elements):
    """The unstretched line (length exact.L) laid on a parabola through both ends."""
    s = np.linspace(0.0, 1.0, 4001)
    chord = anchor + s[:, None] * (fairlead - anchor)

    def shape(depth):
        pts = chord.copy()
        pts[:, 2] -= depth * 4 * s * (1 - s)
        return pts, np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])

    lo, hi = 0.0, 50.0
    for _ in range(80):  # bisection on the parabola's depth for the length
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if shape(mid)[1][-1] < exact.L else (lo, mid)
    pts, arc = shape(lo)
    nodes = np.linspace(0.0, arc[-1], n_elements + 1)
    return np.column_stack([np.interp(nodes, arc, pts[:, k]) for k in range(3)])


def fairlead_tension(n_elements):
    """Fairlead tension (N) of the FE solve with the engineering strain law (Irvine's)."""
    line = skmoor.Line.from_polyline(unstretched_start(n_elements), steel)
    system = skmoor.System(skmoor.LineSet([line], law="engineering"), fairleads="fixed")
    x = skmoor.solve_static(system, pretension=steel.weight * exact.L).x
    return np.linalg.norm(system.reactions(x)[0][0])


elements = [5, 10, 20, 40]
errors = [abs(fairlead_tension(n) - exact.T_fairlead) / exact.T_fairlead for n in elements]
order = np.polyfit(np.log(elements), np.log(errors), 1)[0]

if __name__ == "__main__":
    print(f"analytic fairlead tension {exact.T_fairlead / 1e3:.3f} kN, L = {exact.L:.3f} m")
    for n, e in zip(elements, errors):
        print(f"{n:4d} elements: relative error {e:.2e}")
    print(f"order of convergence: {-order:.2f}")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 4))
    ax.loglog(elements, errors, "o-", label="skmoor FE")
    ax.loglog(elements, errors[0] * (elements[0] / np.array(elements)) ** 2, "k--", label="slope 2")
    ax.set_xlabel("elements")
    ax.set_ylabel("fairlead tension error (relative)")
    ax.legend()
    fig.tight_layout()
    fig.savefig("static_line.png", dpi=120)
