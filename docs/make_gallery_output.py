"""Saves what the gallery's text-only examples print, for their documentation pages.

Runs each example in EXAMPLES with its default settings (``python examples/NAME.py``) and
writes its standard output to ``docs/gallery_output/NAME.txt``; the docs hook shows that
file under "Output" on the example's page. Rerun after changing one of those examples:

    python docs/make_gallery_output.py [NAME ...]
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ("03_weak_form_drag", "10_host_loop")  # the examples that draw no picture


def save(name: str) -> Path:
    """Runs examples/NAME.py from the repository root and saves its output."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    env.pop("SKMOOR_EXAMPLE_DURATION", None)  # the example's own duration
    run = subprocess.run([sys.executable, str(ROOT / "examples" / f"{name}.py")], cwd=ROOT,
                         env=env, capture_output=True, text=True, check=False)
    if run.returncode:
        raise SystemExit(f"examples/{name}.py failed:\n{run.stderr[-2000:]}")
    path = ROOT / "docs" / "gallery_output" / f"{name}.txt"
    path.write_text(without_moordyn_log(run.stdout))
    return path


def without_moordyn_log(text: str) -> str:
    """The output less what MoorDyn's library prints on its own while it sets up (from
    its banner to its note on the run's water kinematics)."""
    kept, inside, runtime = [], False, False
    for line in text.splitlines():
        if "Running MoorDyn (" in line:
            inside = True
        if not inside:
            kept.append(line)
        elif line.startswith("Water kinematics for runtime"):
            runtime = True
        elif runtime and line.startswith("   "):  # its last note
            inside = runtime = False
    return "\n".join(kept).strip() + "\n"


if __name__ == "__main__":
    for name in sys.argv[1:] or EXAMPLES:
        print("wrote", save(name))
