"""Time of one tangent + residual of the cable: scikit-fem forms vs the compiled kernel.

Both evaluate the same physics (tests/fem/test_forms.py holds them equal to 1e-12): the forms
path is ``LineSet.internal_force(u)`` + ``LineSet.tangent_stiffness(u)`` (two scikit-fem
assemblies), the fast path ``CableKernel.force_and_tangent(u)``. The line is the paper's
steel line (analytic catenary, sag ratio 1/60) with n elements, at a random displacement.
Times are the best of several repeats (timeit).

Run: ``python benchmarks/assembly.py``
"""
import timeit

import numpy as np

from skmoor.lines.cable_kernel import CableKernel
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType

ELEMENTS = (11, 100, 1_000, 10_000)


def best_time(call, budget=2.0, repeat=5):
    """Best time of one call, s, with enough calls per repeat to fill ~budget / repeat."""
    timer = timeit.Timer(call)
    once = min(timer.repeat(repeat=2, number=1))
    number = max(1, int(budget / repeat / max(once, 1e-9)))
    return min(timer.repeat(repeat=repeat, number=number)) / number


def main():
    steel = LineType.steel_rod(0.1)
    anchor = np.array([-100.0 / np.tan(np.radians(50.0)), 0.0, -100.0])
    cable = solve_catenary(anchor, [0.0, 0.0, 0.0], steel.weight, steel.EA, sag_ratio=1 / 60)
    print(f"{'elements':>9} {'forms (ms)':>11} {'kernel (ms)':>12} {'ratio':>7}")
    for n in ELEMENTS:
        lines = LineSet([Line.from_catenary(cable, steel, n)])
        kernel = CableKernel(lines)
        u = 1e-3 * np.random.default_rng(0).normal(size=lines.ndofs)
        forms = best_time(lambda: (lines.internal_force(u), lines.tangent_stiffness(u)))
        fast = best_time(lambda: kernel.force_and_tangent(u))
        print(f"{n:>9,} {forms * 1e3:>11.3f} {fast * 1e3:>12.3f} {forms / fast:>7.1f}")


if __name__ == "__main__":
    main()
