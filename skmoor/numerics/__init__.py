"""Numerical building blocks with no physics: roots, input validation, band and bordered LU.
"""
from .banded import Band, as_layout
from .roots import brent
from .validation import check_finite, check_positive

__all__ = ["Band", "as_layout", "brent", "check_finite", "check_positive"]
