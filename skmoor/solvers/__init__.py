"""Solvers that know nothing of the model: Newton, statics, modes, time integration and
the compiled step.
"""
from .dynamics import Scheme, integrate
from .modes import Modes, eigenmodes
from .newton import ConvergenceError, DivergenceError
from .statics import solve_static

__all__ = ["ConvergenceError", "DivergenceError", "solve_static", "eigenmodes", "Modes",
           "Scheme", "integrate"]
