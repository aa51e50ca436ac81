"""The sea: waves and currents, water grids, the sea bed, Morison hydrodynamics, the free
surface and vortex-induced vibration.
"""
from .hydro import PointDrag, SeaTerm, body_hydrodynamics, line_hydrodynamics
from .seabed import Bathymetry, Seabed, seabed_term
from .surface import SurfaceTerm
from .viv import VortexLift, VortexLiftForm, vortex_lift_term
from .waves import AiryWave, Current, JonswapWave, Sea

__all__ = ["Sea", "Current", "AiryWave", "JonswapWave", "Seabed", "Bathymetry",
           "seabed_term", "line_hydrodynamics", "body_hydrodynamics", "PointDrag",
           "SurfaceTerm", "VortexLift", "VortexLiftForm", "vortex_lift_term", "SeaTerm"]
