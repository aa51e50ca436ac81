"""Inputs: the case file's schema and reader, MoorDyn decks and MoorDyn sea files.
(The schema, :func:`validate_case`, loads pydantic: it is imported when first asked for.)
"""
from .case import Case, paper_case
from .deck import Deck, read_deck, write_deck

__all__ = ["Case", "paper_case", "Deck", "read_deck", "write_deck", "validate_case"]


def __getattr__(name):
    if name == "validate_case":
        from .schema import validate_case

        return validate_case
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
