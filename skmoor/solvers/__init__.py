"""Solvers that know nothing of the model: Newton, statics, modes, time integration and
the compiled step.
"""
