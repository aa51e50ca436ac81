"""Rigid bodies: mass and hydrostatics, rotations, body motion, prescribed motions, loads,
wave radiation and BEM coefficients.
"""
from .bem import Hydrodynamics
from .body import Hydrostatics, RigidBody
from .body_motion import BodyMotion
from .loads import BodyLoad, BodyTerm, PointLoad
from .motion import Motion, Record, fade_in
from .radiation import PotentialFlow
from .restoring import AppliedLoad, BodyRestoring

__all__ = ["RigidBody", "Hydrostatics", "BodyMotion", "BodyTerm", "PointLoad", "BodyLoad",
           "Motion", "Record", "fade_in", "BodyRestoring", "AppliedLoad", "PotentialFlow",
           "Hydrodynamics"]
