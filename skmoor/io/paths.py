"""File references of a case or a deck (bathymetry, sea files, hull meshes, curves):
resolved against the folder of the file that names them, and refused when they leave it."""
from __future__ import annotations

from pathlib import Path

__all__ = ["resolve_inside"]


def resolve_inside(name, folder, field: str, root=None) -> Path:
    """The path of file ``name`` named by ``field`` of a case or deck in ``folder``:
    relative names start at ``folder``; a name that leads out of ``folder`` (``..``, an
    absolute path elsewhere, a link out) is refused with a ValueError naming the field.
    folder None (a case made in Python): the name as given, relative to the working
    folder. root: the folder it must stay in, when not ``folder`` itself."""
    path = Path(name)
    if folder is None:
        return path
    folder = Path(folder).resolve()
    root = folder if root is None else Path(root).resolve()
    path = (path if path.is_absolute() else folder / path).resolve()
    if not path.is_relative_to(root):
        raise ValueError(f"{field}: {str(name)!r} leads out of the folder {root} of the "
                         "file that names it (give a file in that folder or below it)")
    return path
