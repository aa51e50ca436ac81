"""A network without lines: bodies, rods and points alone (MoorDyn decks with no LINES).

A scikit-fem ``MeshLine1`` cannot be empty, so a network without lines gets
:class:`NoLines` in place of the :class:`~skmoor.line.LineSet`: no DOFs, no elements,
nothing to assemble. The System then holds only its bodies' (and pins') equations;
its line kernel and element pattern are the empty ones below.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .banded import Band


class EmptyMesh:
    """The node and element arrays of a mesh with no elements (``p`` (1, 0) in s, m;
    ``t`` (2, 0))."""

    p = np.zeros((1, 0))
    t = np.zeros((2, 0), int)


class NoLines:
    """The LineSet of a network without lines: ndofs = 0, every per-node and per-element
    array empty, zero loads and mass."""

    hermite = False
    damped = False
    element = "p1"
    block_size = 6
    tension_only = True
    has_static_laws = False
    mesh = EmptyMesh()
    basis = None

    def __init__(self):
        self.lines = []
        self.points = np.zeros((0, 3))  # m
        self.nodal_dofs = np.zeros((0, 3), int)
        self.slope_dofs = None
        self.element_dofs = np.zeros((0, 6), int)
        self.anchor_nodes = self.fairlead_nodes = np.zeros(0, int)
        self.line_of_cell = np.zeros(0, int)
        self.element_lengths = np.zeros(0)  # m
        self.reference_dofs = np.zeros(0)
        self.fields = self.cable_fields = {}
        self.bandwidth = 0

    ndofs = 0

    def weight_load(self):
        return np.zeros(0)

    def mass_matrix(self, lumped: bool = True):
        return sp.csr_matrix((0, 0))

    def unit_tension_stiffness(self):
        return sp.csr_matrix((0, 0))

    def element_tension_and_strain(self, u, ud=None):
        return np.zeros(0), np.zeros(0)

    def element_tension(self, u, ud=None):
        return np.zeros(0)

    def element_strain(self, u):
        return np.zeros(0)

    def curvature(self, u):
        return np.zeros(0)

    def bending_moment(self, u):
        return np.zeros(0)

    def use_static_laws(self, static: bool):
        pass

    def carry_compression(self, fraction: float):
        pass

    def set_static_state(self, u):
        pass


class EmptyPattern:
    """The element pattern of no elements on ``ndofs`` unknowns: every assembly a zero
    matrix of that size."""

    nel, nloc, nnz, bandwidth = 0, 6, 0, 0

    def __init__(self, ndofs: int = 0):
        self.ndofs = ndofs

    def assemble(self, ke, layout="sparse"):
        n = self.ndofs
        if layout == "dense":
            return np.zeros((n, n))
        if layout == "band":
            return Band(np.zeros((Band.rows(0, 0), n), order="F"), 0, 0)
        return sp.csr_matrix((n, n))


class NoLineKernel:
    """The cable kernel of no lines: adds nothing."""

    def __init__(self, ndofs: int = 0):
        self.pattern = EmptyPattern(ndofs)

    def add_to(self, u, ud, R, Ke=None, Ce=None):
        pass

    def element_tension_and_strain(self, u, ud=None):
        return np.zeros(0), np.zeros(0)
