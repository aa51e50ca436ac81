"""The first run's compile shared with a helper process (skmoor.run.first_compile).

The helper compiles some of the compiled step's parts for the paper's case while the run
settles its own model; the run then reads them from numba's cache. That only saves time if
the helper compiles exactly the signatures a run of any model calls (one whose arguments
drifted would compile unused code, and the run would compile them again), and if the run
compiles its own parts before waiting for the helper (waiting first serializes the two).
"""
import subprocess
import sys

import numpy as np
import pytest
from numba import typeof
from test_network import network_two_bodies

import skmoor
from skmoor.run import first_compile
from skmoor.solvers import compiled_step
from skmoor.solvers.dynamics import Scheme


def _step(model):
    step = compiled_step.build(model.system, None, Scheme.generalized_alpha(), 1e-8, 20)
    assert step is not None, compiled_step.last_refusal
    return step


@pytest.mark.filterwarnings("ignore::UserWarning")  # (the shared rope starts stretched)
def test_the_helper_compiles_the_signatures_a_run_of_another_model_calls():
    model = skmoor.from_network(network_two_bodies())  # bodies, points, a shared rope
    skmoor.simulate(model, duration=0.2, dt=0.1, progress=False)
    helper = _step(skmoor.build(skmoor.paper_case()))  # what the helper compiles for
    data_type = helper._data_type()
    assert data_type == typeof(_step(model)._data())  # made without compiling _step_data
    for part in compiled_step.PARTS:
        function, arguments = helper._part_arguments(part, data_type)
        argtypes = tuple(data_type if a is data_type else typeof(a) for a in arguments)
        assert argtypes in function.overloads, part  # the run's own compilation


class _Helper:
    """A helper process that has compiled its parts when it is waited for."""

    def __init__(self, seen):
        self.seen = seen

    def wait(self, timeout=None):
        self.seen.append("wait")
        return 0


def test_the_first_step_compiles_its_own_parts_then_waits_for_the_helper(monkeypatch):
    seen = []
    compile_parts = compiled_step.CompiledStep.compile

    def compile_logged(self, parts, data=None):
        seen.append(tuple(parts))
        return compile_parts(self, parts, data)

    monkeypatch.setattr(compiled_step.CompiledStep, "compile", compile_logged)
    monkeypatch.setattr(compiled_step, "_CALLEES", {})  # as in a new process
    compiled_step.share_compile(_Helper(seen), first_compile.HELPER_PARTS)
    model = skmoor.build(skmoor.paper_case())
    results = skmoor.simulate(model, duration=0.2, dt=0.1, progress=False)
    own = tuple(p for p in compiled_step.PARTS if p not in first_compile.HELPER_PARTS)
    assert seen == [own, "wait", first_compile.HELPER_PARTS]
    assert compiled_step._shared is None
    assert np.all(np.isfinite(results.fairlead_tension))


def test_precompile_starts_the_helper_only_when_the_cache_lacks_the_step(monkeypatch):
    started = []
    monkeypatch.setattr(first_compile.subprocess, "Popen",
                        lambda command, **kw: started.append(command) or _Helper([]))
    monkeypatch.setattr(first_compile.atexit, "register", lambda *a: None)
    monkeypatch.setattr(compiled_step, "cached", lambda: True)
    assert not skmoor.precompile() and not started
    monkeypatch.setattr(compiled_step, "cached", lambda: False)
    try:
        assert skmoor.precompile()
        assert compiled_step._shared[1] == first_compile.HELPER_PARTS
        assert f"compile_parts({list(first_compile.HELPER_PARTS)!r})" in started[0][-1]
        assert skmoor.precompile() and len(started) == 1  # one helper at a time
    finally:
        compiled_step._shared = None


def test_an_empty_numba_cache_lacks_the_step(tmp_path):
    code = "from skmoor.solvers import compiled_step; print(compiled_step.cached())"
    empty = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           env={"NUMBA_CACHE_DIR": str(tmp_path), "PATH": ""}, check=True)
    assert empty.stdout.strip() == "False"
    skmoor.simulate(skmoor.build(skmoor.paper_case()), duration=0.1, dt=0.1, progress=False)
    assert compiled_step.cached()  # this process's cache holds it now
