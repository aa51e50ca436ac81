"""Running a model: simulate (statics, modes, damping, time loop, outputs) and sweeps.
"""
from .equilibrium import equilibrium, mooring_stiffness
from .recorder import static_results
from .sweep import Study, run_sweep

__all__ = ["equilibrium", "static_results", "mooring_stiffness", "run_sweep",
           "Study"]
