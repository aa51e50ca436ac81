"""Inputs: the case file's schema and reader, MoorDyn decks and MoorDyn sea files.
"""
from .case import Case, paper_case
from .deck import Deck, read_deck, write_deck
from .schema import validate_case

__all__ = ["Case", "paper_case", "Deck", "read_deck", "write_deck", "validate_case"]
