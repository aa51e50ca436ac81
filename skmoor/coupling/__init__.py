"""The network (points, lines, bodies, rods, joints) and the System that couples it into one
set of equations on reduced DOFs.
"""
from ..bodies.rod_loads import RodType
from .build import build_system
from .dofs import DofMap
from .joints import BodyPin
from .network import Body, MooringLine, Network, Point
from .system import Ends, PointMass, System

__all__ = ["Point", "MooringLine", "Body", "Network", "build_system", "System", "Ends",
           "PointMass", "DofMap", "RodType", "BodyPin"]
