"""MkDocs hooks of skmoor's documentation (mkdocs.yml: ``hooks:``).

- The gallery: one page per ``examples/*.py``, made at build time from the file itself
  (its docstring, its source included by pymdownx.snippets, its pictures from
  ``docs/images/``, what it prints from ``docs/gallery_output/``), listed in the nav under
  "Gallery". The examples are not run.
- README sections: ``<!-- readme: HEADING -->`` in a page is replaced by that section of
  README.md (up to the next heading of the same or a higher level), links into ``docs/``
  rewritten for the page; ``<!-- readme: HEADING | code -->`` by its code blocks alone,
  each with the paragraph before it. A missing heading stops the build.
- Reports: any ``docs/*.md`` the nav does not list goes under "Reports".
"""
from __future__ import annotations

import ast
import posixpath
import re
from pathlib import Path

from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File

GALLERY = "Gallery"
REPORTS = "Reports"
# Pictures of the examples kept in docs/images/ under other names than the files the
# example writes (those are found in its source: "NAME.png" with docs/images/NAME.png).
EXTRA_IMAGES = {
    "02_paper_case": ["paper_fig6.png", "paper_snapshot.png"],
    "04_export_and_animation": ["mode1_frame.png"],
    "05_parameter_studies": ["study_sag_ratio.png", "study_chord_angle.png"],
    "08_box_in_jonswap": ["jonswap_motions.png", "jonswap_tension_spectra.png"],
}
_MARKER = re.compile(r"^<!--\s*readme:\s*(.+?)\s*(\|\s*code\s*)?-->[ \t]*$", re.MULTILINE)
_PICTURE = re.compile(r"[\w.-]+\.(?:png|gif|jpg|jpeg|svg)")
_FENCE = re.compile(r"^\s*(```|~~~)")


def _root(config) -> Path:
    return Path(config.config_file_path).resolve().parent


def _examples(config) -> list[Path]:
    return sorted((_root(config) / "examples").glob("[0-9]*.py"))


def _title(stem: str) -> str:
    number, _, name = stem.partition("_")
    return f"{number} {name.replace('_', ' ').capitalize()}" if number.isdigit() else stem


def _nav_files(nav) -> set[str]:
    found = set()
    for item in nav or []:
        value = next(iter(item.values())) if isinstance(item, dict) else item
        if isinstance(value, list):
            found |= _nav_files(value)
        elif isinstance(value, str):
            found.add(value)
    return found


def on_config(config):
    root = _root(config)
    snippets = config.mdx_configs.setdefault("pymdownx.snippets", {})
    snippets["base_path"] = [str(root)]  # examples/ and README.md, wherever mkdocs runs
    nav = config.nav
    if nav is None:
        raise PluginError("mkdocs.yml: the hooks expect an explicit nav")
    for item in nav:
        if isinstance(item, dict) and GALLERY in item:
            item[GALLERY] = ["gallery/index.md"] + [
                {_title(p.stem): f"gallery/{p.stem}.md"} for p in _examples(config)]
            break
    else:
        raise PluginError(f"mkdocs.yml: the nav has no '{GALLERY}' entry")
    listed = _nav_files(nav)
    docs = Path(config.docs_dir)
    reports = [p.name for p in sorted(docs.glob("*.md")) if p.name not in listed]
    if reports:
        nav.append({REPORTS: reports})
    return config


def _docstring(path: Path) -> str:
    doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")))
    if not doc:
        raise PluginError(f"{path.name}: the example has no docstring")
    return doc


def _pictures(path: Path, images: Path) -> list[str]:
    names = list(dict.fromkeys(_PICTURE.findall(path.read_text(encoding="utf-8"))))
    names = [n for n in names if (images / n).is_file()]
    for name in EXTRA_IMAGES.get(path.stem, []):
        if not (images / name).is_file():
            raise PluginError(f"docs hook: {path.stem}'s picture docs/images/{name} is missing")
        if name not in names:
            names.append(name)
    return names


def _example_page(path: Path, images: Path) -> str:
    rel = f"examples/{path.name}"
    parts = [f"# {_title(path.stem)}", "", f"`{rel}`", "", _docstring(path), ""]
    for name in _pictures(path, images):
        parts += [f"![{name}](../images/{name})", ""]
    printed = images.parent / "gallery_output" / f"{path.stem}.txt"
    if printed.is_file():  # what a text-only example prints (docs/make_gallery_output.py)
        parts += ["## Output", "", f"What `python {rel}` prints "
                  "(saved by `docs/make_gallery_output.py`):", "", "```text",
                  printed.read_text(encoding="utf-8").rstrip(), "```", ""]
    parts += ["## Source", "", "```python", f'--8<-- "{rel}"', "```", ""]
    return "\n".join(parts)


def _index_page(examples: list[Path], images: Path) -> str:
    rows = ["# Gallery", "",
            "The scripts in `examples/`, each a short computation at module level (the tests "
            "import them with shorter runs). The pictures and printed outputs are the ones in the "
            "repository (`docs/images`, `docs/gallery_output`); the documentation build does "
            "not run the examples.", "",
            "| example | what it does |", "|---|---|"]
    for path in examples:
        first = " ".join(_docstring(path).split("\n\n")[0].split())
        pictures = _pictures(path, images)
        thumb = f" ![{pictures[0]}](../images/{pictures[0]}){{ width=240 }}" if pictures else ""
        rows.append(f"| [{_title(path.stem)}]({path.stem}.md) | {first}{thumb} |")
    return "\n".join(rows) + "\n"


def on_files(files, config):
    examples = _examples(config)
    images = Path(config.docs_dir) / "images"
    files.append(File.generated(config, "gallery/index.md", content=_index_page(examples, images)))
    for path in examples:
        files.append(File.generated(config, f"gallery/{path.stem}.md",
                                    content=_example_page(path, images)))
    return files


def _readme_section(readme: str, heading: str) -> str:
    lines = readme.splitlines()
    start = level = None
    fenced = False
    for i, line in enumerate(lines):
        if _FENCE.match(line):
            fenced = not fenced
            continue
        if fenced:
            continue
        m = re.match(r"^(#+)\s+(.*?)\s*$", line)
        if not m:
            continue
        if start is None:
            if m.group(2) == heading:
                start, level = i, len(m.group(1))
        elif len(m.group(1)) <= level:
            return "\n".join(lines[start:i]).rstrip() + "\n"
    if start is None:
        raise PluginError(f"README.md has no section '{heading}' (asked for by a docs page)")
    return "\n".join(lines[start:]).rstrip() + "\n"


def _code_blocks(section: str) -> str:
    """The fenced blocks of a section, each with the paragraph just before it."""
    out, paragraph, block = [], [], None
    for line in section.splitlines()[1:]:
        if block is not None:
            block.append(line)
            if _FENCE.match(line):
                out += paragraph + [""] + block + [""]
                paragraph, block = [], None
        elif _FENCE.match(line):
            block = [line]
        elif line.strip():
            paragraph.append(line)
        else:
            paragraph = []
    return "\n".join(out)


def on_page_markdown(markdown, page, config, files):
    if not _MARKER.search(markdown):
        return markdown
    readme = (_root(config) / "README.md").read_text(encoding="utf-8")
    up = posixpath.relpath(".", posixpath.dirname(page.file.src_uri) or ".")
    prefix = "" if up == "." else up + "/"

    def section(match):
        text = _readme_section(readme, match.group(1))
        if match.group(2):
            text = _code_blocks(text)
        return re.sub(r"\]\(docs/", f"]({prefix}", text)

    return _MARKER.sub(section, markdown)
