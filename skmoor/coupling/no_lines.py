"""A network without lines: bodies, rods and points alone (MoorDyn decks with no LINES).

A scikit-fem ``MeshLine1`` cannot be empty, so a network without lines gets
:class:`NoLines` in place of the :class:`~skmoor.lines.line.LineSet`: no DOFs, no elements,
nothing to assemble. The System then holds only its bodies' (and pins') equations;
its line kernel and element pattern are the empty ones below.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..numerics.banded import Band


class EmptyMesh:
    """The node and element arrays of a mesh with no elements (``p`` (1, 0) in s, m;
    ``t`` (2, 0))."""

    p = np.zeros((1, 0))
    t = np.zeros((2, 0), int)


class NoLines:
    """The LineSet of a network without lines: ndofs = 0, every per-node and per-element
    array empty, no load, no mass."""

    hermite = False
    damped = False
    tension_only = True
    has_static_laws = False
    has_user_law = False
    creep = None  # (no creep laws' term)
    laws = ()
    ndofs = 0
    slope_dofs = None

    def __init__(self):
        self.lines = []
        self.mesh = EmptyMesh()
        self.points = np.zeros((0, 3))  # m
        self.nodal_dofs = np.zeros((0, 3), int)
        self.anchor_nodes = self.fairlead_nodes = np.zeros(0, int)
        self.line_of_cell = np.zeros(0, int)

    def weight_load(self):
        return np.zeros(0)

    def mass_matrix(self, lumped: bool = True):
        return sp.csr_matrix((0, 0))

    def unit_tension_stiffness(self):
        return sp.csr_matrix((0, 0))

    def element_tension_and_strain(self, u, ud=None):
        return np.zeros(0), np.zeros(0)

    def use_static_laws(self, static: bool):
        """No line laws to switch (as LineSet.use_static_laws)."""

    def carry_compression(self, fraction: float):
        """No line to let compression through (as LineSet.carry_compression)."""


class EmptyPattern:
    """The element pattern of no elements on ``ndofs`` unknowns: every assembly a zero
    matrix of that size."""

    nel, nloc, bandwidth = 0, 6, 0

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

    def __init__(self):
        self.pattern = EmptyPattern()

    def add_to(self, u, ud, R, Ke=None, Ce=None):
        """Nothing to add (as CableKernel.add_to)."""
