"""Physically impossible input refused and suspicious input warned about, with the
numbers, before anything is solved (skmoor.coupling.checks), for networks, cases and decks."""
import re
from pathlib import Path

import pytest

import skmoor
from skmoor.coupling.checks import check_network
from skmoor.lines.line import LineType

CHAIN = LineType(EA=5e8, mass=100.0, diameter=0.1)


def network(anchor=(-120.0, 0.0, -80.0), length=150.0, top=(0.0, 0.0, -5.0), **kw):
    points = [skmoor.Point("anchor", "fixed", anchor),
              skmoor.Point("fairlead", "coupled", top)]
    return skmoor.Network(points, [skmoor.MooringLine("leg", CHAIN, "anchor", "fairlead",
                                                      length, 10)], depth=100.0, **kw)


def test_a_sound_network_passes_silently():
    assert check_network(network()) == []


def test_a_point_below_the_bed_is_refused():
    with pytest.raises(ValueError, match=r"point anchor: z = -130 m is below the sea bed"):
        check_network(network(anchor=(-120.0, 0.0, -130.0)))


def test_a_line_far_too_short_is_refused_and_a_stretched_one_warned():
    span = (120.0**2 + 75.0**2) ** 0.5  # 141.5 m
    with pytest.raises(ValueError, match=r"line leg: its ends are 141\.51 m apart, 34 % more"):
        check_network(network(length=span / 1.34))
    warned = check_network(network(length=span / 1.05))
    assert len(warned) == 1 and re.search(r"5\.0 % more than its length", warned[0])


def test_an_anchor_above_the_water_and_above_its_fairlead_is_warned():
    warned = check_network(network(anchor=(-20.0, 0.0, 20.0), length=40.0))
    assert any("point anchor: a fixed point (an anchor?) 20 m above the water" in w
               for w in warned)
    assert any("anchor anchor (z = 20 m) is above its fairlead fairlead (z = -5 m)" in w
               for w in warned)


def test_a_current_with_nothing_to_act_on_is_warned():
    sea = skmoor.Sea(100.0, current=skmoor.Current(1.0))
    warned = check_network(network(sea=sea))
    assert warned and "the current acts on nothing" in warned[0]
    dragged = LineType(EA=5e8, mass=100.0, diameter=0.1, Cd_n=1.2)
    net = network(sea=sea)
    net.lines[0].line_type = dragged
    assert check_network(net) == []


def test_a_deck_line_too_short_is_refused_at_its_deck_line(tmp_path):
    """(A line to a free point is not checked: the build settles the point first.)"""
    text = Path("examples/decks/chain_50m.dat").read_text().replace(
        "1   chain     1        2        410.0", "1   chain     1        2        300.0")
    path = tmp_path / "short.dat"
    path.write_text(text)
    with pytest.raises(ValueError, match=r"short\.dat line \d+: LINES 1: .*more than its length"):
        skmoor.build(path)


def test_a_case_with_an_anchor_above_the_water_warns(tmp_path):
    """The case's network tables are checked (the build would go on to its statics)."""
    from skmoor.model.from_case import explicit_network

    text = Path("examples/network_buoy.toml").read_text().replace(
        "position = [560.0, 0.0, -160.0]", "position = [60.0, 0.0, 20.0]")
    path = tmp_path / "case.toml"
    path.write_text(text)
    warned = check_network(explicit_network(skmoor.Case.from_toml(path)))
    assert any("leg1.anchor: a fixed point (an anchor?) 20 m above the water" in w
               for w in warned)


def test_a_model_too_big_for_memory_is_refused_before_allocating(monkeypatch):
    from skmoor.coupling import checks

    monkeypatch.setattr(checks, "available_memory", lambda: 8 * 2**30)
    net = network()
    net.lines[0].n_elements = 10**6  # 3 million unknowns: 11 GiB at 4 kB each
    with pytest.raises(ValueError, match=r"n_elements: 1000000 elements on 1 lines need about "
                                         r"11\.4 GiB, this machine has 8 GiB"):
        check_network(net)
    net.lines[0].n_elements = 10**4
    assert check_network(net) == []


def test_a_long_line_on_a_body_needs_no_n_squared_memory():
    """The sparse residual of a body on 4 x 1500 elements (18,000 unknowns) stays far
    below the 2.6 GB an (n, n) array would take (a dense body block used to be made)."""
    import tracemalloc

    import numpy as np

    model = skmoor.build(skmoor.paper_case().replace("mooring.n_elements", 1500))
    system = model.system
    x, v = np.zeros(system.n), np.zeros(system.n)
    v[system.nf:] = [0.1, 0.0, 0.05, 0.0, 0.01, 0.0]  # a moving body: the slope columns too
    tracemalloc.start()
    _, K, _Kv = system.residual(x, v, 0.0, layout="sparse")
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert system.n > 17_000 and K.shape == (system.n, system.n)
    assert peak < 100e6
