"""Results and what is made of them: ParaView files, off-screen renders, plots.
(The renderer, :mod:`skmoor.post.render`, is imported on its own: it loads pyvista.)
"""
from .plots import plot_time_histories
from .results import Results

__all__ = ["Results", "plot_time_histories"]
