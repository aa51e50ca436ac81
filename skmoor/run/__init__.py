"""Running a model: simulate (statics, modes, damping, time loop, outputs) and sweeps.
"""
from .simulate import equilibrium, mooring_stiffness, static_results
from .sweep import Study, run_sweep

__all__ = ["equilibrium", "static_results", "mooring_stiffness", "run_sweep",
           "Study"]
