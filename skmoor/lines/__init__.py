"""Mooring lines: constitutive laws, the LineSet on one scikit-fem mesh, the cable forms
(Eqs. 11-12) and kernels, bending, creep and the analytic catenary.
"""
from .cable import CableTerm
from .catenary import Catenary, solve_catenary
from .creep import CreepTerm
from .laws import Curve, Engineering, Paper, StaticDynamic, Viscoelastic
from .line import Line, LineSet, LineType, read_line_mesh, write_line_mesh
from .user_law import UserLaw

__all__ = ["LineType", "Line", "LineSet", "read_line_mesh", "write_line_mesh", "CableTerm",
           "Catenary", "solve_catenary", "Paper", "Engineering", "Curve", "StaticDynamic",
           "Viscoelastic", "CreepTerm", "UserLaw"]
