"""Finite-element machinery: form operations, element patterns, Hermite shapes, the term
protocol (Term, LineForm) and the form compiler.
"""
from .hermite import hermite_shapes
from .patterns import ElementPattern
from .terms import LineForm, TangentCheck, Term, check_tangent

__all__ = ["Term", "LineForm", "TangentCheck", "check_tangent", "ElementPattern",
           "hermite_shapes"]
