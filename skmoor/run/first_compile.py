"""The compiled time step's first compile, shared with a helper process.

The first run after an install (or a change of the step's source) finds numba's disk cache
empty and compiles the step (:mod:`skmoor.solvers.compiled_step`), about half a minute on a
2-core machine, once. Its parts call one another by address, so they are independent
compile units: :func:`precompile` has a helper process compile some of them into the cache
while this one builds the model, solves its statics and compiles the others, and the first
step reads the helper's parts from the cache. One compiled step serves every model (its
types do not depend on the model), so the helper compiles it for the paper's case.
"""
from __future__ import annotations

import atexit
import os
import subprocess
import sys

from ..solvers import compiled_step

# the helper's share: about half of the compile time (measured cold: residual 14 s,
# factor 2 s; this process: run 7 s, the others 5 s, while it builds and settles)
HELPER_PARTS = ("residual", "factor")


def precompile():
    """Starts the helper when numba's cache does not hold the compiled step (call it first
    thing: it works while the model is built and settled); True if it did (the first run
    after an install, which then says why its first step waits; also when one is at
    work already)."""
    if compiled_step.compiling_elsewhere():
        return True
    if compiled_step.cached():
        return False
    package = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    code = (f"import sys; sys.path.insert(0, {package!r}); "
            "from skmoor.run.first_compile import compile_parts; "
            f"compile_parts({list(HELPER_PARTS)!r})")  # (the same skmoor as this process's)
    process = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    compiled_step.share_compile(process, HELPER_PARTS)
    atexit.register(_stop, process)
    return True


def _stop(process):
    """Ends the helper if this process ends first (an error before the first step)."""
    if process.poll() is None:
        process.kill()


def compile_parts(parts):
    """Compiles the step's ``parts`` (names in ``compiled_step.PARTS``) into numba's cache,
    for the paper's case (the helper's work)."""
    from ..io.case import paper_case
    from ..model.model import build
    from ..solvers.dynamics import Scheme

    system = build(paper_case()).system
    step = compiled_step.build(system, None, Scheme.generalized_alpha(), 1e-8, 20)
    step.compile(parts)
