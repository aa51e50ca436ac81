"""`skmoor run` returns with its numbers and renders the animations in the background.

Independent check: the files the background process writes (read back as images and
videos by imageio, their frame counts against the run's samples) and the output lock it
holds while it writes (a second run into the folder is refused meanwhile).
"""
import time

import imageio.v3 as iio
import pytest

from skmoor import cli
from skmoor.run.outputs import LOCK, output_lock


def _wait_for(path, seconds=300):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if path.exists() and not (path.parent / LOCK).exists():
            return True
        time.sleep(0.5)
    return False


def test_run_renders_in_the_background_and_holds_the_folder(tmp_path, capsys):
    out = tmp_path / "run"
    assert cli.main(["run", "--out", str(out), "--duration", "4", "--output-interval",
                     "0.2", "--no-export", "--quiet"]) == 0
    said = capsys.readouterr().out
    assert "in the background" in said and "render.log" in said
    assert (out / "summary.json").exists()  # the numbers are there at once
    started = time.monotonic()
    while not (out / LOCK).exists() and not (out / "animation.gif").exists():
        assert time.monotonic() - started < 60, (out / "render.log").read_text()
        time.sleep(0.1)
    if (out / LOCK).exists():  # still rendering: a run into the folder is refused
        with pytest.raises(ValueError, match="is writing there"):
            with output_lock(out):
                pass
    assert _wait_for(out / "animation.gif"), (out / "render.log").read_text()
    assert iio.imread(out / "snapshot.png").ndim == 3
    frames = iio.imread(out / "animation.gif", index=None)
    assert len(frames) == 21  # the run's 21 samples, every one (fewer than 80)
