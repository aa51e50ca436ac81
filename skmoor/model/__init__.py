"""From a case, a MoorDyn deck or a network to one Model.
"""
from .from_deck import heave_motion, read_motion
from .model import Model, build, from_network
from .openfast_motion import openfast_motion

__all__ = ["Model", "build", "from_network", "heave_motion", "read_motion",
           "openfast_motion"]
