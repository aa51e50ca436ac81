"""Mooring lines as one scikit-fem model: a ``MeshLine1`` in s, a vector P1 basis (cables)
or a vector Hermite basis (lines with bending stiffness EI > 0, see :mod:`skmoor.lines.bending`).

A :class:`Line` is a reference (static) state: node arclengths s (m), node positions
X (m), and the reference fields X'(s) (unit tangent) and T(s) (tension, N). It is built
from the analytic catenary (:func:`Line.from_catenary`) or from a polyline
(:func:`Line.from_polyline`, :func:`read_line_mesh`). A :class:`LineSet` puts several
lines on one mesh (each on its own stretch of s, with a gap between them) so that one
assembly covers them all.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from skfem import (
    Basis,
    ElementLineHermite,
    ElementLineP1,
    ElementVector,
    MeshLine1,
    asm,
)

from ..numerics.validation import check_finite, check_positive
from . import bending, laws
from . import cable_forms as forms
from .fatigue_curves import curve as fatigue_curve
from .user_law import UserLaw, law_tension

RHO_WATER = 1025.0
G = 9.81
LAWS = laws.LAWS  # the strain laws' shorthand names


@dataclass
class LineType:
    """Cable properties (per unit unstretched length).

    EA: axial stiffness, N. mass: mass per length, kg/m. diameter: volume-equivalent
    diameter, m. weight: submerged weight per length, N/m (default: (mass - rho_w A) g).
    Cd_n, Cd_t, Ca_n, Ca_t: normal / tangential drag and added-mass coefficients (used by
    the hydrodynamic terms, not by the paper's model). BA: axial internal damping, N s
    (MoorDyn's BA: the tension gains BA times the strain rate; 0 in the paper's model).
    law: the strain law (:mod:`skmoor.lines.laws`: a Law or 'paper' / 'engineering'; None: the
    LineSet's). With a :class:`~skmoor.lines.laws.Curve`, EA may be None: the curve's last
    secant (MoorDyn's EA of a curve), which stands for the law where one number is needed.
    EI: bending stiffness, N m2 (MoorDyn's EI; 0: a cable on P1 elements, > 0: the line
    goes on the C1 Hermite element with the bending form, :mod:`skmoor.lines.bending`).
    Cl, viv_dF, viv_cF: the cross-flow VIV lift coefficient and the synchronization
    range and centre (MoorDyn's Cl, dF, cF; Cl = 0: no VIV, see :mod:`skmoor.sea.viv`).
    MBL: minimum breaking load, N (None: unknown; the strength check then reports no
    safety factor). MBR: the allowable (minimum) bend radius, m, of a bending line.
    fatigue_curve: the T-N or S-N curve of the line's fatigue, a name in
    :data:`skmoor.lines.fatigue_curves.CURVES` (None: no fatigue unless one is given
    when the damage is computed). d_nom: the nominal diameter, m, whose section
    pi d_nom^2 / 4 turns a tension range into the curves' stress range (default: the
    diameter; a chain's volume-equivalent diameter is about 1.8 times its nominal one).
    """

    EA: float | None
    mass: float
    diameter: float
    weight: float | None = None
    Cd_n: float = 0.0
    Cd_t: float = 0.0
    Ca_n: float = 0.0
    Ca_t: float = 0.0
    BA: float = 0.0
    rho_water: float = RHO_WATER
    g: float = G
    law: object = None
    EI: float = 0.0
    Cl: float = 0.0
    viv_dF: float = 0.08
    viv_cF: float = 0.18
    MBL: float | None = None
    MBR: float | None = None
    fatigue_curve: str | None = None
    d_nom: float | None = None

    def __post_init__(self):
        for name in ("MBL", "MBR", "d_nom"):
            if getattr(self, name) is not None:
                check_positive(f"LineType.{name}", getattr(self, name))
        if self.fatigue_curve is not None:
            fatigue_curve(self.fatigue_curve, "LineType.fatigue_curve")
        if self.law is not None:
            self.law = laws.as_law(self.law, "LineType.law")
        if self.EA is None:
            self.EA = None if self.law is None else self.law.nominal_EA(None)
            if self.EA is None:
                raise ValueError("LineType.EA: give the axial stiffness (N), or a Curve law "
                                 "whose last secant stands for it")
        for name in ("EA", "mass", "diameter"):
            check_positive(f"LineType.{name}", getattr(self, name))
        for name in ("Cd_n", "Cd_t", "Ca_n", "Ca_t", "BA", "rho_water", "g", "EI", "Cl",
                     "viv_dF", "viv_cF"):
            check_finite(f"LineType.{name}", getattr(self, name))
        if self.BA < 0:
            raise ValueError(f"LineType.BA: internal damping must be >= 0 N s, got {self.BA}")
        if self.EI < 0:
            raise ValueError(f"LineType.EI: bending stiffness must be >= 0 N m2, got {self.EI}")
        if self.Cl < 0:
            raise ValueError(f"LineType.Cl: the VIV lift coefficient must be >= 0, got {self.Cl}")
        if self.weight is None:
            self.weight = (self.mass - self.rho_water * self.area) * self.g
        check_finite("LineType.weight", self.weight)

    @property
    def area(self) -> float:
        """Cross-section area, m2."""
        return np.pi * self.diameter**2 / 4

    @classmethod
    def steel_rod(cls, diameter: float, E: float = 2e11, density: float = 8000.0, **kw):
        """A solid round steel cable (the paper's Table 1), E in Pa, density in kg/m3."""
        check_positive("LineType.steel_rod.diameter", diameter)
        area = np.pi * diameter**2 / 4
        return cls(EA=E * area, mass=density * area, diameter=diameter, **kw)


@dataclass
class Line:
    """One line's reference state.

    s: (n,) node arclengths of the reference configuration from the anchor, m.
    X: (n, 3) node positions, m. The first node is the anchor end, the last the fairlead.
    tangent(s) -> (..., 3) and tension(s) -> (...) give the reference fields at any s.
    stretch(s): reference stretch (1 + T/EA for an elastic catenary, 1 for a stress-free
    polyline); mass and weight per unit reference length are divided by it.
    end_tangents: unit tangents (along increasing s) that replace the reference's at end
    A and B (None: keep it), e.g. the direction a clamped bending line leaves its end in.
    """

    name: str
    line_type: LineType
    s: np.ndarray
    X: np.ndarray
    tangent: object
    tension: object
    stretch: object = field(default=lambda s: np.ones_like(s))
    end_tangents: tuple = (None, None)

    def __post_init__(self):
        self.end_tangents = tuple(None if t is None else _unit(f"Line {self.name!r} end tangent", t)
                                  for t in self.end_tangents)
        if len(self.end_tangents) != 2:
            raise ValueError(f"Line {self.name!r} end_tangents: need two entries (A, B)")
        self.s = np.asarray(self.s, float)
        self.X = np.asarray(self.X, float)
        check_finite(f"Line {self.name!r} s", self.s)
        check_finite(f"Line {self.name!r} X", self.X)
        if self.s.ndim != 1 or self.X.shape != (len(self.s), 3) or len(self.s) < 2:
            raise ValueError(f"Line {self.name!r}: need n >= 2 arclengths s and (n, 3) "
                             f"positions X, got s {self.s.shape} and X {self.X.shape}")
        if np.any(np.diff(self.s) <= 0):
            raise ValueError(f"Line {self.name!r} s: element lengths must be positive "
                             "(two nodes at the same place?)")

    @property
    def n_elements(self) -> int:
        return len(self.s) - 1

    @property
    def length(self) -> float:
        """Reference (static) length, m."""
        return float(self.s[-1] - self.s[0])

    @classmethod
    def from_catenary(cls, catenary, line_type: LineType, n_elements: int, name="line"):
        """Reference state = the analytic elastic catenary, elements of equal unstretched
        length (as MoorDyn's segments)."""
        if int(n_elements) < 1:
            raise ValueError(f"Line {name!r} n_elements: must be >= 1, got {n_elements}")
        s0 = np.linspace(0.0, catenary.L, int(n_elements) + 1)
        unstretched = _inverse_monotone(catenary.stretched_arclength, catenary.L)

        def tangent(s):
            return catenary.tangent(unstretched(s).ravel()).reshape(np.shape(s) + (3,))

        def tension(s):
            return catenary.tension(unstretched(s).ravel()).reshape(np.shape(s))

        def stretch(s):
            return 1.0 + catenary.strain(tension(s))

        return cls(name, line_type, catenary.stretched_arclength(s0), catenary.position(s0),
                   tangent, tension, stretch)

    def reversed(self) -> Line:
        """The same reference state numbered from the other end (tangent flipped)."""
        total = self.s[-1] + self.s[0]
        tangent, tension, stretch = self.tangent, self.tension, self.stretch
        a, b = (None if t is None else -t for t in self.end_tangents)
        return Line(self.name, self.line_type, total - self.s[::-1], self.X[::-1].copy(),
                    lambda s: -tangent(total - np.asarray(s)),
                    lambda s: tension(total - np.asarray(s)),
                    lambda s: stretch(total - np.asarray(s)), (b, a))

    @classmethod
    def from_polyline(cls, points, line_type: LineType, name="line", tension=0.0):
        """Reference state = a polyline (anchor first), straight between nodes, with a
        uniform reference tension (N; 0 for a stress-free line)."""
        X = np.asarray(points, float)
        check_finite(f"Line {name!r} points", X)
        check_finite(f"Line {name!r} tension", tension)
        if X.ndim != 2 or X.shape[1] != 3 or len(X) < 2:
            raise ValueError(f"Line {name!r} points: need an (n >= 2, 3) array, got {X.shape}")
        chords = np.diff(X, axis=0)
        lengths = np.linalg.norm(chords, axis=1)
        if np.any(lengths <= 0):
            raise ValueError(f"Line {name!r} points: node {int(np.argmin(lengths)) + 1} "
                             "repeats the previous one (zero-length element)")
        s = np.concatenate([[0.0], np.cumsum(lengths)])
        directions = chords / lengths[:, None]

        def element(sq):
            return np.clip(np.searchsorted(s, sq) - 1, 0, len(lengths) - 1)

        return cls(name, line_type, s, X, lambda sq: directions[element(sq)],
                   lambda sq: np.full(np.shape(sq), float(tension)))


def _unit(name, vector):
    """A direction as a unit 3-vector (ValueError naming it when it is not one)."""
    v = np.asarray(vector, float)
    check_finite(name, v)
    if v.shape != (3,) or np.linalg.norm(v) == 0:
        raise ValueError(f"{name}: need a non-zero 3-vector, got {vector!r}")
    return v / np.linalg.norm(v)


def _inverse_monotone(f, upper):
    """x(y) for an increasing function y = f(x) with f' ~ 1, by Newton from x = y."""

    def inverse(y):
        y = np.asarray(y, float)
        x = np.clip(y.copy(), 0.0, upper)
        for _ in range(50):
            h = 1e-7 * max(upper, 1.0)
            slope = (f(np.minimum(x + h, upper + h)) - f(x)) / h
            step = (f(x) - y) / slope
            x = x - step
            if np.all(np.abs(step) < 1e-13 * max(upper, 1.0)):
                break
        return x

    return inverse


class LineSet:
    """All lines on one ``MeshLine1`` with one vector basis: P1 (3 DOFs per node) for
    cables, or Hermite (6 per node: the displacement and its d/ds) for bending lines.

    Attributes: ``mesh``, ``basis`` (Gauss quadrature), ``cable_basis`` (for the
    displacement-dependent cable terms: the element mid-points on P1, see forms.py; the
    Gauss points on Hermite), ``points`` (nnodes, 3) reference positions, ``anchor_nodes``
    and ``fairlead_nodes`` (one per line), ``line_of_cell``, and the reference fields at
    quadrature points (``Xp``, ``T``, ``EA``, ``m``, ``w``, ``BA`` and the strain law's
    parameters, see :mod:`skmoor.lines.cable_forms`; on Hermite also ``EI`` and ``Xpp``, the
    reference curvature vector X'', see :mod:`skmoor.lines.bending`).

    law: the strain law of the lines whose LineType has none (a :class:`skmoor.lines.laws.Law`
    or 'paper' / 'engineering'); ``laws`` lists each line's. element: 'p1', 'hermite' or
    None (Hermite when a line type has EI > 0; one element for the whole set, so the
    cables of a set with a bending line are Hermite lines with EI = 0).
    """

    GAP = 1.0  # m of s between two lines on the shared mesh
    ELEMENTS = ("p1", "hermite")

    def __init__(self, lines, law="paper", intorder: int = 4, element=None):
        lines = list(lines)
        if not lines:
            raise ValueError("LineSet: no lines")
        if element is None:
            element = "hermite" if any(ln.line_type.EI > 0 for ln in lines) else "p1"
        if element not in self.ELEMENTS:
            raise ValueError(f"LineSet element: {element!r} is not one of {self.ELEMENTS}")
        self.element = element
        self.hermite = element == "hermite"
        self.law = laws.as_law(law, "LineSet law")
        self.law_name = self.law.name
        self.lines = lines
        self.laws = [line.line_type.law or self.law for line in lines]
        self.has_user_law = any(isinstance(law, UserLaw) for law in self.laws)
        self._static = False  # the static laws in force (StaticDynamic lines)
        self.static_mode = False  # a static solve is on (its terms may act differently)
        self._pushing = 0.0  # compression let through (a static solve's continuation)
        self._mean = None  # per-element (T_mean, e_mean) of StaticDynamic lines
        self.creep = None  # the creep laws' term (skmoor.lines.creep.CreepTerm), if any
        offsets, coords, cells, node0 = [], [], [], 0
        start = 0.0
        for line in lines:
            offsets.append(start - line.s[0])
            coords.append(line.s + offsets[-1])
            n = len(line.s)
            cells.append(np.stack([np.arange(node0, node0 + n - 1), np.arange(node0 + 1, node0 + n)]))
            node0 += n
            start = coords[-1][-1] + self.GAP
        self.mesh = MeshLine1(np.concatenate(coords)[None, :], np.concatenate(cells, axis=1))
        if self.hermite:  # 4 Gauss points: the cubic's mass and bending forms exactly
            self.basis = Basis(self.mesh, self._element(), intorder=max(intorder, 7))
            self.cable_basis = self.basis
        else:
            self.basis = Basis(self.mesh, self._element(), intorder=intorder)
            self.cable_basis = Basis(self.mesh, self._element(),
                                     quadrature=(np.array([[0.5]]), np.array([1.0])))
        self.points = np.concatenate([line.X for line in lines])
        sizes = [len(line.s) for line in lines]
        first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        self.anchor_nodes = first
        self.fairlead_nodes = first + np.array(sizes) - 1
        self.line_of_cell = np.repeat(np.arange(len(lines)), [n - 1 for n in sizes])
        self._offsets = np.array(offsets)
        if self.hermite and self.has_static_laws:
            named = ", ".join(repr(line.name) for line, law in zip(lines, self.laws)
                              if _static_dynamic(law))
            raise ValueError(f"LineSet: line {named}: a static-dynamic law (two EA values, "
                             "a creep law, a UserLaw about the static state) is not "
                             "available on bending (EI > 0) line sets; give the line EI 0 "
                             "or a single EA")
        for line, law in zip(lines, self.laws):  # a state of the reference's: at its EA
            if (isinstance(law, UserLaw) and law.reference and law.start is not None
                    and law.balanced):
                law.check_reference(line.line_type.EA, f" on line {line.name!r}")
        self.reference_dofs = self._reference_dofs()
        self.fields = self._fields(self.basis)
        self.cable_fields = (self.fields if self.cable_basis is self.basis
                             else self._fields(self.cable_basis))
        self._reference = asm(forms.reference_force, self.basis, **self.fields)
        self._nodal_basis = self._nodal_fields = self._bandwidth = None
        self._kernels = []  # CableKernels reading the law fields (refreshed with them)
        self._element_lengths = np.diff(self.mesh.p[0, self.mesh.t], axis=0)[0]

    def _element(self):
        return ElementVector(ElementLineHermite() if self.hermite else ElementLineP1(), dim=3)

    def _reference_dofs(self):
        """The reference geometry as a DOF vector of the basis: node positions (m) and, on
        Hermite, the unit tangents at the nodes (the mean of the two sides at a kink)."""
        X = np.zeros(self.ndofs)
        X[self.nodal_dofs] = self.points
        if self.hermite:
            tangents = []
            for line in self.lines:
                step = 1e-9 * line.length
                before = line.tangent(np.maximum(line.s - step, line.s[0]))
                after = line.tangent(np.minimum(line.s + step, line.s[-1]))
                mean = before + after
                mean /= np.linalg.norm(mean, axis=1, keepdims=True)
                for node, given in zip((0, -1), line.end_tangents):
                    if given is not None:
                        mean[node] = given
                tangents.append(mean)
            X[self.slope_dofs] = np.concatenate(tangents)
        return X

    @property
    def nodal_basis(self):
        """The line basis with nodal quadrature (the element ends, weights h/2): for
        point-wise terms such as sea-bed contact, one decision per node as in a lumped
        model."""
        if self._nodal_basis is None:
            self._nodal_basis = Basis(self.mesh, self._element(),
                                      quadrature=(np.array([[0.0, 1.0]]), np.array([0.5, 0.5])))
        return self._nodal_basis

    @property
    def nodal_fields(self) -> dict:
        """Reference fields at the nodal quadrature points (see :attr:`nodal_basis`)."""
        if self._nodal_fields is None:
            self._nodal_fields = self._fields(self.nodal_basis)
        return self._nodal_fields

    @property
    def ndofs(self) -> int:
        return self.basis.N

    @property
    def nodal_dofs(self) -> np.ndarray:
        """(nnodes, 3) global DOF numbers of each node's x, y, z displacement."""
        return self.basis.nodal_dofs[:3].T

    @property
    def slope_dofs(self):
        """(nnodes, 3) global DOF numbers of each node's d/ds of the displacement (the
        tangent's change, -) on Hermite; None on P1."""
        return self.basis.nodal_dofs[3:].T if self.hermite else None

    @property
    def element_dofs(self) -> np.ndarray:
        """(nel, nloc) global DOFs of each element in the order of the element blocks:
        P1 [node i x, y, z, node j x, y, z]; Hermite [node i x, y, z, x', y', z', node j
        ...] (scikit-fem's local order)."""
        if self.hermite:
            return self.basis.element_dofs.T
        t = self.mesh.t
        return np.concatenate([self.nodal_dofs[t[0]], self.nodal_dofs[t[1]]], axis=1)

    @property
    def block_size(self) -> int:
        """DOFs per element block: 6 on P1, 12 on Hermite."""
        return 12 if self.hermite else 6

    def _fields(self, basis):
        """Reference fields at the quadrature points of ``basis``: Xp, T, EA, m, w, BA and
        the strain law's parameters (see :mod:`skmoor.lines.cable_forms`)."""
        s_global = basis.mapping.F(basis.X)[0]  # (nel, nqp)
        Xp = np.empty((3,) + s_global.shape)
        T, EA, m, w, BA, e_ref = (np.empty(s_global.shape) for _ in range(6))
        for k, line in enumerate(self.lines):
            cells = self.line_of_cell == k
            s = s_global[cells] - self._offsets[k]
            Xp[:, cells] = np.moveaxis(line.tangent(s), -1, 0)
            T[cells] = line.tension(s)
            stretch = line.stretch(s)
            EA[cells] = line.line_type.EA
            BA[cells] = line.line_type.BA
            m[cells] = line.line_type.mass / stretch
            w[cells] = line.line_type.weight / stretch
            e_ref[cells] = self.laws[k].static_strain(np.maximum(T[cells], 0.0),
                                                      line.line_type.EA)
        out = dict(Xp=Xp, T=T, EA=EA, m=m, w=w, BA=BA,
                   **self._law_fields(T, EA, e_ref, s_global.shape))
        if self.hermite:  # the bending form's fields (skmoor.lines.bending)
            EI = np.array([line.line_type.EI for line in self.lines])[self.line_of_cell]
            out["EI"] = np.repeat(EI[:, None], s_global.shape[1], axis=1)
            geometry = basis.interpolate(self.reference_dofs)
            out["Xp"] = geometry.grad[:, 0]  # X' of the C1 reference geometry, as in r'
            out["Xpp"] = geometry.hess[:, 0, 0]
        return out

    def _law_fields(self, T, EA, e_ref, shape):
        """The strain laws' parameters at points of shape (nel, nqp) (forms' fields)."""
        out = {name: np.empty(shape) for name in laws.PARAMETERS}
        hinges = []
        for k, law in enumerate(self.laws):
            cells = self.line_of_cell == k
            T_k, e_k = T[cells], e_ref[cells]
            if self._mean is not None and isinstance(law, laws.StaticDynamic):
                T_k = np.broadcast_to(self._mean[0][cells][:, None], T_k.shape)
                e_k = np.broadcast_to(self._mean[1][cells][:, None], T_k.shape)
            p, h = law.parameters(EA[cells], T_k, e_k, static=self._static)
            p["e_ref"] = e_ref[cells]
            for name in laws.PARAMETERS:
                out[name][cells] = p[name]
            hinges.append(h)
        out["tension_only"] *= 1.0 - self._pushing
        m = max((len(h[0]) for h in hinges if h is not None), default=0)
        knots, coef = np.full((m,) + shape, np.inf), np.zeros((m,) + shape)
        for k, h in enumerate(hinges):
            if h is not None and len(h[0]):
                cells = self.line_of_cell == k
                knots[:len(h[0]), cells] = h[0][:, None, None]
                coef[:len(h[0]), cells] = h[1][:, None, None]
        out.update(knots=knots, coef=coef)
        return out

    @property
    def user_law_cells(self) -> np.ndarray:
        """(nel,) True on the elements whose axial force a :class:`UserLaw`'s term carries
        (not those of a law about the static state while the static laws are in force:
        the kernel carries them with their static law)."""
        return np.isin(self.line_of_cell, [
            k for k, law in enumerate(self.laws) if isinstance(law, UserLaw)
            and not (self._static and law.reference == "static")])

    @property
    def tension_only(self) -> bool:
        """True when a line's law carries no compression."""
        return any(law.tension_only for law in self.laws)

    def carry_compression(self, fraction: float):
        """Let the tension-only lines carry ``fraction`` of their compression (1: they push
        like the laws with tension_only=False, 0: the laws as they are); the fields and
        the kernel's parameters change in place (a static solve's continuation)."""
        fraction = float(fraction)
        if not 0.0 <= fraction <= 1.0:
            raise ValueError(f"carry_compression fraction: must lie in [0, 1], got {fraction}")
        if fraction != self._pushing:
            self._pushing = fraction
            self._refresh_laws()

    # --- the static and dynamic laws (StaticDynamic lines)
    @property
    def has_static_laws(self) -> bool:
        """True when a line's law differs between statics and dynamics (StaticDynamic, a
        UserLaw about the static state)."""
        return any(_static_dynamic(law) for law in self.laws)

    def use_static_laws(self, static: bool):
        """Switch the lines' laws to their static (True) or dynamic (False) form; the
        fields and the kernel's parameters change in place. ``static_mode`` follows it
        (the sea bed's static friction acts while it is on)."""
        self.static_mode = bool(static)
        if self.has_static_laws and bool(static) != self._static:
            self._static = bool(static)
            self._refresh_laws()

    def set_static_state(self, u):
        """Take the static state at displacement u (m) as the mean state of the
        StaticDynamic lines: their dynamic tension is T_mean + EA_d (e - e_mean) with
        (T_mean, e_mean) each element's static tension and engineering strain there."""
        if not self.has_static_laws:
            return
        static, self._static = self._static, True
        self._refresh_laws()
        T, _ = self.element_tension_and_strain(u)
        lam = np.linalg.norm(self.cable_fields["Xp"][:, :, 0] + self.element_slopes(u), axis=0)
        e = (1.0 + self.cable_fields["e_ref"][:, 0]) * lam - 1.0
        self._mean = (T, e)
        self._static = static
        self._refresh_laws()

    def _refresh_laws(self):
        for fields in (self.fields, self.cable_fields, self._nodal_fields):
            if fields is not None:
                shape = fields["T"].shape
                new = self._law_fields(fields["T"], fields["EA"], fields["e_ref"], shape)
                for name, value in new.items():
                    if fields[name].shape == value.shape:
                        fields[name][...] = value
                    else:
                        fields[name] = value
        for kernel in self._kernels:
            kernel.refresh_laws()

    # --- assembly through the forms (the definition; see kernels.py for the fast path)
    def internal_force(self, u):
        """Eq. 9 = Eq. 11 + reference part (+ the bending form on Hermite): internal
        force vector, N."""
        f = asm(forms.cable_force, self.cable_basis, u=u, **self.cable_fields) + self._reference
        if self.hermite:
            f += asm(bending.bending_force, self.basis, u=u, **self.fields)
        return f

    @property
    def damped(self) -> bool:
        """True when any line has axial internal damping (BA > 0)."""
        return any(line.line_type.BA > 0 for line in self.lines)

    def damping_force(self, u, ud):
        """Axial internal damping force int BA eps_dot r'.du' ds (N) at displacement u and
        velocity ud."""
        return asm(forms.axial_damping, self.cable_basis, u=u, du=ud, **self.cable_fields)

    def reference_force(self):
        """The reference part of Eq. 9, int T X'.du' ds, as nodal forces, N."""
        return self._reference.copy()

    def tangent_stiffness(self, u):
        """Eq. 17 (+ the bending tangent on Hermite): d(internal_force)/du, sparse, N/m."""
        K = asm(forms.cable_tangent, self.cable_basis, u=u, **self.cable_fields)
        if self.hermite:
            K = K + asm(bending.bending_tangent, self.basis, u=u, **self.fields)
        return K

    def unit_tension_stiffness(self):
        """Geometric stiffness of a 1 N tension in every line (sparse, 1/m)."""
        return asm(forms.unit_tension_stiffness, self.basis)

    def weight_load(self):
        """Eq. 8: submerged weight as nodal loads, N."""
        return asm(forms.weight, self.basis, **self.fields)

    def mass_matrix(self, lumped: bool = True):
        """Eq. 20 (lumped, default) or Eq. 19 (consistent), sparse, kg. On Hermite always
        Eq. 19 (row sums would give the slope DOFs no mass)."""
        M = asm(forms.mass, self.basis, **self.fields)
        if lumped and not self.hermite:  # Eq. 20 as the row sums of Eq. 19: keeps the line's mass exactly
            return sp.diags(np.asarray(M.sum(axis=1)).ravel()).tocsr()
        return M

    def element_tension(self, u, ud=None):
        """(nel,) tension at each element's mid-point, N (with the velocity ud, the
        internal damping's BA x strain rate included, as MoorDyn reports it)."""
        return self.element_tension_and_strain(u, ud)[0]

    def element_strain(self, u):
        """(nel,) strain of Eq. 3 at each element's mid-point, -."""
        return forms.strain(self.cable_fields["Xp"][:, :, 0], self.element_slopes(u))

    def element_tension_and_strain(self, u, ud=None):
        """(nel,) tension (N) and strain of Eq. 3 (-) at each element's mid-point. Given
        the velocity ud (m/s), the tension includes the internal damping BA deps/dt
        (MoorDyn's reported T + BA x strain rate); without it, the elastic tension."""
        if self._kernels or self.hermite:  # the compiled copy of the forms below
            kernel = self._bending_kernel() if self.hermite else self._kernels[0]
            tension, strain = kernel.element_tension_and_strain(u, ud)
        else:
            f, up = self.cable_fields, self.element_slopes(u)
            Xp = f["Xp"][:, :, 0]
            point = {name: value[..., 0] for name, value in f.items() if name != "Xp"}
            rate = None if ud is None else forms.dot(Xp + up, self.element_slopes(ud))
            tension, strain = forms.tension(Xp, up, point, rate), forms.strain(Xp, up)
        if self.has_user_law:  # their N - T
            tension = tension + law_tension(self, u, ud)
        if self.creep is not None:  # the creep laws' N - T_mean
            tension = tension + self.creep.tension_less_mean(u, ud)
        return tension, strain

    def curvature(self, u):
        """(nel,) curvature |r' x r''| / |r'|^3 of the deformed line at each element's
        mid-point, 1/m (zeros on P1, whose lines have no curvature inside an element)."""
        if not self.hermite:
            return np.zeros(len(self.line_of_cell))
        return self._bending_kernel().curvature(u)

    def bending_moment(self, u):
        """(nel,) bending moment EI kappa at each element's mid-point, N m."""
        if not self.hermite:
            return np.zeros(len(self.line_of_cell))
        return self.fields["EI"][:, 0] * self.curvature(u)

    def _bending_kernel(self):
        for kernel in self._kernels:
            if isinstance(kernel, bending.HermiteKernel):
                return kernel
        return bending.HermiteKernel(self)

    def element_slopes(self, u):
        """(3, nel) u' on each element (constant for P1; at the mid-point on Hermite)."""
        weights, dofs = self.midpoint_slope()
        return np.einsum("eb,ebc->ce", weights, u[dofs])

    def midpoint_slope(self):
        """(weights (nel, nb), dofs (nel, nb, 3) int64): d/ds of a field at each element's
        mid-point, sum_b weights[e, b] u[dofs[e, b]] (1/m on values; P1: the nodes' values,
        nb = 2; Hermite: the nodes' values and slopes, nb = 4)."""
        if "_midpoint_slope" not in self.__dict__:
            if self.hermite:
                _, dN, _ = bending.hermite_shapes(np.array([0.5]), self.element_lengths)
                weights, dofs = dN[:, 0], self.element_dofs.reshape(-1, 4, 3)
            else:
                h, t = self.element_lengths, self.mesh.t
                weights = np.stack([-1.0 / h, 1.0 / h], axis=1)
                dofs = np.stack([self.nodal_dofs[t[0]], self.nodal_dofs[t[1]]], axis=1)
            self.__dict__["_midpoint_slope"] = (np.ascontiguousarray(weights, float),
                                                np.ascontiguousarray(dofs, np.int64))
        return self.__dict__["_midpoint_slope"]

    def midpoint_fields(self):
        """The reference fields at each element's mid-point, (nel,) each (Xp (3, nel))."""
        if not self.hermite:  # the cable's points are the mid-points
            return {name: value[..., 0] for name, value in self.cable_fields.items()}
        if "_midpoint_fields" not in self.__dict__:
            middle = Basis(self.mesh, self.basis.elem,
                           quadrature=(np.array([[0.5]]), np.array([1.0])))
            self.__dict__["_midpoint_fields"] = {
                name: value[..., 0] for name, value in self._fields(middle).items()}
        return self.__dict__["_midpoint_fields"]

    @property
    def bandwidth(self) -> int:
        """Half-bandwidth of the line matrices (5 for one P1 line, node-major DOFs)."""
        if self._bandwidth is None:
            edofs = self.element_dofs
            self._bandwidth = int(np.max(edofs.max(axis=1) - edofs.min(axis=1)))
        return self._bandwidth

    @property
    def element_lengths(self) -> np.ndarray:
        """(nel,) element lengths in s, m."""
        return self._element_lengths


def read_line_mesh(path, line_type: LineType, name=None, tension=0.0) -> Line:
    """Read a polyline (gmsh ``.msh``, ``.vtu``, ...) with meshio as a stress-free Line.

    The line cells must form one unbroken chain; its end with the lower z is the anchor.
    """
    import meshio

    path = Path(path)
    mesh = meshio.read(path)
    segments = [c.data for c in mesh.cells if c.type == "line"]
    if not segments:
        types = sorted({c.type for c in mesh.cells})
        raise ValueError(f"{path.name}: no line cells in the mesh (found {types or 'none'})")
    order = _chain(np.concatenate(segments), path.name)
    points = np.zeros((len(order), 3))
    points[:, : mesh.points.shape[1]] = mesh.points[order]
    if points[0, 2] > points[-1, 2]:
        points = points[::-1]
    return Line.from_polyline(points, line_type, name=name or path.stem, tension=tension)


def _chain(segments, source):
    """Node order of an unbroken chain of 2-node segments."""
    neighbours = {}
    for a, b in segments:
        neighbours.setdefault(int(a), []).append(int(b))
        neighbours.setdefault(int(b), []).append(int(a))
    ends = [n for n, nb in neighbours.items() if len(nb) == 1]
    if len(ends) != 2 or any(len(nb) > 2 for nb in neighbours.values()):
        raise ValueError(f"{source}: the line cells do not form one unbroken chain "
                         f"({len(ends)} free ends, a chain has 2)")
    order, previous = [ends[0]], None
    while len(order) < len(neighbours):
        nxt = [n for n in neighbours[order[-1]] if n != previous]
        previous = order[-1]
        order.append(nxt[0])
    if len(order) != len(segments) + 1:
        raise ValueError(f"{source}: the line cells do not form one unbroken chain (a loop?)")
    return np.array(order)


def write_line_mesh(line: Line, path) -> Path:
    """Write a line's reference polyline with meshio (format from the suffix; ``.msh`` is
    gmsh 2.2, binary, since meshio reads ASCII gmsh with point data back wrongly)."""
    import meshio

    path = Path(path)
    n = len(line.s)
    cells = [("line", np.stack([np.arange(n - 1), np.arange(1, n)], axis=1))]
    if path.suffix == ".msh":  # meshio would pick the ANSYS format for .msh
        tags = {"gmsh:physical": [np.ones(n - 1, int)], "gmsh:geometrical": [np.ones(n - 1, int)]}
        meshio.write(path, meshio.Mesh(line.X, cells, point_data={"s": line.s}, cell_data=tags),
                     file_format="gmsh22", binary=True)
    else:
        meshio.write(path, meshio.Mesh(line.X, cells, point_data={"s": line.s}))
    return path


def _static_dynamic(law) -> bool:
    """Whether a law acts about the static state in time (its static law in statics)."""
    return (isinstance(law, laws.StaticDynamic)
            or (isinstance(law, UserLaw) and law.reference == "static"))
