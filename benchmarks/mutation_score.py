"""Mutation score of the physics modules: mutmut (``pip install 'skmoor[mutation]'``)
mutates each module in a copy of the repository and runs the tests that mirror it; the
score is the share of the mutants the tests detect (killed, or timed out).

    python benchmarks/mutation_score.py                      # the physics modules
    python benchmarks/mutation_score.py --module skmoor/numerics/roots.py \\
        --tests tests/numerics/test_roots.py                  # one module, its tests
    python benchmarks/mutation_score.py --report WORKDIR     # the score of a finished run

Nothing is written into this repository: the copy is made in --workdir (default: a new
temporary folder, kept so that ``mutmut results`` / ``mutmut show NAME`` can be run there
afterwards). The full set takes hours on two cores (each mutant runs its module's tests):
this is a benchmark, never part of the test suite. The issue's aim is 90 %.

Two scores are printed: of all mutants, and of those that change more than the text of a
message (mutmut also rewrites the strings of ``raise`` and ``warn``: "XXtextXX", upper
case; no test should pin an error's exact wording, so those survive by design).
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# the physics, each with the tests that mirror it (tests/<subpackage>/)
PHYSICS = {
    "skmoor/lines/laws.py": ["tests/lines/test_laws.py", "tests/lines/test_user_law.py",
                             "tests/lines/test_creep.py",
                             "tests/lines/test_laws_closed_forms.py"],
    "skmoor/lines/catenary.py": ["tests/lines/test_catenary_limits.py",
                                 "tests/lines/test_catenary_closed_forms.py",
                                 "tests/lines/test_catenary.py",
                                 "tests/lines/test_curve_catenary.py",
                                 "tests/lines/test_chain_statics.py"],
    "skmoor/lines/cable_forms.py": ["tests/lines/test_cable_forms.py",
                                    "tests/lines/test_line_statics.py",
                                    "tests/lines/test_laws.py"],
    "skmoor/sea/seabed.py": ["tests/sea/test_seabed.py", "tests/sea/test_bathymetry.py",
                             "tests/sea/test_seabed_static_friction.py",
                             "tests/sea/test_seabed_closed_forms.py",
                             "tests/io/test_bathymetry_case.py"],
    "skmoor/sea/hydro.py": ["tests/sea/test_hydro.py", "tests/sea/test_hydro_closed_forms.py",
                            "tests/test_blind_spots.py"],
    "skmoor/sea/waves.py": ["tests/sea/test_wave_closed_forms.py", "tests/sea/test_waves.py",
                            "tests/test_blind_spots.py"],
    "skmoor/bodies/restoring.py": ["tests/bodies/test_restoring.py",
                                   "tests/bodies/test_exact_body_terms.py",
                                   "tests/bodies/test_large_rotations.py",
                                   "tests/bodies/test_rotations_setting.py",
                                   "tests/bodies/test_body.py",
                                   "tests/solvers/test_compiled_step.py"],
}

DETECTED = ("killed", "timeout", "segfault", "caught by type check")
UNDETECTED = ("survived", "suspicious")
IGNORED = ("no tests", "skipped", "not checked", "check was interrupted by user")


def copy_repository(workdir: Path) -> Path:
    """The tracked files of this repository (and the working tree's edits) in workdir."""
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True,
                           check=True).stdout.decode().split("\0")
    for name in filter(None, files):
        source = ROOT / name
        if source.is_file():
            target = workdir / name
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target)
    return workdir


def configure(workdir: Path, modules: list[str], tests: list[str]):
    """[tool.mutmut] in the copy's pyproject.toml: mutate ``modules``, run ``tests``."""
    def toml_list(items):
        return "[" + ", ".join(json.dumps(i) for i in items) + "]"

    pyproject = workdir / "pyproject.toml"
    text = pyproject.read_text()
    if "[tool.mutmut]" in text:
        raise SystemExit(f"{pyproject}: has a [tool.mutmut] table already")
    pyproject.write_text(text + "\n[tool.mutmut]\n"
                         f"source_paths = [\"skmoor\"]\n"
                         f"only_mutate = {toml_list(modules)}\n"
                         f"pytest_add_cli_args_test_selection = {toml_list(tests)}\n"
                         "pytest_add_cli_args = [\"-p\", \"no:cacheprovider\", \"-q\", \"-x\", \"-n\", \"0\"]\n"
                         "also_copy = [\"benchmarks\", \"examples\", \"meshes\", \"docs\", \"README.md\"]\n")


def statuses(workdir: Path, messages=False) -> dict[str, Counter]:
    """{module: Counter(status)} from mutmut's records (mutants/**/*.py.meta); with
    ``messages``, the mutants that change only string literals (error texts, dtype names:
    :func:`text_only_mutants`) are left out."""
    from mutmut.stats import status_by_exit_code

    out = {}
    for meta in sorted((workdir / "mutants").rglob("*.py.meta")):
        module = str(meta.relative_to(workdir / "mutants"))[: -len(".meta")]
        data = json.loads(meta.read_text())
        skip = text_only_mutants(meta.with_suffix("")) if messages else set()
        out[module] = Counter(status_by_exit_code[code]
                              for key, code in data.get("exit_code_by_key", {}).items()
                              if key.rsplit(".", 1)[-1] not in skip)
    return out


def text_only_mutants(source: Path) -> set[str]:
    """Names of the mutant functions in mutmut's copy ``source`` that differ from their
    original (``<name>__mutmut_orig``) only in the text of a message: a string in a
    ``raise`` statement, a ``warn(...)`` call or a checker's call (``check_positive("Seabed.
    depth", x)``: the field its error names); other strings, keys and names, count."""
    import ast

    class Blank(ast.NodeTransformer):
        """Blanks the strings of messages."""

        def visit_Raise(self, node):
            return _blank_strings(node)

        def visit_Call(self, node):
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if name == "warn" or name.startswith(("check_", "_check_", "_fail")):
                return _blank_strings(node)  # a warning, or a checker's field name
            return self.generic_visit(node)

    def _blank_strings(node):
        for child in ast.walk(node):
            if isinstance(child, ast.Constant) and isinstance(child.value, str):
                child.value = ""
            elif isinstance(child, ast.Constant) and child.value is None:
                child.value = ""  # mutmut's "message -> None"
        return node

    functions = {node.name: node for node in ast.walk(ast.parse(source.read_text()))
                 if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))}

    def shape(node):
        node = Blank().visit(ast.parse(ast.unparse(node)))  # a copy, strings blanked
        body = node.body[0]
        body.name = ""
        return ast.dump(body)

    originals = {name[: -len("orig")]: shape(node) for name, node in functions.items()
                 if name.endswith("__mutmut_orig")}
    same = set()
    for name, node in functions.items():
        base, _, number = name.rpartition("__mutmut_")
        if number.isdigit() and originals.get(base + "__mutmut_") == shape(node):
            same.add(name)
    return same


def report(found: dict[str, Counter]) -> float | None:
    """Print each module's and the total score; returns the total (None: nothing run)."""
    total = Counter()
    print(f"{'module':40s} {'mutants':>8s} {'detected':>9s} {'survived':>9s} {'score':>7s}")
    for module, counts in found.items():
        total += counts
        _line(module, counts)
    if not total:
        print("no mutants were checked")
        return None
    return _line("total", total)


def _line(name, counts) -> float | None:
    detected = sum(counts[s] for s in DETECTED)
    missed = sum(counts[s] for s in UNDETECTED)
    score = detected / (detected + missed) if detected + missed else None
    ignored = sum(counts[s] for s in IGNORED)
    print(f"{name:40s} {sum(counts.values()):8d} {detected:9d} {missed:9d} "
          f"{'-' if score is None else f'{100 * score:6.1f}%':>7s}"
          + (f"  ({ignored} without tests or not run)" if ignored else ""))
    return score


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--module", action="append", help="a module to mutate (repeat; default: "
                   "the physics modules)")
    p.add_argument("--tests", action="append", help="a test file or folder to run (repeat; "
                   "default: the tests that mirror the modules)")
    p.add_argument("--workdir", help="folder for the copy (default: a new temporary one)")
    p.add_argument("--max-children", type=int, default=os.cpu_count() or 1,
                   help="mutants run at once (default: one per core)")
    p.add_argument("--report", metavar="WORKDIR", help="only print the score of the run "
                   "kept in WORKDIR")
    args = p.parse_args(argv)
    try:
        import mutmut  # noqa: F401
    except ImportError:
        raise SystemExit("mutation_score: needs mutmut (pip install 'skmoor[mutation]')") from None
    if args.report:
        score = report(statuses(Path(args.report)))
        print("\nleaving out the mutants that change only string literals (message texts):")
        report(statuses(Path(args.report), messages=True))
        return 0 if score is not None else 1
    modules = args.module or list(PHYSICS)
    tests = args.tests or sorted({t for m in modules for t in PHYSICS.get(m, [])})
    if not tests:
        raise SystemExit("mutation_score: give --tests for modules outside the physics list")
    workdir = Path(args.workdir or tempfile.mkdtemp(prefix="skmoor-mutation-"))
    workdir.mkdir(parents=True, exist_ok=True)
    copy_repository(workdir)
    configure(workdir, modules, tests)
    print(f"mutation_score: mutating {', '.join(modules)} in {workdir}; tests: "
          f"{' '.join(tests)}", flush=True)
    env = {**os.environ, "PYTHONPATH": ""}  # the copy's skmoor (mutmut's mutants/), not ours
    run = subprocess.run([sys.executable, "-m", "mutmut", "run", "--max-children",
                          str(args.max_children)], cwd=workdir, env=env, check=False)
    score = report(statuses(workdir))
    print("\nleaving out the mutants that change only string literals (message texts):")
    report(statuses(workdir, messages=True))
    print(f"kept in {workdir} (`cd {workdir} && mutmut results` lists the survivors)")
    return run.returncode if score is not None else 1


if __name__ == "__main__":
    sys.exit(main())
