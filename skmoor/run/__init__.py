"""Running a model: simulate (statics, modes, damping, time loop, outputs) and sweeps.
"""
