"""Physically impossible input refused and suspicious input warned about, with the
numbers, before anything is solved (skmoor.checks), for networks, cases and decks."""
import re

import pytest

import skmoor
from skmoor.checks import check_network
from skmoor.line import LineType

CHAIN = LineType(EA=5e8, mass=100.0, diameter=0.1)
DECK = "tests/decks/network/two_segment.dat"


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
    text = open(DECK).read().replace("1   chain      1        2        400.0",
                                     "1   chain      1        2        150.0")
    path = tmp_path / "short.dat"
    path.write_text(text)
    with pytest.raises(ValueError, match=r"short\.dat line \d+: LINES 1: .*more than its length"):
        skmoor.build(path)


def test_a_case_with_an_anchor_above_the_water_warns(tmp_path):
    """The case's network tables are checked (the build would go on to its statics)."""
    from skmoor.model import explicit_network

    text = open("examples/network_buoy.toml").read().replace(
        "position = [560.0, 0.0, -160.0]", "position = [60.0, 0.0, 20.0]")
    path = tmp_path / "case.toml"
    path.write_text(text)
    warned = check_network(explicit_network(skmoor.Case.from_toml(path)))
    assert any("leg1.anchor: a fixed point (an anchor?) 20 m above the water" in w
               for w in warned)
