"""Results and what is made of them: ParaView files, off-screen renders, plots.
"""
