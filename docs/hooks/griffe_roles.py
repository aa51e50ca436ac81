"""Griffe extension of skmoor's documentation (mkdocs.yml, mkdocstrings' ``extensions``):
Sphinx roles in docstrings (:class:`~skmoor.sea.waves.Sea`, :func:`name`, ...) shown as code
and linked where the target is in the API reference. A name is resolved in the scope of
the docstring's object as Python would (imports included); the link is an optional
cross-reference, so a target outside the reference is plain code, not a warning."""
from __future__ import annotations

import re

import griffe

_ROLE = re.compile(r":(?:class|func|meth|mod|attr|data|obj|exc|const):`(~?)([^`]+)`")


def _identifier(obj, target: str) -> str:
    if target.split(".", 1)[0] == "skmoor":
        return target
    head, _, rest = target.partition(".")
    try:
        path = obj.resolve(head)
    except (griffe.NameResolutionError, AttributeError):
        path = f"{obj.module.path}.{head}"
    return f"{path}.{rest}" if rest else path


def _rewrite(obj) -> None:
    doc = obj.docstring
    if doc is not None and ":`" in doc.value:
        def replace(match):
            short, target = match.group(1), match.group(2).strip()
            text = target.rsplit(".", 1)[-1] if short else target
            ident = _identifier(obj, target)
            return f'<autoref identifier="{ident}" optional><code>{text}</code></autoref>'

        doc.value = _ROLE.sub(replace, doc.value)
    for member in obj.members.values():
        if not member.is_alias:
            _rewrite(member)


class SphinxRoles(griffe.Extension):
    def on_package(self, *, pkg, **kwargs):
        _rewrite(pkg)
