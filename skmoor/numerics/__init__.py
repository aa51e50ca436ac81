"""Numerical building blocks with no physics: roots, input validation, band and bordered LU.
"""
