"""Finite-element machinery: form operations, element patterns, Hermite shapes, the term
protocol (Term, LineForm) and the form compiler.
"""
