"""The network (points, lines, bodies, rods, joints) and the System that couples it into one
set of equations on reduced DOFs.
"""
