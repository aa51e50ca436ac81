"""Inputs: the case file's schema and reader, MoorDyn decks and MoorDyn sea files.
"""
