"""Figures of time histories and parameter studies."""
from pathlib import Path

import imageio.v3 as iio
import pytest
from _synthetic import synthetic_results

from skmoor.post.plots import plot_study, plot_time_histories

ROWS = [dict(value=1 / n, surge=1.0 + 0.01 * n, heave=0.1 - 0.0005 * n, pitch=0.002 * n,
             max_tension_steady=6e5 + 1e3 * n) for n in (80, 45, 60)]


def _check_png(path, size):
    image = iio.imread(path)
    assert image.shape[:2] == (size[1], size[0])
    assert image[..., :3].std() > 10                  # not blank


def test_time_histories(tmp_path):
    path = plot_time_histories(synthetic_results(), tmp_path / "fig" / "th.png",
                               title="synthetic", figsize=(8, 9), dpi=50)
    _check_png(path, (400, 450))


def test_study(tmp_path):
    path = plot_study(ROWS, tmp_path / "study.png", "sag-to-span ratio d/l [-]",
                      figsize=(9, 7), dpi=50)
    _check_png(path, (450, 350))


def test_study_bad_rows(tmp_path):
    with pytest.raises(ValueError, match="max_tension_steady"):
        plot_study([{k: v for k, v in ROWS[0].items() if k != "max_tension_steady"}],
                   tmp_path / "s.png", "x")
    with pytest.raises(ValueError, match="rows is empty"):
        plot_study([], tmp_path / "s.png", "x")


def test_bad_suffix(tmp_path):
    with pytest.raises(ValueError, match="path"):
        plot_time_histories(synthetic_results(), tmp_path / "th.jpg")


def test_a_network_without_bodies_plots_its_line_tensions(tmp_path):
    """A deck of lines and points only: the CLI's plot shows each line's end tensions
    (the body panels would be empty), written as a PNG of a real size."""
    import skmoor
    from skmoor.post.plots import plot_line_tensions

    model = skmoor.build(Path(__file__).parents[1] / "decks" / "network" / "clump_weight.dat")
    results = skmoor.simulate(model, duration=1.0, progress=False)
    assert not results.body_names
    path = plot_line_tensions(results, tmp_path / "tensions.png")
    assert path.stat().st_size > 10_000
