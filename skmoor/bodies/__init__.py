"""Rigid bodies: mass and hydrostatics, rotations, body motion, prescribed motions, loads,
wave radiation and BEM coefficients.
"""
