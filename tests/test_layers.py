"""The package's layering: import-linter's contracts (pyproject.toml) and no import cycle
between any two modules, so a change cannot quietly import back up the data flow."""
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
grimp = pytest.importorskip("grimp", reason="the layers are checked with import-linter")


def test_import_linter_contracts_are_kept():
    command = shutil.which("lint-imports")
    assert command, "import-linter's lint-imports is not installed (pip install .[test])"
    done = subprocess.run([command, "--no-cache"], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout[-3000:]
    assert "0 broken" in done.stdout


def cycles(graph, modules):
    """Strongly connected components of more than one module (Tarjan's algorithm)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10 * len(modules)))

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.find_modules_directly_imported_by(v) & modules:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(modules):
        if v not in index:
            visit(v)
    return found


def test_no_module_imports_itself_back():
    graph = grimp.build_graph("skmoor", cache_dir=None)
    # a package's __init__ re-exports its modules: only modules proper take part
    modules = {m for m in graph.modules
               if not (ROOT / (m.replace(".", "/") + "/__init__.py")).exists()}
    assert cycles(graph, modules) == []


def test_cycles_are_found():
    """The cycle finder itself: two modules importing each other are one component."""

    class Graph:
        edges = {"a": {"b"}, "b": {"a"}, "c": {"a"}}

        def find_modules_directly_imported_by(self, module):
            return self.edges[module]

    assert cycles(Graph(), {"a", "b", "c"}) == [["a", "b"]]


def test_import_skmoor_leaves_the_heavy_optional_packages_out():
    """``import skmoor`` loads none of the packages only some commands need (plots,
    the case schema, renders, progress bars, datasets, batches, JAX): each costs a
    fraction of a second on every start (docs/speed.md, fixed costs)."""
    heavy = ("matplotlib", "pydantic", "pyvista", "scipy.optimize", "scipy.integrate", "tqdm",
             "xarray", "dask", "jax", "openfast_io")
    code = ("import sys, skmoor\n"
            f"print(' '.join(m for m in {heavy!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, check=True)
    assert done.stdout.strip() == ""
    import skmoor.io
    import skmoor.post

    assert callable(skmoor.io.validate_case) and callable(skmoor.post.plot_time_histories)
