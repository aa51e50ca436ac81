"""Hydrodynamic loads: Morison drag on the velocity relative to the water, fluid inertia
and added mass on the lines; quadratic drag and added mass on a rigid body.

Conventions are MoorDyn v2's, so a MoorDyn line type maps one to one
(MoorDyn source/Line.cpp, ``Line::getStateDeriv``, tags v2.7.1 and later; docs/inputs.rst,
"Line Types"): with d the line type's diameter (constant, no contraction), A = pi d^2 / 4,
per unit UNSTRETCHED length, the relative flow v = u_water - rdot split along the line's
current unit tangent q into v_q = (v.q) q and v_p = v - v_q:

- transverse drag  1/2 rho Cd    d      |v_p| v_p   (Cd: "w.r.t. frontal area d l")
- tangential drag  1/2 rho CdAx (pi d)  |v_q| v_q   (CdAx: "w.r.t. surface area pi d l")
- fluid inertia    rho A [(1 + Ca) a_p + (1 + CaAx) a_q], a the water acceleration
  (Froude-Krylov plus the added-mass part of the water's acceleration)
- added mass       rho A [Ca (I - q q^T) + CaAx q q^T]

LineType's Cd_n, Cd_t, Ca_n, Ca_t are MoorDyn's Cd, CdAx, Ca, CaAx. skmoor integrates over
s, the REFERENCE arclength (line.py): a load per unstretched length is divided by the
reference stretch, as LineSet does for ``m`` and ``w`` (the factor is read off as
m / LineType.mass). Differences from MoorDyn: the loads are integrated with Gauss points
over each element (MoorDyn lumps them at the nodes with the nodal tangent); the added mass
is a constant matrix on the reference tangent X' (MoorDyn uses the current tangent);
the line is taken as fully submerged here (:mod:`skmoor.sea.surface` takes the buoyancy and
the drag of a line's dry part back; MoorDyn's decks have it).

The water velocity and acceleration are evaluated at the displaced nodes X + u at time t
(as MoorDyn does) and interpolated linearly along each element; their spatial gradient is
neglected in the tangent d/du, which differentiates only the current tangent
tau = (X' + u') / |X' + u'|.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from numba import carray, njit
from skfem import BilinearForm, LinearForm, asm

from ..bodies.loads import BodyLoad
from ..fem import ops
from ..fem.form_compiler import compiled_when_asked
from ..fem.hermite import hermite_shapes
from ..fem.native_calls import advanced, call_form
from ..fem.ops import d_ds, dot
from ..fem.patterns import NO_BLOCKS, NO_BLOCKS_12
from ..fem.terms import LineForm, Term
from ..numerics.validation import check_finite, check_positive
from .water_grids import (
    field_elevation,
    field_kinematics,
    fields_accelerate,
    fields_lower,
    packed_fields,
)
from .waves import Sea

# --- the forms. Fields (nel, nqp), per unit reference length: drag_n = 1/2 rho Cd_n d,
# drag_t = 1/2 rho Cd_t pi d, inertia_n/t = (1 + Ca_n/t) rho A, added_n/t = Ca_n/t rho A;
# uw, aw: P1 fields of the water velocity and acceleration (nodal_water).

def _tangent(w):
    """tau = r' / |r'| and |r'|, r' = X' + u' (the current unit tangent and stretch)."""
    rp = w.Xp + d_ds(w.u)
    length = ops.sqrt(dot(rp, rp))
    return rp / length, length


def _split(vec, tau):
    """(vec . tau, vec - (vec . tau) tau): axial component and normal part."""
    along = dot(vec, tau)
    return along, vec - along * tau


def _nonzero(x):
    """x with zeros replaced by 1, for quotients that vanish with their numerator."""
    return ops.where(x > 0, x, 1.0)


@LinearForm
def morison_drag(v, w):
    # -int [drag_n |v_n| v_n + drag_t |v_t| v_t] . du ds,  v = u_w - udot split along tau
    tau, _ = _tangent(w)
    a, vn = _split(w.uw - w.du, tau)
    speed = ops.norm(vn)
    return -(w.drag_n * speed * dot(vn, v) + w.drag_t * ops.abs(a) * a * dot(tau, v))


@BilinearForm
def morison_drag_rate(dv, v, w):
    # d/d(udot): int [drag_n (|v_n| P + v_n v_n^T / |v_n|) + 2 drag_t |v.tau| tau tau^T] dv . du ds
    tau, _ = _tangent(w)
    a, vn = _split(w.uw - w.du, tau)
    speed = ops.norm(vn)
    _, dvn = _split(dv, tau)
    return (w.drag_n * (speed * dot(dvn, v) + dot(vn, dv) * dot(vn, v) / _nonzero(speed))
            + 2.0 * w.drag_t * ops.abs(a) * dot(tau, dv) * dot(tau, v))


@BilinearForm
def morison_drag_stiffness(du, v, w):
    # d/du via tau only (dtau = P du'/|r'|): -int [drag_n d(|v_n| v_n) + drag_t d(|v_t| v_t)].du ds
    tau, length = _tangent(w)
    a, vn = _split(w.uw - w.du, tau)
    speed = ops.norm(vn)
    _, dtau = _split(d_ds(du), tau)
    dtau = dtau / length
    vd = dot(vn, dtau)
    d_normal = -(speed * a * dtau + speed * vd * tau + a * vd * vn / _nonzero(speed))
    d_axial = 2.0 * ops.abs(a) * vd * tau + ops.abs(a) * a * dtau
    return -dot(w.drag_n * d_normal + w.drag_t * d_axial, v)


@LinearForm
def fluid_inertia(v, w):
    # -int [inertia_n a_n + inertia_t a_t] . du ds,  a = water acceleration split along tau
    tau, _ = _tangent(w)
    a, an = _split(w.aw, tau)
    return -(w.inertia_n * dot(an, v) + w.inertia_t * a * dot(tau, v))


@LinearForm
def morison_in_waves(v, w):
    # the drag and the fluid inertia above in one form (the water evaluated once for both)
    return morison_drag.form(v, w) + fluid_inertia.form(v, w)


@BilinearForm
def fluid_inertia_stiffness(du, v, w):
    # d/du via tau: -int (inertia_t - inertia_n) d(a_t).du ds, d(a_t) = (a_n.dtau) tau + (a.tau) dtau
    tau, length = _tangent(w)
    a, an = _split(w.aw, tau)
    _, dtau = _split(d_ds(du), tau)
    dtau = dtau / length
    return -(w.inertia_t - w.inertia_n) * dot(dot(an, dtau) * tau + a * dtau, v)


@BilinearForm
def added_mass(du, v, w):
    # int [added_n (I - X' X'^T) + added_t X' X'^T] dudd . du ds, on the reference tangent X'
    along = dot(w.Xp, du) * dot(w.Xp, v)
    return w.added_n * (dot(du, v) - along) + w.added_t * along


# --- line terms

def coefficients(lines):
    """The coefficient fields of the forms above, (nel, nqp) each at the Gauss points
    (``lines.basis``), from each cell's LineType, per unit reference length."""
    fields = lines.fields
    types = [line.line_type for line in lines.lines]

    def per_cell(name):
        return np.array([getattr(lt, name) for lt in types])[lines.line_of_cell][:, None]

    per_reference = fields["m"] / per_cell("mass")  # 1 / stretch, as m = mass / stretch
    rho, d, area = per_cell("rho_water"), per_cell("diameter"), per_cell("area")
    out = dict(drag_n=0.5 * rho * per_cell("Cd_n") * d,
               drag_t=0.5 * rho * per_cell("Cd_t") * np.pi * d,
               inertia_n=(1.0 + per_cell("Ca_n")) * rho * area,
               inertia_t=(1.0 + per_cell("Ca_t")) * rho * area,
               added_n=per_cell("Ca_n") * rho * area,
               added_t=per_cell("Ca_t") * rho * area)
    return {name: value * per_reference for name, value in out.items()}


def nodal_water(lines, sea, u, t, kind="velocity"):
    """(ndofs,) water velocity (m/s) or, for kind='acceleration', acceleration (m/s2)
    at the displaced nodes X + u, as a P1 field (the forms see its interpolation)."""
    out = np.zeros(lines.ndofs)
    if sea is None or (sea.still if kind == "velocity" else not sea.has_waves):
        return out
    x = lines.points + u[lines.nodal_dofs]
    out[lines.nodal_dofs] = sea.velocity(x, t) if kind == "velocity" else sea.acceleration(x, t)
    return out


def lump_blocks(M, nodal_dofs):
    """Row-sum lumping by 3 x 3 nodal blocks: node i keeps sum_j M_ij (Eq. 20 for a
    direction-dependent mass), sparse."""
    M = M.tocoo()
    node = np.empty(M.shape[0], int)
    component = np.empty(M.shape[0], int)
    node[nodal_dofs] = np.arange(len(nodal_dofs))[:, None]
    component[nodal_dofs] = np.arange(3)
    cols = nodal_dofs[node[M.row], component[M.col]]
    return sp.csr_matrix((M.data, (M.row, cols)), shape=M.shape)


def added_mass_matrix(lines, lumped=True):
    """The lines' added mass (sparse, kg), block-lumped when ``lumped``; None when every
    Ca_n and Ca_t is zero."""
    c = coefficients(lines)
    if not (np.any(c["added_n"]) or np.any(c["added_t"])):
        return None
    M = asm(added_mass, lines.basis, **lines.fields, **c)
    return lump_blocks(M, lines.nodal_dofs) if lumped else M.tocsr()


class SeaTerm(LineForm):
    """A :class:`~skmoor.fem.terms.LineForm` with the water's velocity (field ``uw``) or
    acceleration (``aw``, when ``water='acceleration'``; both when ``water='both'``) from
    :func:`nodal_water` at the displaced nodes at time t; its mass (the added mass) is
    block-lumped when ``lumped``."""

    WATER = {"velocity": ("uw",), "acceleration": ("aw",), "both": ("uw", "aw")}

    def __init__(self, residual, *, sea=None, water="velocity", lumped=True, **kw):
        if water not in self.WATER:
            raise ValueError(f"SeaTerm water: {water!r} is not one of {tuple(self.WATER)}")
        super().__init__(residual, **kw)
        self.sea, self.water, self.lumped = sea, water, lumped

    def add_to(self, u, v, t, R, K=None, C=None):
        if self.water == "velocity" and (self.sea is None or self.sea.still) and not np.any(v):
            return  # drag and its derivatives vanish with the relative velocity
        super().add_to(u, v, t, R, K, C)

    def fields_at(self, t, u):
        kinds = {"uw": "velocity", "aw": "acceleration"}
        return dict(self.fields, **{name: nodal_water(self.lines, self.sea, u, t, kinds[name])
                                    for name in self.WATER[self.water]})

    def fields_vary(self) -> bool:
        return not (self.sea is None or self.sea.still)  # still water: uw = 0 throughout

    _water_size = 0  # floats of the water after the generated kernel's (_water_step_kernel)

    def lowered(self):
        """'form' also in moving water of a kind the compiled kernels evaluate
        (:func:`water_lowers`): the generated kernel (and with a memory its commit) called
        after the water at the displaced nodes (:func:`_sea_form_packed`)."""
        kind = super().lowered()
        if (kind is None and self.fields_vary() and self.path == "compiled"
                and self.generated is not None and water_lowers(self.sea)):
            self.step_kernel = self._water_step_kernel()
            if self.state:
                self.step_commit = self._packed_steps()[1]
            kind = "form"
        return kind

    def step_state(self):
        memory, offset = super().step_state()
        return memory, offset + self._water_size

    @property
    def why_python(self):
        if self.path == "compiled" and self.fields_vary() and not water_lowers(self.sea):
            return LineHydroKernel.why_python
        return super().why_python

    def _water_step_kernel(self):
        """(C function, ints, floats) of :func:`_sea_form_packed`: ints [the generated
        kernel's address, where the water's floats start, nodes, profile points, wave
        components, 1 with waves or fields (x and y matter) else 0, where the velocity's
        and the acceleration's DOF fields start in floats (-1: not read), the generated
        commit's address (0: none); the nodes' z DOFs (then with waves or fields their x and y
        DOFs), their x, y, z DOFs (nodes, 3), then the kernel's ints], floats [the
        kernel's, then the water's (:func:`_water`)]."""
        function, form_ints, form_floats, dof_names, D_start, commit = self.generated
        lines = self.lines
        field_at = [D_start + dof_names.index(name) * lines.ndofs
                    if name in self.WATER[self.water] else -1 for name in ("uw", "aw")]
        heading, heights, speeds, waves, fields = water_arrays(self.sea)
        xy = len(waves) > 0 or fields[0] > 0
        axes = [2, 0, 1] if xy else [2]  # z, then with waves or fields x and y
        dofs, X = lines.nodal_dofs, lines.points
        header = [function.address, form_floats.size, len(dofs), len(heights), len(waves), xy,
                  *field_at, 0 if commit is None else commit.address]
        ints = np.concatenate([header, *dofs[:, axes].T, dofs.ravel(),
                               self._more_ints(dof_names, D_start), form_ints])
        floats = np.concatenate([np.ravel(a) for a in (
            form_floats, *X[:, axes].T, heading, heights, speeds, waves, fields,
            np.zeros(3 * len(X)), np.zeros(3 * len(X) * xy))])
        self._water_size = floats.size - form_floats.size
        return self._packed_steps()[0], ints.astype(np.int64), floats.astype(float)

    def _more_ints(self, dof_names, D_start):
        """Ints a subclass's packed kernel reads after the water's, before the generated
        kernel's (dof_names, D_start: the generated kernel's DOF fields and where they
        start in its floats)."""
        return np.zeros(0, np.int64)

    def _packed_steps(self):
        """(the packed kernel, the packed commit) the compiled step calls, C functions."""
        return _sea_form_step(), _sea_commit_step()

    def mass_matrix(self):
        return None if self.mass is None else added_mass_matrix(self.lines, self.lumped)


class LineHydroKernel(Term):
    """The forms above (drag, fluid inertia, added mass) as a compiled kernel (see
    :mod:`skmoor.lines.cable_kernel`), a line :class:`~skmoor.fem.terms.Term`: the same Gauss
    points, element by element, on P1 lines (:func:`_morison`) or on bending lines' cubics
    (:func:`_morison_shapes`; in the compiled time step by address, :attr:`step_kernel`)."""

    why_python = "a water field of a kind the compiled kernels lack (water_lowers)"

    def __init__(self, lines, sea=None, lumped_mass=True):
        basis = lines.basis
        self.lines, self.sea = lines, sea
        self.moving_water = sea is not None and not sea.still
        self.has_waves = sea is not None and sea.has_waves
        self.Xp = np.ascontiguousarray(np.moveaxis(lines.fields["Xp"], 0, -1))  # (nel, nqp, 3)
        self.points, self.nodal_dofs = lines.points, lines.nodal_dofs
        xi, h, t = basis.X[0], lines.element_lengths, lines.mesh.t.T  # t: each element's nodes
        self.h = h
        self.edofs = np.ascontiguousarray(lines.element_dofs, np.int64)  # (nel, 6 or 12)
        if not lines.hermite:  # _morison's arrays
            self.phi = np.stack([1.0 - xi, xi])  # (2, nqp) P1 shape functions
            self.enodes = np.ascontiguousarray(t, np.int64)  # (nel, 2)
            self.wphi = np.ascontiguousarray(basis.dx[:, None, :] * self.phi)  # (nel, 2, nqp)
        else:  # _morison_shapes': the cubics [u_i, u_i', u_j, u_j'], values, slopes, weight
            N, dN, _ = hermite_shapes(xi, h)  # (nel, nqp, 9), each shape's node (< 0: a slope)
            self.shapes = np.ascontiguousarray(np.concatenate([N, dN, basis.dx[..., None]], -1))
            self.nodes = np.ascontiguousarray(
                np.stack([t[:, 0], -t[:, 0] - 1, t[:, 1], -t[:, 1] - 1], axis=1), np.int64)
        c = coefficients(lines)
        self.kn, self.kt = c["drag_n"], c["drag_t"]
        self.mn, self.dm = c["inertia_n"], c["inertia_t"] - c["inertia_n"]
        self._still = np.zeros((len(self.points), 3))
        self._no_velocity = np.zeros(lines.ndofs)
        self._mass = added_mass_matrix(lines, lumped_mass)

    def step_arrays(self):
        """The arrays :func:`_morison` reads before the state, in its order (P1 lines)."""
        return (self.Xp, self.h, self.phi, self.wphi, self.kn, self.kt, self.mn, self.dm,
                self.edofs, self.enodes)

    @property
    def compiled_water(self) -> bool:
        """True when the compiled kernels evaluate the water at the nodes
        (:func:`water_lowers`)."""
        return water_lowers(self.sea)

    def lowered(self):
        return "form" if self.compiled_water else None

    @property
    def step_kernel(self):
        """In water the compiled kernels evaluate (:func:`water_lowers`), (C function, ints,
        floats): :func:`_morison` (P1) or :func:`_morison_shapes` (bending lines) as the
        compiled time step calls a user's LineForm (by address,
        :data:`~skmoor.fem.form_compiler.STEP_SIGNATURE`; compiled when first asked for), the
        water at the displaced nodes (:func:`_water`), the arrays packed: ints [nel, nqp,
        nodes, profile points, wave components, 1 with waves or fields (x and y matter) else
        0, each element's nodes (P1: 2; bending: 4, one per shape, -1 on a slope and all -1
        in still water), element DOFs, the nodes' z DOFs (then, with waves or fields, their
        x and y DOFs)], floats [X', (P1: h, phi, w phi;
        bending: shapes), drag_n, drag_t, inertia_n, inertia_t - inertia_n, then the
        water's (:func:`_water`)]; in still water no nodes on bending lines."""
        if not self.compiled_water:
            return None
        nel, nqp = self.kn.shape
        heading, heights, speeds, waves, fields = water_arrays(self.sea)
        hermite = self.lines.hermite
        if hermite and not self.moving_water:
            nodes, dofs, X = np.full(4 * nel, -1), np.zeros((0, 3), int), np.zeros((0, 3))
        else:
            nodes = self.nodes.ravel() if hermite else self.enodes.ravel()
            dofs, X = self.nodal_dofs, self.points
        xy = len(waves) > 0 or fields[0] > 0
        axes = [2, 0, 1] if xy else [2]  # z, then with waves or fields x and y
        shape = (self.shapes,) if hermite else (self.h, self.phi, self.wphi)
        ints = np.concatenate([[nel, nqp, len(dofs), len(heights), len(waves), xy], nodes,
                               self.edofs.ravel(), *dofs[:, axes].T]).astype(np.int64)
        floats = np.concatenate([np.ravel(a) for a in (
            self.Xp, *shape, self.kn, self.kt, self.mn, self.dm, *X[:, axes].T, heading,
            heights, speeds, waves, fields, np.zeros(3 * len(X)), np.zeros(3 * len(X) * xy))])
        return (_morison_step if hermite else _morison_p1_step)(), ints, floats

    def add_to(self, u, ud, t, R, Ke=None, Ce=None):
        """Adds the residual into R and, with Ke, Ce, its derivatives into the element
        blocks (the term protocol, :mod:`skmoor.fem.terms`)."""
        water = acceleration = self._still
        if self.moving_water:
            water, acceleration = self.sea.kinematics(self.points + u[self.nodal_dofs], t)
        none = NO_BLOCKS_12 if self.lines.hermite else NO_BLOCKS
        ud = self._no_velocity if ud is None else ud
        Ke, Ce = none if Ke is None else Ke, none if Ce is None else Ce
        if self.lines.hermite:
            _morison_shapes(self.Xp, self.shapes, self.kn, self.kt, self.mn, self.dm,
                            self.edofs, self.nodes, u, ud, water, acceleration,
                            self.has_waves, R, Ke, Ce)
        else:
            _morison(*self.step_arrays(), u, ud, water, acceleration, self.has_waves, R, Ke,
                     Ce)

    def mass_matrix(self):
        """The added mass (sparse, kg), or None when every Ca is zero."""
        return self._mass


@njit(cache=True, inline="always")
def _point_force(kn, kt, mn, dm, rx, ry, rz, vx, vy, vz, cx, cy, cz, has_waves):
    """morison_drag (+ fluid_inertia with waves) at a point: the force per length f for
    r' = (rx, ry, rz), the relative velocity v = u_w - udot and the water's acceleration c,
    with what its slopes need: (f, tau, v_n, a_n (water's acceleration normal to tau), v.tau,
    c.tau, drag_n |v_n|, |v_n|, |r'|)."""
    length = np.sqrt(rx * rx + ry * ry + rz * rz)
    tx, ty, tz = rx / length, ry / length, rz / length
    a = vx * tx + vy * ty + vz * tz  # along tau
    nx, ny, nz = vx - a * tx, vy - a * ty, vz - a * tz
    speed = np.sqrt(nx * nx + ny * ny + nz * nz)
    # f = drag_n |v_n| v_n + drag_t |a| a tau (+ inertia_n a_n + inertia_t a_t)
    cn, ct = kn * speed, kt * abs(a) * a
    fx, fy, fz = cn * nx + ct * tx, cn * ny + ct * ty, cn * nz + ct * tz
    aa = wnx = wny = wnz = 0.0  # the water's acceleration along tau and normal to it
    if has_waves:
        aa = cx * tx + cy * ty + cz * tz
        wnx, wny, wnz = cx - aa * tx, cy - aa * ty, cz - aa * tz
        mt = (mn + dm) * aa
        fx += mn * wnx + mt * tx
        fy += mn * wny + mt * ty
        fz += mn * wnz + mt * tz
    return ((fx, fy, fz), (tx, ty, tz), (nx, ny, nz), (wnx, wny, wnz), a, aa, cn, speed,
            length)


@njit(cache=True, inline="always")
def _point_slopes(kn, kt, dm, tau, vn, wn, a, aa, cn, speed, has_waves, B, G):
    """The force's derivatives at a point (the tuple of :func:`_point_force`): B = df/dudot
    and G = df/du' |r'| (3 x 3 each, into B and G)."""
    # d/dudot: alpha I + beta tau tau^T + gamma v_n v_n^T, alpha = drag_n |v_n|
    beta = 2.0 * kt * abs(a) - cn
    gamma = kn / speed if speed > 0 else kn
    # d/du' |r'|: c1 I + tau y^T - gamma a v_n v_n^T, y = beta v_n - c1 tau (+ dm a_n)
    c1 = (kt * abs(a) - cn) * a + (dm * aa if has_waves else 0.0)
    for p in range(3):
        for s in range(3):
            y = beta * vn[s] - c1 * tau[s] + (dm * wn[s] if has_waves else 0.0)
            B[p, s] = beta * tau[p] * tau[s] + gamma * vn[p] * vn[s]
            G[p, s] = tau[p] * y - gamma * a * vn[p] * vn[s]
        B[p, p] += cn
        G[p, p] += c1


@njit(cache=True)
def _morison(Xp, h, phi, wphi, kn, kt, mn, dm, edofs, enodes, u, ud, water, acceleration,
             has_waves, R, Ke, Ce):
    """Adds morison_drag (+ fluid_inertia with waves) into R and their derivatives
    (morison_drag_stiffness + fluid_inertia_stiffness, morison_drag_rate) into Ke, Ce on P1
    elements. An element's nodal values are read once into scalars (the Gauss-point loop
    runs in registers; :func:`_morison_shapes`' loop over shape functions costs P1 lines a
    tenth to a fifth more)."""
    tangent = Ke.shape[0] > 0
    if tangent:  # the tangent's scratch (a residual alone allocates nothing)
        B, G = np.empty((3, 3)), np.empty((3, 3))  # d/dudot and d/du' of the force
    ax = ay = az = bx = by = bz = 0.0  # the water's acceleration at the nodes (waves)
    for e in range(h.size):
        i0, i1, i2 = edofs[e, 0], edofs[e, 1], edofs[e, 2]
        j0, j1, j2 = edofs[e, 3], edofs[e, 4], edofs[e, 5]
        na, nb = enodes[e, 0], enodes[e, 1]
        he = h[e]
        sx, sy, sz = (u[j0] - u[i0]) / he, (u[j1] - u[i1]) / he, (u[j2] - u[i2]) / he
        # v = u_w - udot at the two nodes
        wx, wy, wz = water[na, 0] - ud[i0], water[na, 1] - ud[i1], water[na, 2] - ud[i2]
        qx, qy, qz = water[nb, 0] - ud[j0], water[nb, 1] - ud[j1], water[nb, 2] - ud[j2]
        if has_waves:
            ax, ay, az = acceleration[na, 0], acceleration[na, 1], acceleration[na, 2]
            bx, by, bz = acceleration[nb, 0], acceleration[nb, 1], acceleration[nb, 2]
        for q in range(phi.shape[1]):
            pa, pb = phi[0, q], phi[1, q]
            f, tau, vn, wn, a, aa, cn, speed, length = _point_force(
                kn[e, q], kt[e, q], mn[e, q], dm[e, q], Xp[e, q, 0] + sx, Xp[e, q, 1] + sy,
                Xp[e, q, 2] + sz, pa * wx + pb * qx, pa * wy + pb * qy, pa * wz + pb * qz,
                pa * ax + pb * bx, pa * ay + pb * by, pa * az + pb * bz, has_waves)
            wa, wb = wphi[e, 0, q], wphi[e, 1, q]
            R[i0] -= wa * f[0]
            R[i1] -= wa * f[1]
            R[i2] -= wa * f[2]
            R[j0] -= wb * f[0]
            R[j1] -= wb * f[1]
            R[j2] -= wb * f[2]
            if not tangent:
                continue
            _point_slopes(kn[e, q], kt[e, q], dm[e, q], tau, vn, wn, a, aa, cn, speed,
                          has_waves, B, G)
            for i in range(2):
                for j in range(2):
                    rate_weight = wphi[e, i, q] * phi[j, q]
                    # K_e[i, j] = -w phi_i dphi_j/ds dF/du', dphi_j/ds = -+1/h
                    slope_weight = (wphi[e, i, q] / (length * he)) * (1.0 if j == 0 else -1.0)
                    for p in range(3):
                        for s in range(3):
                            Ce[e, 3 * i + p, 3 * j + s] += rate_weight * B[p, s]
                            Ke[e, 3 * i + p, 3 * j + s] += slope_weight * G[p, s]


@njit(cache=True)
def _morison_shapes(Xp, shapes, kn, kt, mn, dm, edofs, nodes, u, ud, water, acceleration,
                    has_waves, R, Ke, Ce):
    """:func:`_morison` on any shape functions (the bending lines' cubics): adds
    morison_drag (+ fluid_inertia with waves) into R and their derivatives into Ke, Ce, on
    the shape functions given at each Gauss point as shapes (nel, nqp, 2 m + 1): m values,
    their m d/ds and the point's weight (m), each shape acting on three DOFs of edofs; the
    water's velocity and acceleration (per node) on the shapes of nodes >= 0 (a value), none
    on a slope (nodes < 0), as the forms interpolate them."""
    tangent = Ke.shape[0] > 0
    count = nodes.shape[1]
    if tangent:  # the tangent's scratch (a residual alone allocates nothing)
        B, G = np.empty((3, 3)), np.empty((3, 3))  # d/dudot and d/du' of the force
    for e in range(edofs.shape[0]):
        for q in range(shapes.shape[1]):
            # r' = X' + u', v = u_w - udot and the water's acceleration c at the point
            rx, ry, rz = Xp[e, q, 0], Xp[e, q, 1], Xp[e, q, 2]
            vx = vy = vz = 0.0
            cx = cy = cz = 0.0
            for b in range(count):
                d0, d1, d2 = edofs[e, 3 * b], edofs[e, 3 * b + 1], edofs[e, 3 * b + 2]
                slope, value = shapes[e, q, count + b], shapes[e, q, b]
                rx += slope * u[d0]
                ry += slope * u[d1]
                rz += slope * u[d2]
                vx -= value * ud[d0]
                vy -= value * ud[d1]
                vz -= value * ud[d2]
                node = nodes[e, b]
                if node >= 0:
                    vx += value * water[node, 0]
                    vy += value * water[node, 1]
                    vz += value * water[node, 2]
                    if has_waves:
                        cx += value * acceleration[node, 0]
                        cy += value * acceleration[node, 1]
                        cz += value * acceleration[node, 2]
            f, tau, vn, wn, a, aa, cn, speed, length = _point_force(
                kn[e, q], kt[e, q], mn[e, q], dm[e, q], rx, ry, rz, vx, vy, vz, cx, cy, cz,
                has_waves)
            for b in range(count):
                w = shapes[e, q, 2 * count] * shapes[e, q, b]
                R[edofs[e, 3 * b]] -= w * f[0]
                R[edofs[e, 3 * b + 1]] -= w * f[1]
                R[edofs[e, 3 * b + 2]] -= w * f[2]
            if not tangent:
                continue
            _point_slopes(kn[e, q], kt[e, q], dm[e, q], tau, vn, wn, a, aa, cn, speed,
                          has_waves, B, G)
            for i in range(count):
                wi = shapes[e, q, 2 * count] * shapes[e, q, i]
                for j in range(count):
                    # K_e[i, j] = -w N_i dN_j dF/du' / |r'|, C_e[i, j] = w N_i N_j dF/dudot
                    rate_weight = wi * shapes[e, q, j]
                    slope_weight = -wi * shapes[e, q, count + j] / length
                    for p in range(3):
                        for s in range(3):
                            Ce[e, 3 * i + p, 3 * j + s] += rate_weight * B[p, s]
                            Ke[e, 3 * i + p, 3 * j + s] += slope_weight * G[p, s]


def _morison_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """:func:`_morison_shapes` in still water, a current and Airy waves (the water at the
    displaced nodes, :func:`_water`) on the buffers of ``LineHydroKernel.step_kernel``."""
    nel, nqp = ints[0], ints[1]
    points = nel * nqp
    nodes = carray(advanced(ints, 6), (nel, 4))
    edofs = carray(advanced(ints, 6 + 4 * nel), (nel, 12))
    Xp = carray(floats, (nel, nqp, 3))
    shapes = carray(advanced(floats, 3 * points), (nel, nqp, 9))
    kn, kt, mn, dm = _coefficients(floats, 12 * points, nel, nqp)
    u = carray(u_p, (ndofs,))
    water, acceleration, waves = _water(u, t, ints, 6 + 16 * nel, floats, 16 * points)
    blocks = nel if tangent else 0
    _morison_shapes(Xp, shapes, kn, kt, mn, dm, edofs, nodes, u, carray(ud_p, (ndofs,)),
                    water, acceleration, waves, carray(R_p, (ndofs,)),
                    carray(K_p, (blocks, 12, 12)), carray(C_p, (blocks, 12, 12)))


def _morison_p1_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """:func:`_morison` in still water, a current and Airy waves (the water at the
    displaced nodes, :func:`_water`) on the buffers of ``LineHydroKernel.step_kernel``
    (P1 lines)."""
    nel, nqp = ints[0], ints[1]
    points = nel * nqp
    enodes = carray(advanced(ints, 6), (nel, 2))
    edofs = carray(advanced(ints, 6 + 2 * nel), (nel, 6))
    Xp = carray(floats, (nel, nqp, 3))
    at = 3 * points
    h = carray(advanced(floats, at), (nel,))
    phi = carray(advanced(floats, at + nel), (2, nqp))
    at += nel + 2 * nqp
    wphi = carray(advanced(floats, at), (nel, 2, nqp))
    at += 2 * points
    kn, kt, mn, dm = _coefficients(floats, at, nel, nqp)
    u = carray(u_p, (ndofs,))
    water, acceleration, waves = _water(u, t, ints, 6 + 8 * nel, floats, at + 4 * points)
    blocks = nel if tangent else 0
    _morison(Xp, h, phi, wphi, kn, kt, mn, dm, edofs, enodes, u, carray(ud_p, (ndofs,)),
             water, acceleration, waves, carray(R_p, (ndofs,)), carray(K_p, (blocks, 6, 6)),
             carray(C_p, (blocks, 6, 6)))


@njit(cache=True)
def _set_water(u, t, ints, floats, ndofs):
    """A :class:`SeaTerm`'s water fields (velocity and/or acceleration, DOF fields) set at
    the displaced nodes (:func:`_water`) in the buffers of ``SeaTerm._water_step_kernel``;
    returns where the generated kernel's ints start."""
    nnodes, axes = ints[2], 3 if ints[5] else 1
    water, acceleration, accelerates = _water(u, t, ints, 9, floats, ints[1])
    dofs = carray(advanced(ints, 9 + axes * nnodes), (nnodes, 3))
    velocity_field = carray(advanced(floats, max(ints[6], 0)), (ndofs,))
    acceleration_field = carray(advanced(floats, max(ints[7], 0)), (ndofs,))
    for p in range(nnodes):
        for c in range(3):
            if ints[6] >= 0:
                velocity_field[dofs[p, c]] = water[p, c]
            if ints[7] >= 0:
                acceleration_field[dofs[p, c]] = acceleration[p, c] if accelerates else 0.0
    return 9 + (axes + 3) * nnodes


def _sea_form_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """A :class:`SeaTerm`'s generated kernel (the C function at ints[0]) in a current and
    Airy waves, its water field set first (:func:`_set_water`)."""
    start = _set_water(carray(u_p, (ndofs,)), t, ints, floats, ndofs)
    call_form(ints[0], u_p, ud_p, ndofs, t, advanced(ints, start), floats, R_p, K_p, C_p,
              tangent)


def _sea_commit_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """A :class:`SeaTerm`'s generated commit (the C function at ints[8]): its memory
    advanced to the accepted step, its water field set first (:func:`_set_water`)."""
    start = _set_water(carray(u_p, (ndofs,)), t, ints, floats, ndofs)
    call_form(ints[8], u_p, ud_p, ndofs, t, advanced(ints, start), floats, R_p, K_p, C_p,
              tangent)


@njit(cache=True)
def _coefficients(floats, at, nel, nqp):
    """The packed Morison coefficients (drag_n, drag_t, inertia_n, inertia_t - inertia_n;
    each (nel, nqp)) from item ``at`` of the float buffer on."""
    block = carray(advanced(floats, at), (4, nel, nqp))
    return block[0], block[1], block[2], block[3]


WAVE_COLUMNS = 8  # a component's packed numbers: see wave_components


def water_arrays(sea):
    """(the current's heading (2,; unit, horizontal), its profile's heights (m) and speeds
    (m/s), the Airy components (:func:`wave_components`), the tabulated fields packed
    (:func:`~skmoor.sea.water_grids.packed_fields`)) of ``sea`` as the compiled kernels
    read them: empty in still water ([0] the fields), the heading zero without a current."""
    moving = sea is not None and not sea.still
    current = sea.current if moving else None
    heading, heights, speeds = ((np.zeros(2), np.zeros(0), np.zeros(0)) if current is None
                                else (np.asarray(current.direction[:2], float),
                                      np.asarray(current.z, float),
                                      np.asarray(current.speeds, float)))
    fields = packed_fields(sea.fields) if moving else np.zeros(1)
    if fields is None:
        raise ValueError("water_arrays: a water field the compiled kernels lack "
                         f"({[type(f).__name__ for f in sea.fields]}); see water_lowers")
    return heading, heights, speeds, wave_components(sea.waves if moving else []), fields


def water_lowers(sea) -> bool:
    """True when the compiled kernels evaluate ``sea``'s water (:func:`water_arrays`): still
    water, a current, Airy waves and fields of MoorDyn's kinds
    (:func:`~skmoor.sea.water_grids.packed_fields`)."""
    return sea is None or sea.still or fields_lower(sea.fields)


def wave_components(waves) -> np.ndarray:
    """(components, 8) of Airy waves (:mod:`skmoor.sea.waves`) as the compiled kernels
    read them: a (m), omega (rad/s), k (rad/m), phase (rad), 1 / (1 - exp(-2 k h)), the
    heading's x and y, the depth h (m)."""
    rows = [np.column_stack([w.a, w.omega, w.k, w.phi, w.depth_scale,
                             np.full(w.a.size, w.direction[0]), np.full(w.a.size, w.direction[1]),
                             np.full(w.a.size, w.depth)]) for w in waves]
    return np.concatenate(rows) if rows else np.zeros((0, WAVE_COLUMNS))


@njit(cache=True)
def wave_kinematics(x, y, z, t, components, out):
    """Adds the water velocity (out[0:3], m/s) and local acceleration (out[3:6], m/s2) of
    the Airy components (:func:`wave_components`) at the point (x, y, z) (m) and time t (s)
    into out: ``skmoor.sea.waves._Components.kinematics``, z clipped to [-h, 0]."""
    for c in range(components.shape[0]):
        a, omega, k, phase, scale, dx, dy, depth = (
            components[c, 0], components[c, 1], components[c, 2], components[c, 3],
            components[c, 4], components[c, 5], components[c, 6], components[c, 7])
        theta = (x * dx + y * dy) * k - t * omega + phase
        zc = min(max(z, -depth), 0.0)
        up, down = math.exp(k * zc), math.exp(-k * (zc + 2.0 * depth))
        ch, sh = (up + down) * scale, (up - down) * scale
        cos, sin = math.cos(theta), math.sin(theta)
        aw = a * omega
        aw2 = aw * omega
        horizontal, rising = ch * cos * aw, ch * sin * aw2
        out[0] += horizontal * dx
        out[1] += horizontal * dy
        out[2] += sh * sin * aw
        out[3] += rising * dx
        out[4] += rising * dy
        out[5] -= sh * cos * aw2


@njit(cache=True, inline="always")
def water_kinematics(x, y, z, t, heading, heights, speeds, components, fields, out):
    """out[0:6] <- the water's velocity (m/s) and local acceleration (m/s2) at (x, y, z)
    (m) and time t (s), as ``Sea.kinematics``: the current of the heading (unit,
    horizontal) and profile (heights m, speeds m/s; none: no current), the Airy
    components (:func:`wave_kinematics`) and the packed fields
    (:func:`~skmoor.sea.water_grids.field_kinematics`)."""
    speed = current_speed(z, heights, speeds) if heights.size else 0.0
    for c in range(6):
        out[c] = 0.0
    if components.shape[0]:
        wave_kinematics(x, y, z, t, components, out)
    if fields[0] > 0.0:
        field_kinematics(x, y, z, t, fields, out)
    out[0] += speed * heading[0]
    out[1] += speed * heading[1]


@njit(cache=True)
def wave_elevation(x, y, t, components, fields):
    """The free surface's elevation (m) of the Airy components (:func:`wave_components`)
    and the packed fields at (x, y) (m) and time t (s): ``Sea.elevation``."""
    eta = 0.0
    for c in range(components.shape[0]):
        theta = ((x * components[c, 5] + y * components[c, 6]) * components[c, 2]
                 - t * components[c, 1] + components[c, 3])
        eta += components[c, 0] * math.cos(theta)
    if fields[0] > 0.0:
        eta += field_elevation(x, y, t, fields)
    return eta


@njit(cache=True)
def unpacked_water(floats, at, nprofile, ncomponents):
    """The water of :func:`water_arrays` packed in ``floats`` from ``at`` (the heading, the
    profile's heights and speeds, the components, the fields, in that order) as C arrays:
    (heading, heights, speeds, components, fields, where the floats after them start)."""
    heading = carray(advanced(floats, at), (2,))
    heights = carray(advanced(floats, at + 2), (nprofile,))
    speeds = carray(advanced(floats, at + 2 + nprofile), (nprofile,))
    at += 2 + 2 * nprofile
    components = carray(advanced(floats, at), (ncomponents, WAVE_COLUMNS))
    at += WAVE_COLUMNS * ncomponents
    end = at + 1
    for _ in range(int(floats[at])):  # each field's kind, length and numbers
        end += 2 + int(floats[end + 1])
    return heading, heights, speeds, components, carray(advanced(floats, at), (end - at,)), end


@njit(cache=True)
def _water(u, t, ints, at_ints, floats, at):
    """(velocity, acceleration, whether it accelerates) of the water at the displaced
    nodes (nodes, 3 each; m/s, m/s2): the current (``Current.velocity``), the Airy waves
    and the fields (:func:`water_kinematics`), from the packed buffers of
    ``LineHydroKernel.step_kernel`` (ints from ``at_ints``: the nodes' z DOFs, then with
    waves or fields their x and y DOFs; floats from ``at``: the nodes' reference z (then
    x and y), the current's heading (unit, horizontal), its profile's heights (m) and
    speeds (m/s), the wave components (components, 8), the packed fields, room for the
    velocity (nodes, 3) and with waves or fields for the acceleration), written there
    (left zero in still water)."""
    nnodes, nprofile, ncomponents = ints[2], ints[3], ints[4]
    axes = 3 if ints[5] else 1  # (waves or fields: x and y too)
    dofs = carray(advanced(ints, at_ints), (axes, nnodes))
    X = carray(advanced(floats, at), (axes, nnodes))
    heading, heights, speeds, components, fields, at = unpacked_water(
        floats, at + axes * nnodes, nprofile, ncomponents)
    xy = axes == 3  # waves or fields: the water varies in x and y, and accelerates
    water = carray(advanced(floats, at), (nnodes, 3))
    acceleration = carray(advanced(floats, at + 3 * nnodes), (nnodes if xy else 0, 3))
    if not (nprofile or xy):  # still water
        return water, water, False
    kinematics = np.empty(6)
    for p in range(nnodes):  # (x and y only where waves or fields need them)
        x = X[1, p] + u[dofs[1, p]] if xy else 0.0
        y = X[2, p] + u[dofs[2, p]] if xy else 0.0
        water_kinematics(x, y, X[0, p] + u[dofs[0, p]], t, heading, heights, speeds,
                         components, fields, kinematics)
        for c in range(3):
            water[p, c] = kinematics[c]
            if xy:
                acceleration[p, c] = kinematics[3 + c]
    accelerates = ncomponents > 0 or fields_accelerate(fields)
    return water, (acceleration if accelerates else water), accelerates


_morison_p1_step = compiled_when_asked(_morison_p1_packed)  # (its C function, when first asked for)


_sea_form_step = compiled_when_asked(_sea_form_packed)  # (its C function, when first asked for)


_sea_commit_step = compiled_when_asked(_sea_commit_packed)  # (its C function, when first asked for)


@njit(cache=True)
def current_speed(z, heights, speeds):
    """A Current's speed (m/s) at height z (m) from its profile (heights ascending, m):
    np.interp's, linear in between and constant beyond the ends."""
    if z <= heights[0]:
        return speeds[0]
    last = heights.size - 1
    if z >= heights[last]:
        return speeds[last]
    k = np.searchsorted(heights, z) - 1
    w = (z - heights[k]) / (heights[k + 1] - heights[k])
    return speeds[k] + w * (speeds[k + 1] - speeds[k])


_morison_step = compiled_when_asked(_morison_packed)  # (its C function, when first asked for)


def _check_sea(lines, sea):
    if sea is None:
        return
    if not isinstance(sea, Sea):
        raise ValueError(f"line_hydrodynamics sea: expected a skmoor.sea.waves.Sea or None, "
                         f"got {type(sea).__name__}")
    for line in lines.lines:
        if not np.isclose(line.line_type.rho_water, sea.rho, rtol=1e-12, atol=0.0):
            raise ValueError(f"line_hydrodynamics sea: rho {sea.rho} kg/m3 differs from line "
                             f"{line.name!r}'s LineType.rho_water {line.line_type.rho_water}")


def line_hydrodynamics(lines, sea=None, *, lumped_mass=None):
    """The line term for a System on ``lines`` (a LineSet): Morison drag on the relative
    velocity, fluid inertia (when ``sea`` has waves) and added mass, coefficients from each
    line's LineType (MoorDyn v2 conventions, see the module docstring), as one compiled
    :class:`LineHydroKernel`. sea=None: still water. lumped_mass: block-lump the added
    mass (True) or keep it consistent (False); None: as the System has the line's mass,
    lumped on P1 lines, consistent on bending (Hermite) lines (whose slopes have no
    lumped mass)."""
    if lumped_mass is None:
        lumped_mass = not lines.hermite
    elif lumped_mass and lines.hermite:
        raise ValueError("line_hydrodynamics lumped_mass: bending (Hermite) lines have a "
                         "consistent mass, not a lumped one; give lumped_mass=False or "
                         "leave it out")
    _check_sea(lines, sea)
    return LineHydroKernel(lines, sea, lumped_mass)


def line_terms(lines, sea=None, *, lumped_mass=True, path="auto") -> list:
    """The hydrodynamic line terms of a System on ``lines``: the compiled kernel
    (:func:`line_hydrodynamics`), or on a bending (Hermite) LineSet with ``path`` other
    than 'auto' the forms (:func:`form_terms` on that path); bending lines take the
    consistent added mass (as their line mass)."""
    if lines.hermite and path != "auto":
        return form_terms(lines, sea, lumped_mass=False, path=path)
    return [line_hydrodynamics(lines, sea, lumped_mass=lumped_mass and not lines.hermite)]


def form_terms(lines, sea=None, *, lumped_mass=True, path="auto"):
    """The same physics as :func:`line_hydrodynamics` as :class:`SeaTerm` forms (the
    definition): drag (+ fluid inertia with waves: a second term with its hand-written
    tangents, on the automatic tangents' paths one form, :func:`morison_in_waves`);
    ``path`` as :class:`LineForm` ('auto': scikit-fem's assembly with the hand-written
    tangents)."""
    _check_sea(lines, sea)
    c = coefficients(lines)
    mass = added_mass if np.any(c["added_n"]) or np.any(c["added_t"]) else None
    hand = path in ("auto", "assembly")
    waves = sea is not None and sea.has_waves
    if waves and not hand:  # one pass over the water for both
        return [SeaTerm(morison_in_waves, mass=mass, fields=c, sea=sea, water="both",
                        lumped=lumped_mass, path=path, lines=lines)]
    terms = [SeaTerm(morison_drag, stiffness=morison_drag_stiffness if hand else None,
                     damping=morison_drag_rate if hand else None, mass=mass, fields=c,
                     sea=sea, lumped=lumped_mass, path=path, lines=lines)]
    if waves:
        terms.append(SeaTerm(fluid_inertia, stiffness=fluid_inertia_stiffness if hand else None,
                             fields=c, sea=sea, water="acceleration", path=path, lines=lines))
    return terms


# --- body

def _six(name, value):
    """A (6,) array from 3 (translational, rotational zero) or 6 finite values."""
    arr = np.asarray(value, float).ravel()
    if arr.shape not in ((3,), (6,)):
        raise ValueError(f"body_hydrodynamics {name}: need 3 or 6 values, got {arr.shape}")
    check_finite(f"body_hydrodynamics {name}", arr)
    if np.any(arr < 0):
        raise ValueError(f"body_hydrodynamics {name}: must be >= 0, got {arr}")
    return np.concatenate([arr, np.zeros(6 - arr.size)])


def body_hydrodynamics(*, drag_coefficients=None, drag_areas=None, added_mass=None, sea=None,
                       reference_point=(0.0, 0.0, 0.0), rho=1025.0, axes=None) -> BodyDrag:
    """A :class:`BodyDrag`: quadratic drag on the body's velocity relative to the water and
    a constant added mass, MoorDyn v2's body convention (source/Body.cpp).

    drag_coefficients (-), drag_areas (m2 translational; m5 rotational): 3 or 6 values
    each, multiplied, along / about the body's axes; added_mass: (6, 6) about the
    reference point (kg, kg m, kg m2); reference_point (m): where q is measured and the
    water velocity taken; axes (3, 3): the body's axes (columns, global) at q = 0 (a deck
    body's start attitude; None: the global axes).
    """
    check_positive("body_hydrodynamics rho", rho)
    point = np.asarray(reference_point, float)
    if point.shape != (3,):
        raise ValueError(f"body_hydrodynamics reference_point: need 3 values, got {point.shape}")
    check_finite("body_hydrodynamics reference_point", point)
    if (drag_coefficients is None) != (drag_areas is None):
        raise ValueError("body_hydrodynamics drag_coefficients, drag_areas: give both or neither")
    if sea is not None:
        if not isinstance(sea, Sea):
            raise ValueError(f"body_hydrodynamics sea: expected a Sea or None, "
                             f"got {type(sea).__name__}")
        if not np.isclose(sea.rho, rho, rtol=1e-12, atol=0.0):
            raise ValueError(f"body_hydrodynamics rho: {rho} kg/m3 differs from sea.rho {sea.rho}")
    cda = (np.zeros(6) if drag_coefficients is None
           else _six("drag_coefficients", drag_coefficients) * _six("drag_areas", drag_areas))
    if added_mass is not None:
        added_mass = np.asarray(added_mass, float)
        if added_mass.shape != (6, 6):
            raise ValueError(f"body_hydrodynamics added_mass: need a (6, 6) matrix, "
                             f"got {added_mass.shape}")
        check_finite("body_hydrodynamics added_mass", added_mass)
    if axes is not None:
        axes = np.asarray(axes, float)
        if axes.shape != (3, 3) or not np.allclose(axes.T @ axes, np.eye(3), atol=1e-9):
            raise ValueError("body_hydrodynamics axes: need a (3, 3) rotation matrix (the "
                             f"body's axes as columns), got {axes.tolist()}")
    return BodyDrag(cda, sea, point, float(rho), added_mass, axes=axes)


class BodyDrag(BodyLoad):
    """Quadratic drag on a body (:func:`body_hydrodynamics`), MoorDyn v2's Body.cpp: with
    v_r = u_w(x_ref + q[:3], t) - v the relative velocity of the reference point and
    w_r = -omega,

        F = 1/2 rho D(CdA[:3]) |v_r| v_r,   M = 1/2 rho D(CdA[3:]) |w_r| w_r

    (|.| the norm of the 3-vector), applied as [F, E^T M]. The drag areas are along the
    body's axes: D(c) = R A diag(c) A^T R^T, A the body's axes at q = 0 (``axes``), R its
    rotation (MoorDyn's OrMat diag(CdA) OrMat^T), with omega = E qdot[3:] the angular
    velocity; a 'small' body keeps the linear model (R = I, omega = qdot[3:], E = I).
    The pose comes from :meth:`body_motion` (re-based frames included). Tangents: dF/dqdot
    exact; dF/dq without the water velocity's gradient (zero on a small body, central
    differences in the angles on an exact one)."""

    frame_aware = True
    why_python = "a water field of a kind the compiled kernels lack (water_lowers)"

    def __init__(self, cda, sea, reference_point, rho, added_mass=None, body=0, axes=None):
        self.cda, self.sea, self.point, self.rho = cda, sea, reference_point, rho
        self.axes = np.eye(3) if axes is None else axes
        self._moving_water = sea is not None and not sea.still
        super().__init__(self.forces, body=body, added_mass=added_mass, tangent=self.tangents)

    def lowered(self):
        """'body drag' in water the compiled kernels evaluate (:func:`water_lowers`; the
        compiled step's, on a small-rotation body: an exact one is refused for its
        rotations)."""
        return "body drag" if water_lowers(self.sea) else None

    def step_drag(self):
        """The drag matrices 1/2 rho D(CdA) of the force and the moment at q = 0 (2, 3, 3)
        as the compiled step reads them (a small body's: they do not turn)."""
        half = 0.5 * self.rho * self.cda
        return np.stack([(self.axes * half[:3]) @ self.axes.T,
                         (self.axes * half[3:]) @ self.axes.T])

    def step_water(self):
        """The water the compiled step evaluates at the reference point: :func:`water_arrays`."""
        return water_arrays(self.sea)

    def _drag(self, motion, t):
        """(F, M, D_F, D_M, v_r, w_r): the drag force and moment (global, N, N m), the
        drag matrices 1/2 rho D(CdA) (3, 3 each) and the relative velocities."""
        vr = -motion.velocity
        if self._moving_water:
            vr = vr + self.sea.velocity(self.point + motion.q[:3], t)
        wr = -motion.angular_velocity
        half = 0.5 * self.rho * self.cda
        axes = motion.rotation @ self.axes if motion.exact else self.axes
        D_F, D_M = (axes * half[:3]) @ axes.T, (axes * half[3:]) @ axes.T  # R diag(c) R^T
        return (np.linalg.norm(vr) * (D_F @ vr), np.linalg.norm(wr) * (D_M @ wr),
                D_F, D_M, vr, wr)

    def forces(self, q, qdot, t):
        """The load conjugate to q (6,), N and N m."""
        motion = self.body_motion(q, qdot)
        F, M = self._drag(motion, t)[:2]
        return motion.generalized(F, M)

    def tangents(self, q, qdot, t):
        """(dQ/dq or None, dQ/dqdot) (6, 6 each)."""
        motion = self.body_motion(q, qdot)
        _, _, D_F, D_M, vr, wr = self._drag(motion, t)
        E = motion.rate_map
        dQ_dv = np.zeros((6, 6))
        # d(|w| D w)/dw = D (|w| I + w w^T / |w|); dv_r/dv = -I, dw_r/dqdot[3:] = -E
        for block, D, w, T in ((slice(0, 3), D_F, vr, np.eye(3)), (slice(3, 6), D_M, wr, E)):
            speed = np.linalg.norm(w)
            dQ_dv[block, block] = -T.T @ D @ (speed * np.eye(3) + np.outer(w, w) / (speed or 1.0)) @ T
        if not motion.exact:
            return None, dQ_dv
        step = 1e-6
        dQ_dq = np.zeros((6, 6))
        for k in range(3, 6):
            e = np.zeros(6)
            e[k] = step
            dQ_dq[:, k] = (self.forces(q + e, qdot, t) - self.forces(q - e, qdot, t)) / (2 * step)
        return dQ_dq, dQ_dv


class PointDrag(Term):
    """Quadratic drag on a free point (MoorDyn's point CdA): with w the velocity of the
    water (a current; still water: 0) relative to the point's,

        F = 1/2 rho CdA |w| w,

    entering the residual as -F, with its exact derivative with respect to the velocity
    (N s/m) and none with respect to the position (the water is taken at the point's
    reference position plus its displacement, without its gradient)."""

    acts_on = "points"
    why_python = "a water field of a kind the compiled kernels lack (water_lowers)"

    def __init__(self, point, CdA, rho=1025.0, sea=None):
        self.point, self.CdA, self.rho, self.sea = int(point), float(CdA), float(rho), sea
        self.k = 0.5 * self.rho * self.CdA
        self.moving_water = sea is not None and not sea.still
        self.position = np.zeros(3)

    def bind(self, system):
        super().bind(system)
        self.position = system.point_reference[self.point]

    def lowered(self):
        return "point drag" if water_lowers(self.sea) else None

    def step_water(self):
        """The water the compiled step evaluates at the point: :func:`water_arrays`."""
        return water_arrays(self.sea)

    def add_to(self, u, v, t, R, K=None, C=None):
        relative = -v
        if self.moving_water:
            relative = relative + self.sea.velocity(self.position + u, t)
        speed = np.linalg.norm(relative)
        R -= self.k * speed * relative
        if C is not None and speed > 0:  # the residual's d/dv of -k |w| w, w = U - v
            C += self.k * (speed * np.eye(3) + np.outer(relative, relative) / speed)
