"""Lines through the free surface: no buoyancy and no drag on the dry part of a line.

skmoor's line forms take a line as submerged: its weight per length is the submerged
weight (m - rho A) g (:class:`~skmoor.lines.line.LineType`) and the Morison drag acts all along
it (:mod:`skmoor.sea.hydro`). MoorDyn v2 gives each node the buoyancy and drag of its wetted
length only (source/Line.cpp, ``Line::getStateDeriv`` and ``calcSubSeg``). This term
takes back, on the part of a line above the free surface z = eta(x, y, t), the buoyancy
rho g A and the drag, with the dry fraction of a section linear in the height of its
centre over one diameter d:

    dry(z) = clip(1/2 + (z - eta) / d, 0, 1)

(MoorDyn: the wetted share of each segment from its end heights). The added mass stays
on the dry part (a constant matrix in skmoor, :func:`skmoor.sea.hydro.added_mass_matrix`),
and so does the fluid inertia of waves (their kinematics are held at z = 0 above the
mean surface, :mod:`skmoor.sea.waves`). The surface elevation eta is the sea's
(:meth:`skmoor.sea.waves.Sea.elevation`) at the displaced nodes, interpolated along the
elements.
"""
from __future__ import annotations

import numpy as np
from skfem import BilinearForm, CellBasis, LinearForm, asm

from ..fem import ops
from ..fem.terms import LineForm, _blocks, _local_order, _raw
from .hydro import (
    coefficients,
    morison_drag,
    morison_drag_rate,
    morison_drag_stiffness,
    nodal_water,
    water_arrays,
    water_lowers,
)

_drag = _raw(morison_drag)
_drag_stiffness = _raw(morison_drag_stiffness)
_drag_rate = _raw(morison_drag_rate)


def _dry(w):
    """(dry fraction, its d/dz in 1/m) at the quadrature points: dry = clip(1/2 + (z -
    eta) / d, 0, 1), z the height of the displaced line, eta the surface's."""
    height = ops.value(w.X)[2] + ops.value(w.u)[2] - ops.value(w.eta)[2]
    ratio = height / w.diameter
    inside = (ratio > -0.5) & (ratio < 0.5)
    return ops.clip(0.5 + ratio, 0.0, 1.0), inside / w.diameter


@LinearForm
def dry_buoyancy(v, w):
    # int dry(z) rho g A e_z . du ds: the buoyancy taken back
    dry, _ = _dry(w)
    return dry * w.buoyancy * ops.value(v)[2]


@BilinearForm
def dry_buoyancy_stiffness(du, v, w):
    # d/du: int dry'(z) du_z rho g A v_z ds
    _, slope = _dry(w)
    return slope * ops.value(du)[2] * w.buoyancy * ops.value(v)[2]


@LinearForm
def dry_drag(v, w):
    # -int dry(z) drag(du) ds: the drag taken back
    dry, _ = _dry(w)
    return -dry * _drag(v, w)


@BilinearForm
def dry_drag_stiffness(du, v, w):
    # d/du: -int [dry'(z) du_z drag(v) + dry d(drag(v))/du] ds
    dry, slope = _dry(w)
    return -(slope * ops.value(du)[2] * _drag(v, w) + dry * _drag_stiffness(du, v, w))


@BilinearForm
def dry_drag_damping(dv, v, w):
    # d/d(udot): -int dry d(drag(v))/d(udot) ds
    dry, _ = _dry(w)
    return -dry * _drag_rate(dv, v, w)


@LinearForm
def dry_part(v, w):
    # int dry(z) [rho g A e_z . du - drag(du)] ds: the whole term (its compiled path)
    return _raw(dry_buoyancy)(v, w) + _raw(dry_drag)(v, w)


class SurfaceTerm(LineForm):
    """The dry part of the lines (see the module docstring) as a line term, evaluated on
    the elements with a Gauss point less than half a diameter under the surface only
    (the term is exactly zero on the others: a mooring's fairlead on the surface costs a
    check of the nodes' heights). On path 'auto' the buoyancy part is summed in NumPy
    and the drag part assembled by scikit-fem, both on those elements; on 'compiled' or
    'fd' the LineForm of ``dry_part`` runs on all. sea: a :class:`skmoor.sea.waves.Sea` or
    None (still water, eta = 0); drag: take back the drag too (False where the lines
    have no Morison terms); the buoyancy rho g A from each line's LineType (rho_water,
    g, area)."""

    def __init__(self, lines, sea=None, *, drag=True, path="auto"):
        c = coefficients(lines)

        def per_cell(name):  # (nel, 1)
            return np.array([getattr(ln.line_type, name) for ln in lines.lines])[
                lines.line_of_cell][:, None]

        per_reference = lines.fields["m"] / per_cell("mass")  # 1 / stretch
        shape = lines.fields["m"].shape
        buoyancy = per_cell("rho_water") * per_cell("g") * per_cell("area") * per_reference
        fields = dict(X=lines.reference_dofs.copy(), drag_n=c["drag_n"] * drag,
                      drag_t=c["drag_t"] * drag, buoyancy=buoyancy,
                      diameter=np.broadcast_to(per_cell("diameter"), shape).copy())
        hand = path in ("auto", "assembly")  # then add_to does the work (LineForm's check)
        super().__init__(dry_part, stiffness=dry_buoyancy_stiffness if hand else None,
                         fields=fields, path=path, lines=lines, name="dry_part")
        self.drag = bool(drag) and bool(np.any(c["drag_n"]) or np.any(c["drag_t"]))
        self.sea = sea
        self._flat = sea is None or not (sea.waves or sea.fields)  # eta = 0
        xi = lines.basis.X[0]
        self._phi = np.stack([1.0 - xi, xi])  # P1 shape functions at the Gauss points
        self._half = 0.5 * per_cell("diameter")  # (nel, 1), m
        self.z_reference = lines.points[:, 2].copy()  # the nodes' reference heights, m
        self.z_dofs = lines.nodal_dofs[:, 2].copy()  # their z DOFs
        steps = np.diff(self.z_dofs)
        self._z_view = (slice(self.z_dofs[0], self.z_dofs[-1] + 1, steps[0])
                        if len(steps) and np.all(steps == steps[0]) else self.z_dofs)
        self.deepest_reach = -float(self._half.max())  # m: a node below stays wet
        self._cells_basis = None
        self._nel = lines.mesh.t.shape[1]
        self._test_z = np.stack([np.asarray(f[0])[2] for f in lines.basis.basis])  # (nloc, nel, nqp)
        self._order = _local_order(lines, lines.basis)

    why_python = "a free surface moved by a water field of a kind the compiled kernels lack"

    def lowered(self):
        """'surface' on a flat surface, Airy waves and fields the compiled kernels evaluate
        (:func:`~skmoor.sea.hydro.water_lowers`): the compiled step hands a step to the
        Python step when a node comes within half a diameter of it."""
        return "surface" if water_lowers(self.sea) else None

    def step_water(self):
        """The water the compiled step evaluates at the nodes (its waves' and fields'
        elevation): :func:`~skmoor.sea.hydro.water_arrays`."""
        return water_arrays(self.sea)

    def _eta(self, u, t):
        """(ndofs,) the surface elevation at the displaced nodes on their z DOFs, m."""
        eta = np.zeros(self.lines.ndofs)
        if not self._flat:
            x = self.lines.points + u[self.lines.nodal_dofs]
            eta[self.z_dofs] = self.sea.elevation(x, t)
        return eta

    def _heights(self, u, t):
        """(nel, nqp) heights above the surface (m) at the Gauss points, as the form sees
        them; None when every node of a P1 LineSet lies half a diameter deep (the Gauss
        points lie between the nodes)."""
        lines = self.lines
        if lines.hermite:
            return np.asarray(lines.basis.interpolate(self.fields["X"] + u - self._eta(u, t)))[2]
        nodes = self.z_reference + u[self._z_view]
        if not self._flat:
            nodes = nodes - self._eta(u, t)[self.z_dofs]
        if nodes.max() <= self.deepest_reach:
            return None
        a, b = nodes[lines.mesh.t]  # (nel,) each
        return a[:, None] * self._phi[0] + b[:, None] * self._phi[1]

    def add_to(self, u, v, t, R, K=None, C=None):
        height = self._heights(u, t)
        if height is None:
            return
        v = np.zeros_like(u) if v is None else v  # None: at rest (the drag of the waves alone)
        cells = np.flatnonzero(np.any(height > -self._half, axis=1))
        if not len(cells):  # every Gauss point half a diameter deep: the term is zero
            return
        if self.path != "assembly":  # the compiled and numpy paths take every element
            super().add_to(u, v, t, R, K, C)
            return
        self._add_buoyancy(height[cells], cells, R, K)
        if self.drag and (np.any(v) or not (self.sea is None or self.sea.still)):
            self._add_drag(cells, u, v, t, R, K, C)  # zero without a relative velocity

    def _add_buoyancy(self, height, cells, R, K):
        """dry_buoyancy and dry_buoyancy_stiffness on the elements ``cells`` (heights
        (ncells, nqp) at their Gauss points), summed in NumPy: only z test functions."""
        ratio = height / self.fields["diameter"][cells]
        dry = np.clip(0.5 + ratio, 0.0, 1.0)
        slope = ((ratio > -0.5) & (ratio < 0.5)) / self.fields["diameter"][cells]
        weight = self.fields["buoyancy"][cells] * self.lines.basis.dx[cells]
        Z = self._test_z[:, cells]  # (nloc, ncells, nqp), scikit-fem's local order
        np.add.at(R, self.lines.basis.element_dofs[:, cells], np.einsum("iaq,aq->ia", Z, dry * weight))
        if K is not None:
            local = np.einsum("iaq,jaq,aq->aij", Z, Z, slope * weight)
            K[cells] += local[:, self._order][:, :, self._order]

    def _add_drag(self, cells, u, v, t, R, K, C):
        """dry_drag and its tangents by scikit-fem's assembly on the elements ``cells``."""
        basis, order = self._basis_on(cells)
        nel = self._nel
        _, w = self._w(u, v, t)
        w = {k: x[..., cells, :] if isinstance(x, np.ndarray) and x.ndim >= 2
             and x.shape[-2] == nel else x for k, x in w.items()}
        R += asm(dry_drag, basis, **w)
        if K is not None:
            K[cells] += _blocks(dry_drag_stiffness.elemental(basis, **w), order)
            C[cells] += _blocks(dry_drag_damping.elemental(basis, **w), order)

    def _basis_on(self, cells):
        """The line basis on the elements ``cells`` only (scikit-fem's assembly on them)
        and the permutation of its local DOFs to the element blocks', kept while the
        same elements reach the surface."""
        key = cells.tobytes()
        if self._cells_basis is None or self._cells_basis[0] != key:
            full = self.lines.basis
            basis = CellBasis(self.lines.mesh, full.elem, elements=cells,
                              quadrature=(full.X, full.W))
            ours, theirs = self.lines.element_dofs[cells], basis.element_dofs.T
            order = np.array([int(np.flatnonzero(theirs[0] == d)[0]) for d in ours[0]])
            if not np.array_equal(theirs[:, order], ours):
                raise ValueError("SurfaceTerm: the basis' local DOFs do not follow the nodes")
            self._cells_basis = (key, basis, order)
        return self._cells_basis[1:]

    def fields_at(self, t, u):
        return dict(self.fields, eta=self._eta(u, t), uw=nodal_water(self.lines, self.sea, u, t))
