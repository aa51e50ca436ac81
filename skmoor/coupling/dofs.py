"""DOF numbering and reduction of a :class:`~skmoor.coupling.system.System`: which full
cable DOFs are free (and in which reduced column), held by a body or prescribed, and the
maps between the full cable vectors (m, N) and the reduced ones without forming P = du/dx.

Reduced unknowns x = [line DOFs | 6 per body]: the free line nodes and the free points (3
each, numbered where a line first reaches them, so a chain of lines keeps a narrow band),
on bending lines every node's 3 tangent DOFs but those of clamped ends (the two ends of a
smooth joint share theirs); then each body's displacement (m) and angles (rad).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def _held_nodes(lines, ends):
    """(node -> its end entry, clamped node -> its slot or None, smooth-joint node -> the
    joint's number) of the line ends' nodes."""
    held = {}
    for k, (a, b) in enumerate(zip(ends.a, ends.b)):
        held[int(lines.anchor_nodes[k])] = a
        held[int(lines.fairlead_nodes[k])] = b
    if ends.clamped and lines.slope_dofs is None:
        raise ValueError("System ends: clamped ends need bending lines (a LineType "
                         "with EI > 0); cables are pinned")
    clamped = {int((lines.anchor_nodes if end == "a" else lines.fairlead_nodes)[k]):
               slot[0] if slot else None for k, end, *slot in ends.clamped}
    if ends.smooth and lines.slope_dofs is None:
        raise ValueError("System ends: smooth joints need bending lines (a LineType "
                         "with EI > 0); cables are hinged at their points")
    joint = {}
    for number, (k, j) in enumerate(ends.smooth):
        joint[int(lines.fairlead_nodes[k])] = joint[int(lines.anchor_nodes[j])] = number
    return held, clamped, joint


class DofMap:
    """Where every full cable DOF goes in the reduced vector, and the maps between them.

    position: (ndofs,) reduced column of each full DOF (-1: held); free: the full DOFs
    with a column, columns: their columns (several DOFs of a free point share one);
    nf: line columns, nb: body columns (6 per body), n = nf + nb; identity: no two free
    DOFs share a column; blocks: each body's slice of x; point_columns (npoints, 3) and
    point_reference (npoints, 3, m) of the free points; body_end_dofs (n_ends, 3), their
    flat body_flat, body_of_end and, per body, body_rows (its rows of them) and r_local0
    (where the ends sit from the body's reference point at q = 0, m; a clamped end's
    tangent for its direction rows); directions: the rows that are clamped tangents
    (turned, not moved), direction_translation: their translation entries of the
    Jacobian; prescribed_slots, prescribed_dofs (n, 3) and prescribed_flat of the
    prescribed ends; fairlead_dofs and anchor_dofs (nlines, 3): the B and A ends.
    """

    def __init__(self, lines, ends, bodies, npoints):
        self.ndofs = lines.ndofs
        self.point_columns = np.full((npoints, 3), -1)
        self.point_reference = np.zeros((npoints, 3))  # m
        body_ends, prescribed_ends = self._number(lines, ends, bodies, npoints)
        self.free = np.flatnonzero(self.position >= 0)
        self.columns = self.position[self.free]
        self.identity = len(self.free) == self.nf  # no two DOFs share a column
        self.nb = 6 * len(bodies)
        self.n = self.nf + self.nb
        self.blocks = [slice(self.nf + 6 * k, self.nf + 6 * k + 6) for k in range(len(bodies))]
        body_ends.sort(key=lambda e: e[0])
        self.body_of_end = np.array([b for b, *_ in body_ends], int)
        self.body_end_dofs = np.array([d for _, d, _, _ in body_ends], int).reshape(-1, 3)
        self.body_flat = self.body_end_dofs.ravel()
        # clamped end tangents among the body ends: directions, R(q) t0 - t0 (no translation)
        self.directions = np.flatnonzero([turning for *_, turning in body_ends])
        rows = 3 * self.directions[:, None] + np.arange(3)
        columns = 6 * self.body_of_end[self.directions][:, None] + np.arange(3)
        self.direction_translation = (rows[:, :, None], columns[:, None, :])
        self.r_local0 = [np.array([r for b, _, r, _ in body_ends if b == k]).reshape(-1, 3)
                         for k in range(len(bodies))]
        self.body_rows = [np.flatnonzero(self.body_of_end == k) for k in range(len(bodies))]
        self.prescribed_slots = np.array([slot for slot, _ in prescribed_ends], int)
        self.prescribed_dofs = np.array([d for _, d in prescribed_ends], int).reshape(-1, 3)
        self.prescribed_flat = self.prescribed_dofs.ravel()
        self.has_prescribed = len(self.prescribed_flat) > 0
        self.fairlead_dofs = lines.nodal_dofs[lines.fairlead_nodes]  # (nlines, 3), end B
        self.anchor_dofs = lines.nodal_dofs[lines.anchor_nodes]  # (nlines, 3), end A
        self.free_block = sp.csr_matrix((np.ones(len(self.free)), (self.free, self.columns)),
                                        shape=(lines.ndofs, self.n))
        self.selection = None if self.identity else sp.csr_matrix(
            (np.ones(len(self.free)), (self.columns, np.arange(len(self.free)))),
            shape=(self.nf, len(self.free)))

    def _number(self, lines, ends, bodies, npoints):
        """Numbers the line columns node by node (sets position and nf); returns the body
        ends (body, dofs, r_local, is a tangent) and the prescribed ends (slot, dofs)."""
        dofs, slopes = lines.nodal_dofs, lines.slope_dofs
        held, clamped, joint = _held_nodes(lines, ends)
        joint_columns = {}
        self.position = position = np.full(lines.ndofs, -1)
        columns = 0
        body_ends, prescribed_ends = [], []
        for node in range(len(dofs)):
            end = held.get(node)
            if end is None:
                position[dofs[node]] = np.arange(columns, columns + 3)
                columns += 3
            elif end[0] == "point":
                columns = self._add_point(end[1], lines.points[node], columns, npoints)
                position[dofs[node]] = self.point_columns[end[1]]
            elif end[0] == "body":
                if not 0 <= end[1] < len(bodies):
                    raise ValueError(f"System ends: body {end[1]} does not exist "
                                     f"({len(bodies)} dynamic bodies given)")
                body_ends.append((end[1], dofs[node],
                                  lines.points[node] - bodies[end[1]].reference_point, False))
                if node in clamped:  # the end tangent t0 turns with the body: R(q) t0
                    body_ends.append((end[1], slopes[node],
                                      lines.reference_dofs[slopes[node]], True))
            elif end[0] == "prescribed":
                prescribed_ends.append((int(end[1]), dofs[node]))
                if clamped.get(node) is not None:  # the end tangent moved by its slot
                    prescribed_ends.append((clamped[node], slopes[node]))
            if slopes is not None and node not in clamped:
                if joint.get(node) in joint_columns:
                    position[slopes[node]] = joint_columns[joint[node]]
                    continue
                position[slopes[node]] = np.arange(columns, columns + 3)
                if node in joint:
                    joint_columns[joint[node]] = position[slopes[node]]
                columns += 3
        unused = np.flatnonzero(self.point_columns[:, 0] < 0)
        if len(unused):
            raise ValueError(f"System points: free point {int(unused[0])} has no line")
        self.nf = columns
        return body_ends, prescribed_ends

    def _add_point(self, p, where, columns, npoints):
        """Gives free point p its 3 columns where a line first reaches it (at ``where``,
        m); returns the next free column."""
        if not 0 <= p < npoints:
            raise ValueError(f"System ends: free point {p} does not exist "
                             f"({npoints} points given)")
        if self.point_columns[p, 0] < 0:
            self.point_columns[p] = np.arange(columns, columns + 3)
            self.point_reference[p] = where
            return columns + 3
        if np.linalg.norm(where - self.point_reference[p]) > 1e-6:
            raise ValueError(f"System ends: the lines at free point {p} start from "
                             f"different positions ({self.point_reference[p]} and "
                             f"{where}, m)")
        return columns

    def expand(self, y, J):
        """P y (ndofs,) for a reduced vector y, without forming P (J: the body ends'
        Jacobian (3 n_ends, nb), None without bodies)."""
        out = np.zeros(self.ndofs)
        out[self.free] = y[: self.nf] if self.identity else y[self.columns]
        if J is not None:
            out[self.body_flat] = J @ y[self.nf:]
        return out

    def reduce(self, R_full, J):
        """P^T R_full (n,), without forming P."""
        out = np.empty(self.n)
        if self.identity:
            out[: self.nf] = R_full[self.free]
        else:
            out[: self.nf] = np.bincount(self.columns, R_full[self.free], minlength=self.nf)
        if J is not None:
            out[self.nf:] = J.T @ R_full[self.body_flat]
        return out

    def select(self, A):
        """S A S^T: rows and columns of free DOFs summed into their reduced columns."""
        if self.identity:
            return A
        return (self.selection @ (self.selection @ A).T).T

    def reduce_dense(self, A, J):
        """P^T A P for a dense (ndofs, ndofs) A, without forming P."""
        free, ends = self.free, self.body_flat
        out = np.empty((self.n, self.n))
        out[: self.nf, : self.nf] = self.select(A[np.ix_(free, free)])
        if J is not None:
            S = (lambda B: B) if self.identity else (lambda B: self.selection @ B)
            out[: self.nf, self.nf:] = S(A[np.ix_(free, ends)] @ J)
            out[self.nf:, : self.nf] = S((J.T @ A[np.ix_(ends, free)]).T).T
            out[self.nf:, self.nf:] = J.T @ A[np.ix_(ends, ends)] @ J
        return out

    def reduce_sparse(self, A, J):
        """P^T A P for a sparse A (a row and column selection without bodies)."""
        if not self.nb and self.identity:
            return A[self.free][:, self.free]
        P = self.P(J)
        return (P.T @ A @ P).tocsr()

    def P(self, J):
        """du/dx (ndofs, n), sparse: the free DOFs' columns and the body ends' Jacobian J."""
        if not self.nb:
            return self.free_block
        rows = np.repeat(self.body_flat, self.nb)
        cols = np.tile(self.nf + np.arange(self.nb), len(self.body_flat))
        body = sp.csr_matrix((J.ravel(), (rows, cols)), shape=self.free_block.shape)
        return self.free_block + body

    def embed_bodies(self, A):
        """The (nb, nb) body block in a sparse (n, n) matrix (nothing of size n^2)."""
        rows, cols = np.nonzero(A)
        return sp.csr_matrix((A[rows, cols], (rows + self.nf, cols + self.nf)),
                             shape=(self.n, self.n))
