"""Write ``box_hull_bem.npz``: Capytaine's coefficients of the paper's box
(``box_hull.stl``, 1 m panels) floating at the paper case's draft in 100 m of water,
waves from 0 deg, omega = 0.05 to 3.0 rad/s every 0.05 rad/s (the validation tests and
examples/08_box_in_jonswap.py read it, so that they need no BEM solve of their own; a
few minutes on one core). No lid: the box's first irregular frequency (the interior
Dirichlet sloshing mode, omega^2 = g k coth(k T), k = pi (1/L^2 + 1/B^2)^0.5) is
3.4 rad/s, above the range.

Run: ``python meshes/make_box_bem.py``
"""
from pathlib import Path

import numpy as np

import skmoor
from skmoor import bem

OMEGA = np.round(np.arange(0.05, 3.0001, 0.05), 10)


def box_coefficients(cache=bem.CACHE):
    model = skmoor.build(skmoor.paper_case())
    centre = model.system.body.reference_point
    return bem.from_mesh(Path(__file__).with_name("box_hull.stl"), OMEGA,
                         offset=centre, reference_point=centre, depth=100.0,
                         rho=1025.0, g=9.81, lid=False, cache=cache)


if __name__ == "__main__":
    hydro = box_coefficients()
    path = Path(__file__).with_name("box_hull_bem.npz")
    hydro.save(path)
    print(f"wrote {path}: {hydro.source}, {len(hydro.omega)} frequencies")
