"""Off-screen pictures and animations: frame counts, content, colours, headless use."""
import dataclasses
import os
import subprocess
import sys
from pathlib import Path

import imageio.v2 as iio2
import imageio.v3 as iio
import numpy as np
import pytest
from _synthetic import synthetic_results

from skmoor.post import render

SIZE = (320, 240)


@pytest.fixture(scope="module")
def results():
    return synthetic_results()


def _rgb(path):
    return iio.imread(path)[..., :3].astype(float)


def test_snapshot_cameras(results, tmp_path):
    images = {}
    for camera in render.CAMERAS:
        path = render.snapshot(results, 5, tmp_path / f"{camera}.png", camera=camera,
                               window_size=SIZE)
        images[camera] = _rgb(path)
        assert images[camera].shape == (SIZE[1], SIZE[0], 3)
        assert images[camera].std() > 20, f"{camera} frame looks blank"
    names = list(images)
    for a, b in zip(names, names[1:]):
        assert np.abs(images[a] - images[b]).mean() > 1, f"{a} and {b} look the same"


def test_time_and_scale_labels(results, tmp_path):
    first = _rgb(render.snapshot(results, 0, tmp_path / "a.png", window_size=SIZE))
    later = _rgb(render.snapshot(results, 10, tmp_path / "b.png", window_size=SIZE))
    scaled = _rgb(render.snapshot(results, 10, tmp_path / "c.png", scale=50,
                                  window_size=SIZE))
    corner = np.s_[:25, :100]                          # "t = ... s"
    assert np.abs(first[corner] - later[corner]).max() > 100
    black = np.s_[-18:, SIZE[0] // 2:]                 # "displacements x 50"
    assert (later[black].max(axis=-1) < 60).sum() == 0
    assert (scaled[black].max(axis=-1) < 60).sum() > 20


def test_colour_follows_tension(results, tmp_path):
    """Two states with the same geometry, low and high tension, on one colour range:
    the lines go from the bottom (blue-purple) to the top (yellow) of the colour map."""
    two = results.truncated(2)
    two = dataclasses.replace(two, displacement=np.zeros_like(two.displacement),
                              body=np.zeros_like(two.body),
                              tension=np.ones_like(two.tension) * [[2e5], [1e6]])
    low = _rgb(render.snapshot(two, 0, tmp_path / "low.png", camera="side", window_size=SIZE))
    high = _rgb(render.snapshot(two, 1, tmp_path / "high.png", camera="side",
                                window_size=SIZE))
    scene = np.s_[30:, : int(0.84 * SIZE[0])]          # leave out the time and the bar
    low, high = low[scene], high[scene]
    line = np.abs(low - high).max(axis=-1) > 30        # pixels that changed: the lines
    assert line.sum() > 100

    def yellow(img):
        return (img[..., 0] > 170) & (img[..., 1] > 150) & (img[..., 2] < 120)

    assert yellow(high[line]).mean() > 0.3
    assert yellow(low[line]).mean() == 0
    assert (low[line][:, 2] > low[line][:, 0]).mean() > 0.5     # blue over red


def test_animate_gif(results, tmp_path):
    n = render.animate(results, tmp_path / "run.gif", every=4, window_size=SIZE)
    frames = iio.imread(tmp_path / "run.gif", index=None)
    assert n == len(range(0, len(results.t), 4)) == len(frames)
    assert frames.shape[1:3] == (SIZE[1], SIZE[0])
    assert min(frame[..., :3].std() for frame in frames) > 20
    assert np.abs(frames[0].astype(float) - frames[3]).mean() > 0.1


def test_gif_colour_bar_is_continuous(results, tmp_path):
    """The GIF's colour bar keeps its gradient (one palette for the run, dithered): along
    the bar, smoothed over 9 rows, the colour changes on most rows, as in the true-colour
    snapshot. A GIF quantized per frame without dithering (pyvista's own writer) bands the
    bar into ~5 steps: over 80 % of its rows flat, steps of 12 levels."""
    from scipy.ndimage import uniform_filter1d

    size = (480, 360)
    true = _rgb(render.snapshot(results, 0, tmp_path / "true.png", window_size=size))
    render.animate(results, tmp_path / "run.gif", every=8, window_size=size, progress=False)
    gif = iio.imread(tmp_path / "run.gif", index=None)[0][..., :3].astype(float)
    saturation = true.max(axis=2) - true.min(axis=2)
    right = np.arange(int(0.75 * size[0]), size[0])
    x = int(right[np.argmax([(saturation[:, c] > 80).sum() for c in right])])
    rows = np.flatnonzero(saturation[:, x] > 80)
    assert len(rows) > 0.3 * size[1]  # the bar, found in the snapshot
    bar = np.s_[rows.min() + 3:rows.max() - 3, x - 1:x + 2]

    def steps(image):
        along = uniform_filter1d(image[bar].mean(axis=1), 9, axis=0)
        return np.abs(np.diff(along, axis=0)).sum(axis=1)

    assert (steps(true) < 0.5).mean() < 0.05
    assert (steps(gif) < 0.5).mean() < 0.6 and steps(gif).max() < 9


def test_animate_mp4_real_time_default(results, tmp_path):
    # samples every 0.2 s at 5 frames per second: every sample, in real time
    n = render.animate(results, tmp_path / "run.mp4", fps=5, window_size=SIZE, progress=False)
    assert n == len(results.t)
    reader = iio2.get_reader(tmp_path / "run.mp4")
    assert reader.count_frames() == n
    assert reader.get_meta_data()["fps"] == 5
    assert reader.get_data(n // 2).std() > 20
    reader.close()


def test_animate_mode(results, tmp_path):
    shape = np.zeros_like(results.points)
    shape[:, 1] = np.sin(np.pi * np.tile(np.linspace(0, 1, 12), 4))
    n = render.animate_mode(results.points, results.cells, shape, 3.0, tmp_path / "mode.gif",
                            n_frames=8, window_size=SIZE)
    frames = iio.imread(tmp_path / "mode.gif", index=None)
    assert n == 8 == len(frames)
    assert np.abs(frames[2].astype(float) - frames[6]).mean() > 0.1   # +/- the shape


def test_default_scale(results):
    size = np.linalg.norm(np.ptp(results.points, axis=0))
    for factor in (1e-3, 0.1, 1.0):
        small = dataclasses.replace(results, displacement=factor * results.displacement)
        largest = np.linalg.norm(small.displacement, axis=-1).max()
        scale = render.default_scale(small)
        assert scale / 10 ** np.floor(np.log10(scale)) in {1, 2, 5}
        assert 0.02 * size < scale * largest <= 0.05 * size
    assert render.default_scale(dataclasses.replace(results,
                                                    displacement=100 * results.displacement)) == 1


@pytest.mark.parametrize("call, message", [
    (lambda r, d: render.snapshot(r, 41, d / "a.png"), "i=41"),
    (lambda r, d: render.snapshot(r, 0, d / "a.png", camera="bird"), "camera"),
    (lambda r, d: render.snapshot(r, 0, d / "a.jpg"), "path"),
    (lambda r, d: render.snapshot(r, 0, d / "a.png", scale=0), "scale"),
    (lambda r, d: render.animate(r, d / "a.avi"), "path"),
    (lambda r, d: render.animate(r, d / "a.gif", every=0), "every"),
    (lambda r, d: render.animate(r, d / "a.gif", fps=0), "fps"),
])
def test_bad_input(results, tmp_path, call, message):
    with pytest.raises(ValueError, match=message):
        call(results, tmp_path)


def test_headless_and_not_imported_by_the_core(tmp_path):
    """A fresh process without a display renders; the core modules do not load pyvista."""
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    tests = Path(__file__).parents[1]
    env["PYTHONPATH"] = os.pathsep.join([str(tests.parent), str(tests)])
    code = (
        "import sys\n"
        "import skmoor.post.export, skmoor.post.plots, skmoor.post.results\n"
        "assert 'pyvista' not in sys.modules\n"
        "from _synthetic import synthetic_results\n"
        "from skmoor.post import render\n"
        f"render.snapshot(synthetic_results(nt=2), 1, {str(tmp_path / 'x.png')!r}, "
        "window_size=(160, 120))\n"
    )
    subprocess.run([sys.executable, "-c", code], env=env, check=True, timeout=120)
    assert _rgb(tmp_path / "x.png").std() > 20


def test_free_surface_moves_the_water(results, tmp_path):
    """surface=elevation(xy, t): the water grid sits on the given elevation at the frame's
    time (a 3 m crest along x changes the picture; a flat sea is the default water)."""
    crest = 3.0

    def wave(xy, t):
        return crest * np.cos(0.05 * xy[:, 0] - 0.5 * t)

    scene = render._RunScene(results, "iso", 1.0, (320, 240), surface=wave)
    try:
        scene.show(3)
        water = scene.water.points
        np.testing.assert_allclose(water[:, 2], wave(water[:, :2], results.t[3]), atol=1e-5)  # float32
    finally:
        scene.plotter.close()
    flat = render.snapshot(results, 3, tmp_path / "flat.png", window_size=(320, 240))
    waves = render.snapshot(results, 3, tmp_path / "waves.png", window_size=(320, 240),
                            surface=wave)
    assert np.abs(_rgb(flat) - _rgb(waves)).mean() > 0.1  # translucent water: 0.25 seen
    with pytest.raises(ValueError, match="surface"):
        render.snapshot(results, 3, tmp_path / "bad.png", surface=3.0)
