"""A body's linear potential-flow coefficients: from its hull mesh (Capytaine) or WAMIT files.

:class:`Hydrodynamics` holds, about the body's reference point, for circular frequencies
omega (rad/s): the added mass A(omega) (n, 6, 6) and radiation damping B(omega) (n, 6, 6)
(kg, kg m, kg m2; N s/m, N s, N m s), A at infinite frequency, the excitation force
(Froude-Krylov + diffraction) per metre of wave amplitude for each wave heading (N/m,
N m/m) and the hydrostatic stiffness (N/m, N, N m). Complex amplitudes follow Capytaine:
a quantity is Re(X exp(-i omega t)), and the excitation is that of a wave whose elevation
at the reference point is Re(exp(-i omega t)) (so a crest passes the reference point at
t = 0). Headings are the directions the waves travel, degrees from +x towards +y.

- :func:`from_mesh` solves them with Capytaine (``pip install "skmoor[bem]"``) for the
  hull floated at its draft and keeps them in a cache file keyed by the mesh and the
  settings: the second call with the same mesh and settings reads the file.
- :func:`read_wamit` reads WAMIT's ``.1`` (added mass, damping), ``.3`` (excitation) and
  ``.hst`` (hydrostatics) output, nondimensional per WAMIT's conventions (WAMIT User
  Manual, section 4: A / (rho L^k), B / (rho omega L^k), X / (rho g L^m), C / (rho g L^k);
  time dependence exp(+i omega t), turned here into exp(-i omega t)).
"""
from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

DOFS = ("Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw")  # Capytaine's rigid-body names
CACHE = Path(os.environ.get("SKMOOR_CACHE", Path.home() / ".cache" / "skmoor")) / "bem"
CACHE_VERSION = 1  # raise when what a cached file holds changes


@dataclass
class Hydrodynamics:
    """Frequency-domain coefficients of one body (see the module docstring for units and
    conventions). reference_point: the point (global, m, z up) the 6 DOFs refer to."""

    omega: np.ndarray  # (n,) rad/s, increasing, > 0
    added_mass: np.ndarray  # (n, 6, 6)
    damping: np.ndarray  # (n, 6, 6)
    added_mass_inf: np.ndarray  # (6, 6)
    headings: np.ndarray  # (m,) deg
    excitation: np.ndarray  # (n, m, 6) complex, per m of amplitude
    hydrostatic_stiffness: np.ndarray | None = None  # (6, 6)
    reference_point: np.ndarray = None
    rho: float = 1025.0
    g: float = 9.81
    depth: float = np.inf
    source: str = ""

    def __post_init__(self):
        self.omega = np.asarray(self.omega, float)
        n = len(self.omega)
        if n < 2 or np.any(np.diff(self.omega) <= 0) or self.omega[0] <= 0:
            raise ValueError(f"Hydrodynamics omega: need 2 or more increasing frequencies > 0 "
                             f"(rad/s), got {self.omega}")
        self.headings = np.atleast_1d(np.asarray(self.headings, float))
        self.excitation = np.asarray(self.excitation, complex)
        self.reference_point = (np.zeros(3) if self.reference_point is None
                                else np.asarray(self.reference_point, float))
        for name, shape in (("added_mass", (n, 6, 6)), ("damping", (n, 6, 6)),
                            ("added_mass_inf", (6, 6)),
                            ("excitation", (n, len(self.headings), 6))):
            value = np.asarray(getattr(self, name))
            if value.shape != shape:
                raise ValueError(f"Hydrodynamics {name}: expected shape {shape}, got {value.shape}")
            if not np.all(np.isfinite(value)):
                raise ValueError(f"Hydrodynamics {name}: contains NaN or inf")
            if name != "excitation":
                setattr(self, name, value.astype(float))

    def excitation_force(self, omega, heading_deg=0.0) -> np.ndarray:
        """Excitation per metre of amplitude (k, 6) at frequencies omega (k,) (rad/s) and
        one heading (deg, one of ``headings``): real and imaginary parts interpolated
        linearly in omega. ValueError outside the computed range or headings."""
        omega = np.atleast_1d(np.asarray(omega, float))
        apart = (self.headings - heading_deg + 180.0) % 360.0 - 180.0  # -90 is 270
        j = np.flatnonzero(np.abs(apart) < 1e-6)
        if not len(j):
            raise ValueError(f"Hydrodynamics heading: {heading_deg} deg was not computed "
                             f"(have {self.headings.tolist()})")
        lo, hi = self.omega[0], self.omega[-1]
        if np.any(omega < lo * (1 - 1e-12)) or np.any(omega > hi * (1 + 1e-12)):
            raise ValueError(f"Hydrodynamics excitation: wave frequencies {omega.min():.4g} to "
                             f"{omega.max():.4g} rad/s lie outside the computed range {lo:.4g} "
                             f"to {hi:.4g} rad/s")
        X = self.excitation[:, j[0], :]
        return np.stack([np.interp(omega, self.omega, X[:, i].real)
                         + 1j * np.interp(omega, self.omega, X[:, i].imag) for i in range(6)], -1)

    def coefficients(self, omega):
        """A(omega) and B(omega) (6, 6) at one frequency (rad/s), linear between the
        computed ones."""
        omega = float(omega)
        if not self.omega[0] <= omega <= self.omega[-1]:
            raise ValueError(f"Hydrodynamics: omega {omega:g} rad/s outside the computed range")
        interp = lambda data: np.array([[np.interp(omega, self.omega, data[:, i, k])
                                         for k in range(6)] for i in range(6)])
        return interp(self.added_mass), interp(self.damping)

    def save(self, path):
        """Write to a ``.npz`` file (read back with :meth:`load`)."""
        np.savez(path, **{k: getattr(self, k) for k in _FIELDS},
                 hydrostatic_stiffness=np.full((6, 6), np.nan)
                 if self.hydrostatic_stiffness is None else self.hydrostatic_stiffness)

    @classmethod
    def load(cls, path) -> Hydrodynamics:
        with np.load(path) as data:
            fields = {k: data[k] for k in _FIELDS}
            C = data["hydrostatic_stiffness"]
        fields.update(rho=float(fields["rho"]), g=float(fields["g"]),
                      depth=float(fields["depth"]), source=str(fields["source"]))
        return cls(**fields, hydrostatic_stiffness=None if np.isnan(C).all() else C)


_FIELDS = ("omega", "added_mass", "damping", "added_mass_inf", "headings", "excitation",
           "reference_point", "rho", "g", "depth", "source")


# --------------------------------------------------------------------------- Capytaine

def _mesh_bytes(mesh) -> bytes:
    if isinstance(mesh, (str, Path)):
        return Path(mesh).read_bytes()
    return np.ascontiguousarray(mesh.vertices).tobytes() + np.ascontiguousarray(mesh.faces).tobytes()


def from_mesh(mesh, omega, *, offset=(0.0, 0.0, 0.0), reference_point=(0.0, 0.0, 0.0),
              headings=(0.0,), depth=np.inf, rho=1025.0, g=9.81, lid=True, cache=CACHE,
              n_threads=1) -> Hydrodynamics:
    """Solve the body's radiation and diffraction problems with Capytaine.

    mesh: a closed hull mesh file (any format Capytaine reads, e.g. ``meshes/box_hull.stl``)
    or a Capytaine mesh; offset: the translation (m) that puts it in the global frame, where
    it floats (z = 0 the still water line), as for :func:`skmoor.bodies.body.hull_hydrostatics`;
    reference_point: the point the DOFs refer to (m, global; usually the centre of mass),
    its horizontal position the phase origin of the excitation. omega (rad/s): the frequencies (for the retardation
    kernel, cover B(omega) up to where it has decayed); headings (deg). lid: an internal
    lid at the waterline against irregular frequencies. cache: a folder (None: no cache)
    where the result is kept under a hash of the mesh and every setting.
    """
    omega = np.asarray(omega, float)
    settings = dict(omega=omega.tolist(), offset=np.asarray(offset, float).tolist(),
                    reference_point=np.asarray(reference_point, float).tolist(),
                    headings=np.atleast_1d(np.asarray(headings, float)).tolist(),
                    depth=float(depth), rho=float(rho), g=float(g), lid=bool(lid))
    key = hashlib.sha256(_mesh_bytes(mesh) + json.dumps(dict(settings, version=CACHE_VERSION),
                                                         sort_keys=True).encode())
    path = None if cache is None else Path(cache) / f"{key.hexdigest()[:24]}.npz"
    if path is not None and path.exists():
        return Hydrodynamics.load(path)
    result = _solve_capytaine(mesh, **settings, n_threads=n_threads)
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        partial = path.with_suffix(".part.npz")
        result.save(partial)
        partial.replace(path)
    return result


def _solve_capytaine(mesh, *, omega, offset, reference_point, headings, depth, rho,
                     g, lid, n_threads):
    try:
        import capytaine as cpt
        import xarray as xr
    except ImportError:
        raise ImportError('skmoor.bodies.bem.from_mesh needs Capytaine: pip install "skmoor[bem]"') from None
    cpt.set_logging("ERROR")
    if isinstance(mesh, (str, Path)):
        if not Path(mesh).exists():
            raise ValueError(f"from_mesh mesh: no file {mesh}")
        mesh = cpt.load_mesh(str(mesh))
    centre = np.asarray(reference_point, float)
    # the floating hull in coordinates centred horizontally on the reference point: the
    # excitation phase is then referred to it
    mesh = mesh.translated(np.asarray(offset, float) - [centre[0], centre[1], 0.0])
    local = np.array([0.0, 0.0, centre[2]])
    hull = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=local),
                            center_of_mass=local).immersed_part(water_depth=depth)
    if hull.mesh.nb_faces == 0:
        raise ValueError("from_mesh: no panel of the hull lies under the water line "
                         "(check offset)")
    # an internal lid at the waterline removes the irregular frequencies; A_inf (where
    # the lid has no role) is solved on the hull alone
    waves = (cpt.FloatingBody(mesh=hull.mesh, lid_mesh=hull.mesh.generate_lid(z=-1e-2 * _draft(hull)),
                              dofs=hull.dofs, center_of_mass=local) if lid else hull)
    omegas = np.asarray(omega, float)
    if np.any(~np.isfinite(omegas)) or np.any(omegas <= 0):
        raise ValueError(f"from_mesh omega: need finite frequencies > 0 rad/s, got {omegas}")
    solver = cpt.BEMSolver()
    common = dict(radiating_dof=list(DOFS), water_depth=[depth], rho=[rho], g=[g])
    data = solver.fill_dataset(xr.Dataset(coords=dict(omega=omegas, wave_direction=np.radians(
        headings), **common)), waves, n_threads=n_threads, progress_bar=False)
    infinite = solver.fill_dataset(xr.Dataset(coords=dict(omega=[np.inf], **common)), hull,
                                   n_threads=n_threads, progress_bar=False)
    order = dict(influenced_dof=list(DOFS), radiating_dof=list(DOFS))
    A = data.added_mass.sel(**order).transpose("omega", "influenced_dof", "radiating_dof")
    B = data.radiation_damping.sel(**order).transpose("omega", "influenced_dof", "radiating_dof")
    X = data.excitation_force.sel(influenced_dof=list(DOFS)).transpose(
        "omega", "wave_direction", "influenced_dof")
    A_inf = infinite.added_mass.sel(**order).isel(omega=0).values
    C = np.asarray(hull.compute_hydrostatic_stiffness(rho=rho, g=g)
                   .sel(influenced_dof=list(DOFS), radiating_dof=list(DOFS)).values)
    return Hydrodynamics(omegas, A.values, B.values, A_inf, np.asarray(headings), X.values,
                         C, centre, rho, g, depth,
                         f"Capytaine {cpt.__version__}, {hull.mesh.nb_faces} panels")


def _draft(body):
    return float(-body.mesh.vertices[:, 2].min())


# --------------------------------------------------------------------------- WAMIT

def _k(i, j):
    """WAMIT's length exponent for A_ij, B_ij, C_ij: 3, 4 or 5 with 0-3 / 3-6 DOFs."""
    return 3 + (i >= 3) + (j >= 3)


def _table(path, columns, name):
    path = Path(path)
    if not path.exists():
        raise ValueError(f"read_wamit: no file {path}")
    rows = []
    for number, line in enumerate(path.read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            values = [float(x) for x in line.replace("D", "E").split()]
        except ValueError:
            raise ValueError(f"{path}:{number}: not a WAMIT {name} row: {line.strip()!r}") from None
        if len(values) not in columns:
            raise ValueError(f"{path}:{number}: a WAMIT {name} row has {sorted(columns)} "
                             f"numbers, this one {len(values)}")
        rows.append(values + [np.nan] * (max(columns) - len(values)))
    if not rows:
        raise ValueError(f"{path}: no data")
    return np.array(rows)


def read_wamit(root, *, rho=1025.0, g=9.81, length=1.0, depth=np.inf,
               reference_point=(0.0, 0.0, 0.0)) -> Hydrodynamics:
    """Coefficients from WAMIT output ``root.1``, ``root.3`` and (if present) ``root.hst``
    (root: the path without the extension), made dimensional with rho (kg/m3), g (m/s2)
    and WAMIT's unit length ``length`` (ULEN, m). PER = 0 rows (infinite frequency) give
    A(inf); PER = -1 rows (zero frequency) are skipped; the other periods (s) become the
    frequencies. The ``.1`` and ``.3`` files must hold the same periods."""
    root = str(root)
    radiation = _table(root + ".1", {4, 5}, "added-mass (.1)")
    exciting = _table(root + ".3", {7}, "excitation (.3)")
    periods = np.unique(radiation[radiation[:, 0] > 0, 0])
    omega = 2 * np.pi / periods[::-1]

    def at(T, name):  # the frequency index of a period, as printed
        n = int(np.argmin(np.abs(periods[::-1] - T)))
        if not np.isclose(periods[::-1][n], T, rtol=1e-5):
            raise ValueError(f"{root}{name}: period {T} s is not one of the .1 file's")
        return n
    A, B = np.zeros((len(omega), 6, 6)), np.zeros((len(omega), 6, 6))
    A_inf = np.full((6, 6), np.nan)
    for T, i, j, a, b in radiation:
        i, j = int(i) - 1, int(j) - 1
        if not (0 <= i < 6 and 0 <= j < 6):
            raise ValueError(f"{root}.1: DOF indices {i + 1}, {j + 1} beyond a rigid body's 6")
        scale = rho * length ** _k(i, j)
        if T == 0:
            A_inf[i, j] = a * scale
        elif T > 0:
            A[at(T, '.1'), i, j] = a * scale
            B[at(T, '.1'), i, j] = b * scale * (2 * np.pi / T)
    if np.isnan(A_inf).all():
        raise ValueError(f"{root}.1: no PER = 0 rows (the infinite-frequency added mass), "
                         "which Cummins' equation needs")
    A_inf = np.nan_to_num(A_inf)
    headings = np.unique(exciting[exciting[:, 0] > 0, 1])
    X = np.zeros((len(omega), len(headings), 6), complex)
    for T, beta, i, _, _, re, im in exciting[exciting[:, 0] > 0]:
        i = int(i) - 1
        scale = rho * g * length ** (2 + (i >= 3))
        X[at(T, '.3'), int(np.searchsorted(headings, beta)), i] = np.conj(re + 1j * im) * scale
    C = None
    if Path(root + ".hst").exists():
        C = np.zeros((6, 6))
        for i, j, c in _table(root + ".hst", {3}, "hydrostatics (.hst)"):
            i, j = int(i) - 1, int(j) - 1
            C[i, j] = c * rho * g * length ** (_k(i, j) - 1)
    return Hydrodynamics(omega, A, B, A_inf, headings, X, C, np.asarray(reference_point, float),
                         rho, g, depth, f"WAMIT {root}")
