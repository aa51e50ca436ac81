"""Saves what gallery examples print or draw into their own folders, for their pages.

Runs each example in EXAMPLES with its default settings (``python examples/NAME.py``):
its standard output goes to ``docs/gallery_output/NAME.txt`` (the docs hook shows it under
"Output" on the example's page), and the pictures PICTURES names are copied from the
folder it writes into ``docs/images/`` (the hook's EXTRA_IMAGES lists them). Rerun after
changing one of those examples:

    python docs/make_gallery_output.py [NAME ...]
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ("03_weak_form_drag", "08_box_in_jonswap", "10_host_loop")
PICTURES = {  # example: {the file it writes (its folder's): the name in docs/images}
    "08_box_in_jonswap": {"box-in-jonswap/motions.png": "jonswap_motions.png",
                          "box-in-jonswap/tension_spectra.png": "jonswap_tension_spectra.png"},
}


def save(name: str) -> Path:
    """Runs examples/NAME.py in a scratch folder and saves its output and pictures."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    env.pop("SKMOOR_EXAMPLE_DURATION", None)  # the example's own duration
    env.pop("SKMOOR_EXAMPLE_OUT", None)
    with tempfile.TemporaryDirectory() as scratch:
        run = subprocess.run([sys.executable, str(ROOT / "examples" / f"{name}.py")],
                             cwd=scratch, env=env, capture_output=True, text=True,
                             check=False)
        if run.returncode:
            raise SystemExit(f"examples/{name}.py failed:\n{run.stderr[-2000:]}")
        for written, kept in PICTURES.get(name, {}).items():
            shutil.copyfile(Path(scratch) / written, ROOT / "docs" / "images" / kept)
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
