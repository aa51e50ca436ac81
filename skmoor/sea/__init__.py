"""The sea: waves and currents, water grids, the sea bed, Morison hydrodynamics, the free
surface and vortex-induced vibration.
"""
