"""Results and what is made of them: ParaView files, off-screen renders, plots.
(The renderer, :mod:`skmoor.post.render`, is imported on its own: it loads pyvista; the
plots load matplotlib when first asked for.)
"""
from .results import Results

__all__ = ["Results", "plot_time_histories"]


def __getattr__(name):
    if name == "plot_time_histories":
        from .plots import plot_time_histories

        return plot_time_histories
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
