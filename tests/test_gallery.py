"""Every page of the documentation's gallery shows what its example makes: a picture from
docs/images or the text it prints (docs/gallery_output, saved by docs/make_gallery_output.py).
"""
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def hook():
    spec = importlib.util.spec_from_file_location("skmoor_docs", ROOT / "docs/hooks/skmoor_docs.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("example", sorted(p.stem for p in (ROOT / "examples").glob("[0-9]*.py")))
def test_every_gallery_page_shows_an_output(example):
    page = hook()._example_page(ROOT / "examples" / f"{example}.py", ROOT / "docs" / "images")
    assert "](../images/" in page or "## Output" in page, example


def test_saved_output_leaves_out_moordyns_own_log():
    spec = importlib.util.spec_from_file_location("make", ROOT / "docs/make_gallery_output.py")
    make = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make)
    text = ("skmoor: 1\n\n Running MoorDyn (v2.7.2)\nGenerated entities:\n\tnLines = 1\n"
            "Water kinematics for runtime:\n   No Waves or Currents, or set externally\n"
            "MoorDyn: 2\n")
    assert make.without_moordyn_log(text) == "skmoor: 1\n\nMoorDyn: 2\n"
