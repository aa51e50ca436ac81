"""The examples run (as scikit-fem's do) and their numbers hold physics."""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).parents[1] / "examples"


def load(name, monkeypatch=None, **env):
    for key, value in env.items():
        monkeypatch.setenv(key, value)
    spec = importlib.util.spec_from_file_location(name.replace(".py", ""), EXAMPLES / name)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_static_line_converges_to_catenary_at_second_order():
    """Example 01: FE fairlead tension -> analytic elastic catenary, order 2, < 0.1 % at 20."""
    ex = load("01_static_line.py")
    assert -ex.order == pytest.approx(2.0, abs=0.15)
    assert ex.errors[ex.elements.index(20)] < 1e-3


def test_drag_form_damps_the_coupled_response(monkeypatch):
    """Example 03 (20 s): the user's follower drag form, residual alone, lowers surge and
    fairlead tension amplitudes; its histories are those of the built-in drag kernel
    (skmoor.sea.hydro, hand-written, the same Cd) to 1e-8 (the same drag on the reference
    tangent is 5e-5 away: the follower part is what is checked); its automatic tangents
    pass the Taylor test (slopes 2)."""
    pytest.importorskip("jax", reason="the example's form uses the automatic tangents")
    ex = load("03_weak_form_drag.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="20")
    assert ex.drag[0] < 0.95 * ex.plain[0]
    assert ex.drag[1] < 0.95 * ex.plain[1]
    assert type(ex.builtin_term).__name__ == "LineHydroKernel"
    assert ex.drag_term.path == "compiled" and ex.drag_term.stiffness is None
    t = ex.builtin_run.t
    assert len(t) == len(ex.user_run.t) > 100 and np.array_equal(t, ex.user_run.t)
    for series in (lambda r: r.body_series("surge"), lambda r: r.fairlead_tension,
                   lambda r: r.body_series("pitch")):
        user, builtin = series(ex.user_run), series(ex.builtin_run)
        assert np.max(np.abs(user - builtin)) < 1e-8 * np.max(np.abs(builtin))
    assert ex.drag == pytest.approx(ex.builtin, rel=1e-8)
    assert ex.tangent.slope_u == pytest.approx(2.0, abs=0.1)
    assert ex.tangent.slope_v == pytest.approx(2.0, abs=0.1)


def test_paper_case_example_matches_the_papers_draft(monkeypatch):
    """Example 02 (shortened): draft of Eq. 1 near the paper's 0.896 m; surge follows the load."""
    ex = load("02_paper_case.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="20")
    assert ex.model.draft == pytest.approx(0.896, rel=5e-3)
    assert ex.info["amplitude"]["surge"] > 10 * ex.info["amplitude"]["heave"]


def test_export_and_animation_example_writes_files(monkeypatch, tmp_path):
    """Example 04 (shortened): ParaView files, snapshot, run and mode GIFs exist."""
    import imageio.v3 as iio

    ex = load("04_export_and_animation.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="4",
              SKMOOR_EXAMPLE_OUT=str(tmp_path))
    assert ex.xdmf.with_suffix(".h5").exists() and ex.pvd.exists() and ex.mode_pvd.exists()
    assert len(iio.imread(tmp_path / "run.gif", index=None)) == ex.frames
    assert len(iio.imread(tmp_path / "mode1.gif", index=None)) == ex.mode_frames == 24


def test_parameter_studies_example_shows_the_papers_surge_trends(monkeypatch, tmp_path):
    """Example 05 (3 points, 60 s): surge falls as d/l falls (the paper's Fig. 7 trend)."""
    ex = load("05_parameter_studies.py", monkeypatch, SKMOOR_EXAMPLE_POINTS="3",
              SKMOOR_EXAMPLE_DURATION="60", SKMOOR_EXAMPLE_OUT=str(tmp_path))
    sag = sorted(ex.by_study["sag-ratio"], key=lambda r: r["value"])
    assert not any(r["error"] for r in ex.rows)
    assert sag[0]["surge"] < sag[-1]["surge"]  # smaller d/l (tauter lines): smaller surge
    assert (tmp_path / "sweep.csv").exists()


def test_moordyn_deck_example_heaves_the_chain(monkeypatch, tmp_path):
    """Example 06 (30 s): the deck's static fairlead tension within 2 % of OrcaFlex's
    991.6 kN, a tension swing of over 100 kN under the 2 m heave, and the plot written."""
    ex = load("06_moordyn_deck.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="30",
              SKMOOR_EXAMPLE_OUT=str(tmp_path))
    assert ex.tension[0] == pytest.approx(991.6e3, rel=0.02)
    assert np.ptp(ex.tension[ex.results.t >= 20.0]) > 1e5
    assert (tmp_path / "chain_heave.png").stat().st_size > 10_000


@pytest.mark.slow  # about 15 s on a quiet machine, 35 s under load
def test_box_in_jonswap_example(monkeypatch, tmp_path):
    """Example 08 (120 s of Hs 2 m, Tp 8 s): the box's heave and pitch records follow the
    linear frequency-domain response of the whole linearized network to the same 200
    wave components (same phases): correlated above 0.8 (a wrong phase or sign of the
    excitation drops it to about zero or below), standard deviations within 15 % (not
    closer: the run is short, surge's 8 s mode has not settled, and a 2 m sea on a 0.9 m
    draft swings the fairlead tensions by +-35 %, far from linear)."""
    ex = load("08_box_in_jonswap.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="120",
              SKMOOR_EXAMPLE_OUT=str(tmp_path))
    for name in ("heave (m)", "pitch (deg)"):
        assert ex.correlation[name] > 0.8, name
        assert ex.std_time[name] == pytest.approx(ex.std_linear[name], rel=0.15), name
    for picture in ("motions.png", "tension_spectra.png", "run.gif"):
        assert (tmp_path / picture).exists()


def test_host_loop_example(monkeypatch, tmp_path):
    """Example 10 (10 s): the host loop on skmoor.moordyn; the run continued from the
    checkpoint repeats the uninterrupted one to 1e-12 of the tension; the body swings the
    tension by more than 100 kN; the static tension is MoorDyn's within 1.5 % (the two
    discretizations of the chain on its bed, tests/run/test_host.py)."""
    monkeypatch.chdir(tmp_path)
    ex = load("10_host_loop.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="10")
    assert np.max(np.abs(ex.again - ex.second)) <= 1e-12 * ex.static
    assert np.ptp(ex.tension) > 1e5
    if ex.moordyn_itself is not None:  # MoorDyn's static tension: the discretizations' 1 %
        assert ex.static == pytest.approx(ex.static_md, rel=0.015)


def test_nonlinear_bending_example(monkeypatch, tmp_path):
    """Example 11 (3 s): the armour layers' friction moment, a form of u'' and v'' on the
    riser's bending elements, runs in the compiled step as in Python (1e-9); with a slip
    curvature far beyond the riser's it is the linear beam of EI_stick, the line type's
    bending in the hand kernel (1e-6); the law's largest curvature lies between those of
    the stick and slip beams."""
    pytest.importorskip("jax", reason="the example's form uses the generated kernel")
    ex = load("11_nonlinear_bending.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="3",
              SKMOOR_EXAMPLE_OUT=str(tmp_path))
    assert (tmp_path / "nonlinear_bending.png").is_file()
    peaks = {name: run[1] for name, run in ex.runs.items()}
    assert peaks["stick"].max() < peaks["law"].max() < peaks["slip"].max()
    slow = ex.run(ex.models["law"], compiled=False)[1]
    assert np.abs(slow - peaks["law"]).max() < 1e-9 * peaks["law"].max()
    monkeypatch.setattr(ex, "KAPPA_SLIP", 1e3)  # (the model's field, set when it is made)
    stuck = ex.run(ex.riser(ex.EI_SLIP, ex.EI_STICK - ex.EI_SLIP))[1]
    assert np.abs(stuck - peaks["stick"]).max() < 1e-6 * peaks["stick"].max()


def test_viv_model_example(monkeypatch, tmp_path):
    """Example 12 (80 s): a user's VIV model (the phase at the Strouhal rate alone, put in
    place of the built-in lift with Network.viv_lift) moves the riser at cF U / d (2 %);
    Thorsen's built-in lift, in step with the motion, drives a standing wave (its rms at
    the middle node under a quarter of the antinodes') three times the Strouhal
    forcing's, whose phases spread along the riser give a travelling wave (rms within
    10 % from a quarter to three quarters of the height)."""
    pytest.importorskip("jax", reason="the user's lift runs as a generated form")
    ex = load("12_viv_model.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="80",
              SKMOOR_EXAMPLE_OUT=str(tmp_path))
    assert (tmp_path / "viv_model.png").is_file()
    f, rms = ex.stats["Strouhal rate"]
    assert f == pytest.approx(ex.CF * ex.U / ex.D, rel=0.02)
    middle = rms[ex.ELEMENTS // 4: 3 * ex.ELEMENTS // 4 + 1]
    assert middle.max() < 1.1 * middle.min()
    _, thorsen = ex.stats["Thorsen (built-in)"]
    assert thorsen[ex.ELEMENTS // 2] < 0.25 * thorsen.max()
    assert thorsen.max() > 3 * rms.max()
