"""Mooring lines: constitutive laws, the LineSet on one scikit-fem mesh, the cable forms
(Eqs. 11-12) and kernels, bending, creep and the analytic catenary.
"""
