"""MoorDyn-C v2's water and seafloor input, read into skmoor's sea and sea bed.

A deck's options choose them (MoorDyn-C source/Waves.cpp, source/Waves/WaveGrid.cpp,
source/Seafloor.cpp); the files have MoorDyn's fixed names in the deck's folder:

- ``WaveKin 1``: the waves come from the caller (MoorDyn's ExternalWaveKinSet): give
  ``deck_network(deck, sea=...)`` a :class:`~skmoor.sea.waves.Sea` (:func:`deck_sea` gives
  the deck's own currents and bed to build it on); without one the lines see no waves,
  as MoorDyn's nodes before the caller sets them.
- ``WaveKin 2``: ``wave_frequencies.txt`` (omega rad/s from 0, real and imaginary
  amplitude m, optional heading rad) interpolated onto evenly spaced frequencies, on the
  grid of ``water_grid.txt``: a :class:`~skmoor.sea.water_grids.WaveGrid`.
- ``WaveKin 3``: ``wave_elevation.txt`` (time s, elevation m at x = y = 0) resampled
  every ``dtWave`` s, its FFT below 0.5 Hz, on the grid of ``water_grid.txt``.
- ``WaveKin 7``: ``wave_frequencies.txt`` summed at the points (no grid):
  :class:`~skmoor.sea.water_grids.SpectrumWaves`.
- ``Currents 1``: ``current_profile.txt`` (3 header lines, then z ux [uy [uz]]); a
  profile of horizontal velocities along one heading is a steady
  :class:`~skmoor.sea.waves.Current` (linear in z and held beyond its ends, as the grid
  is; the compiled time step takes it), any other a grid.
- ``Currents 2``: ``current_profile_dynamic.txt`` (line 5: the z's; from line 7: t and
  ux at each z [then uy, uz]).
- ``Currents 5``: ``current_profile_4d.txt`` (line 1: nx ny nz nt; lines 2-5: the x, y,
  z, t axes; line 6 a header; from line 7: x y z t ux uy uz; a grid point without a line
  has zero current, as in MoorDyn-C, and is counted in the deck's notes: MoorDyn's own
  files write a point on line 6, which both codes skip).
- With a wave grid and ``UnifyCurrentGrid`` 1 (MoorDyn's default) the current is sampled
  at the wave grid's nodes and times and stretched with the waves, as MoorDyn adds it to
  that grid; otherwise it is interpolated on its own grid, unstretched.
- MoorDyn-C's initial-condition (IC) solve sees none of this water: its log reads "Water
  kinematics for IC gen: No Waves or Currents" and its IC state is the same to the last
  bit with and without a deck's Currents (the ``moordyn`` 2.7.2 package; the v2.7.1
  source reads as if the IC had them). :func:`still_water` is that water, for a static
  state to set beside MoorDyn's.
- ``SeafloorFile PATH`` (the deck's folder, else the working folder, as MoorDyn opens
  it): line 1 nx ny, line 2 the x's, line 3 the y's, then x y z a line, z the bed's
  height (m, negative): a :class:`~skmoor.sea.seabed.Bathymetry`; the waves then take the
  bed's mean depth.

Water grid file (``water_grid.txt``): 3 header lines, then for x, y and z a line with
the kind (0: the single coordinate 0, 1: a list, 2: first last count) and a line of
values. Bad files are refused naming the file, its line and the reason.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..sea.seabed import Bathymetry
from ..sea.water_grids import (
    CurrentGrid,
    SpectrumWaves,
    Stretching,
    WaveGrid,
    elevation_spectrum,
    evenly_spaced,
    resampled_current,
)
from ..sea.waves import Current, Sea
from .paths import resolve_inside

WAVE_FILES = {2: ("wave_frequencies.txt", "water_grid.txt"),
              3: ("wave_elevation.txt", "water_grid.txt"), 7: ("wave_frequencies.txt",)}
CURRENT_FILES = {1: "current_profile.txt", 2: "current_profile_dynamic.txt",
                 5: "current_profile_4d.txt"}
DT_WAVE = 0.25  # s, MoorDyn-C's default dtWave


class _File:
    """A text file's lines (1-based numbers kept) and errors naming file and line."""

    def __init__(self, path, purpose):
        self.path = Path(path)
        if not self.path.is_file():
            raise ValueError(f"{self.path.name}: no such file in {self.path.parent} "
                             f"({purpose} reads it)")
        self.lines = self.path.read_text(encoding="utf-8", errors="replace").splitlines()

    def error(self, number, what):
        return ValueError(f"{self.path.name} line {number}: {what}")

    def need(self, count, what):
        if len(self.lines) < count:
            raise ValueError(f"{self.path.name}: {len(self.lines)} lines, at least {count} "
                             f"needed ({what})")

    def words(self, number):
        return self.lines[number - 1].split()

    def numbers(self, number, minimum=1, exactly=None):
        words = self.words(number)
        if exactly is not None and len(words) != exactly:
            raise self.error(number, f"{len(words)} values, expected {exactly}")
        if len(words) < minimum:
            raise self.error(number, f"{len(words)} values, at least {minimum} expected")
        values = []
        for word in words:
            try:
                value = float(word)
            except ValueError:
                raise self.error(number, f"{word!r} is not a number") from None
            if not math.isfinite(value):
                raise self.error(number, f"{word!r} is not finite")
            values.append(value)
        return np.array(values)

    def data_rows(self, first):
        """(number, values) of the non-blank lines from line ``first`` on."""
        return [(n, self.numbers(n)) for n in range(first, len(self.lines) + 1)
                if self.lines[n - 1].strip()]

    def increasing(self, number, values, what):
        if np.any(np.diff(values) <= 0):
            raise self.error(number, f"the {what} must increase strictly, got "
                             f"{np.asarray(values).tolist()}")
        return values


def read_water_grid(path):
    """(x, y, z) axes (m) of a MoorDyn ``water_grid.txt``."""
    f = _File(path, "a wave grid (WaveKin 2, 3)")
    f.need(9, "3 header lines, then a kind line and a values line for x, y and z")
    axes = []
    for name, number in zip("xyz", (4, 6, 8)):
        kind = f.numbers(number)[0]
        values = f.numbers(number + 1)
        if kind == 0:
            axis = np.zeros(1)
        elif kind == 1:
            axis = values
        elif kind == 2:
            if len(values) < 3 or values[2] != int(values[2]) or values[2] < 2:
                raise f.error(number + 1, f"{name}: a lattice needs first, last and a count "
                              ">= 2")
            axis = np.linspace(values[0], values[1], int(values[2]))
        else:
            raise f.error(number, f"{name}: grid kind {kind:g} is not 0 (single), 1 (list) "
                          "or 2 (lattice)")
        axes.append(f.increasing(number + 1, axis, f"{name} coordinates"))
    return tuple(axes)


def read_wave_frequencies(path):
    """(omega rad/s, complex amplitude m, heading rad) of a ``wave_frequencies.txt``,
    starting at 0 rad/s as MoorDyn requires."""
    f = _File(path, "frequency-component waves (WaveKin 2, 7)")
    rows = f.data_rows(1)
    if len(rows) < 2:
        raise ValueError(f"{f.path.name}: {len(rows)} components, at least 2 needed")
    omega, amplitude, beta = [], [], []
    for number, values in rows:
        if len(values) < 3:
            raise f.error(number, f"{len(values)} values, need omega, real and imaginary "
                          "amplitude (and an optional heading)")
        if len(values) >= 4 and abs(values[3]) > 2 * np.pi:
            raise f.error(number, f"heading {values[3]:g} is outside [-2 pi, 2 pi] (rad)")
        omega.append(values[0])
        amplitude.append(values[1] + 1j * values[2])
        beta.append(values[3] if len(values) >= 4 else 0.0)
    if omega[0] != 0.0:
        raise f.error(rows[0][0], f"the first frequency must be 0 rad/s, got {omega[0]:g}")
    f.increasing(rows[-1][0], omega, "frequencies")
    return np.array(omega), np.array(amplitude), np.array(beta)


def read_wave_elevation(path, dt):
    """(times s, elevations m) of a ``wave_elevation.txt``; at least two samples of
    dtWave = dt s."""
    f = _File(path, "an elevation record (WaveKin 3)")
    rows = f.data_rows(1)
    for number, values in rows:
        if len(values) < 2:
            raise f.error(number, f"{len(values)} values, need time and elevation")
    if not rows:
        raise ValueError(f"{f.path.name}: no samples")
    table = np.array([values[:2] for _, values in rows])
    f.increasing(rows[-1][0], table[:, 0], "times")
    if table[-1, 0] < dt:
        raise f.error(rows[-1][0], f"the record ends at {table[-1, 0]:g} s, before one "
                      f"dtWave ({dt:g} s)")
    return table[:, 0], table[:, 1]


def read_current_profile(path):
    """(z m, velocity (nz, 3) m/s) of a ``current_profile.txt``."""
    f = _File(path, "a steady current (Currents 1)")
    f.need(4, "3 header lines, then z ux [uy [uz]] a line")
    rows = f.data_rows(4)
    z, velocity = [], []
    for number, values in rows:
        if len(values) < 2:
            raise f.error(number, f"{len(values)} values, need z and ux [uy [uz]]")
        z.append(values[0])
        velocity.append(np.concatenate([values[1:4], np.zeros(4 - min(len(values), 4))]))
    f.increasing(rows[-1][0], z, "z's")
    return np.array(z), np.array(velocity)


def read_dynamic_current(path):
    """(z m, times s, velocity (nz, nt, 3) m/s) of a ``current_profile_dynamic.txt``."""
    f = _File(path, "a dynamic current (Currents 2)")
    f.need(7, "4 header lines, the z's on line 5, a header line, then t and velocities")
    z = f.increasing(5, f.numbers(5), "z's")
    nz = z.size
    rows = f.data_rows(7)
    times, velocity = [], []
    for number, values in rows:
        if len(values) < nz + 1:
            raise f.error(number, f"{len(values)} values, need t and ux at the {nz} z's")
        per = [values[1 + i * nz:1 + (i + 1) * nz] if len(values) >= 1 + (i + 1) * nz
               else np.zeros(nz) for i in range(3)]
        times.append(values[0])
        velocity.append(np.stack(per, axis=-1))
    if not rows:
        raise ValueError(f"{f.path.name}: no samples from line 7 on")
    f.increasing(rows[-1][0], times, "times")
    return z, np.array(times), np.moveaxis(np.array(velocity), 0, 1)


def read_4d_current(path):
    """(x, y, z m, times s, velocity (nx, ny, nz, nt, 3) m/s, missing) of a
    ``current_profile_4d.txt``, read as MoorDyn-C reads it: the points from line 7 on
    (line 6 is a header), each on the axes; a grid point without a line has zero velocity
    (``missing`` counts them)."""
    f = _File(path, "a 4D current (Currents 5)")
    f.need(7, "the counts, the x, y, z, t axes, a header line, then the points")
    counts = f.numbers(1, exactly=4)
    if np.any(counts < 1) or np.any(counts != np.round(counts)):
        raise f.error(1, f"the counts nx ny nz nt must be positive integers, got {counts}")
    axes = []
    for number, (name, count) in enumerate(zip("xyzt", counts.astype(int)), start=2):
        values = f.numbers(number, exactly=count)
        axes.append(f.increasing(number, values, f"{name} coordinates"))
    rows = f.data_rows(7)
    for number, values in rows:
        if len(values) != 7:
            raise f.error(number, f"{len(values)} values, need x y z t ux uy uz")
    numbers = np.array([number for number, _ in rows], int)
    table = np.array([values for _, values in rows]).reshape(-1, 7)
    index = []
    for axis, column, name in zip(axes, table[:, :4].T, "xyzt"):
        nearest = np.clip(np.searchsorted(axis, column), 1, axis.size - 1) if axis.size > 1 \
            else np.zeros(column.size, int)
        if axis.size > 1:
            nearest -= np.abs(column - axis[nearest - 1]) < np.abs(column - axis[nearest])
        off = np.abs(axis[nearest] - column) > 1e-9 * np.maximum(1.0, np.abs(column))
        if np.any(off):
            k = int(np.argmax(off))
            raise f.error(numbers[k], f"{name} = {column[k]:g} is not on the {name} axis")
        index.append(nearest)
    flat = np.ravel_multi_index(index, tuple(counts.astype(int)))
    unique, seen = np.unique(flat, return_counts=True)
    if np.any(seen > 1):
        twice = np.flatnonzero(flat == unique[np.argmax(seen > 1)])[1]
        raise f.error(numbers[twice], "this grid point is given twice")
    velocity = np.zeros((int(np.prod(counts)), 3))
    velocity[flat] = table[:, 4:]
    given = np.zeros(velocity.shape[0], bool)
    given[flat] = True
    velocity = velocity.reshape(tuple(counts.astype(int)) + (3,))
    return (*axes, velocity, int(given.size - given.sum()))


def read_seafloor(path):
    """A :class:`~skmoor.sea.seabed.Bathymetry` from a MoorDyn seafloor file."""
    f = _File(path, "SeafloorFile")
    f.need(4, "nx ny, the x's, the y's, then x y z a line")
    counts = f.numbers(1, minimum=2)[:2]
    if np.any(counts < 1) or np.any(counts != np.round(counts)):
        raise f.error(1, f"nx ny must be positive integers, got {counts}")
    nx, ny = counts.astype(int)
    x = f.increasing(2, f.numbers(2, exactly=nx), "x coordinates")
    y = f.increasing(3, f.numbers(3, exactly=ny), "y coordinates")
    heights = np.full((nx, ny), np.nan)
    for number, values in f.data_rows(4):
        if len(values) != 3:
            raise f.error(number, f"{len(values)} values, need x y z")
        # MoorDyn's calcInsertIndex: the last grid coordinate at or below the value
        i = min(max(int(np.searchsorted(x, values[0], side="right")) - 1, 0), nx - 1)
        j = min(max(int(np.searchsorted(y, values[1], side="right")) - 1, 0), ny - 1)
        heights[i, j] = values[2]
    missing = int(np.isnan(heights).sum())
    if missing:
        raise ValueError(f"{f.path.name}: {missing} of the {nx * ny} grid points have no "
                         "height")
    return Bathymetry(x, y, heights, source=f.path.name)


def _mode(deck, name, supported):
    value = deck.option(name, 0.0)
    if value != int(value) or int(value) not in (0,) + tuple(supported):
        raise ValueError(f"{deck.where(name)}: option {name} = {deck.options[name]}: "
                         f"skmoor reads {name} {', '.join(map(str, supported))} (or 0)")
    return int(value)


def _seafloor_path(deck):
    written = deck.options["SeafloorFile"]
    field = f"{deck.where('SeafloorFile')}: SeafloorFile"
    refused = None
    for base in (deck.folder, Path.cwd()):
        try:
            path = resolve_inside(written, base, field)
        except ValueError as err:
            refused = refused or err
            continue
        if path.is_file():
            return path
    if refused is not None:
        raise refused
    raise ValueError(f"{deck.where('SeafloorFile')}: SeafloorFile {written!r}: no such "
                     f"file in the deck's folder {deck.folder} or the working folder")


def deck_bathymetry(deck):
    """The deck's :class:`~skmoor.sea.seabed.Bathymetry` (its SeafloorFile), or None."""
    if "SeafloorFile" not in deck.options:
        return None
    path = _seafloor_path(deck)
    try:
        return read_seafloor(path)
    except ValueError as err:
        raise ValueError(f"{deck.where('SeafloorFile')}: SeafloorFile: {err}") from None


def steady_profile(z, velocity):
    """The :class:`~skmoor.sea.waves.Current` of a profile (z m, velocity (nz, 3) m/s)
    whose velocities are horizontal and along one heading (signed speeds along it), or
    None."""
    horizontal = velocity[:, :2]
    size = np.linalg.norm(horizontal, axis=1)
    if np.any(velocity[:, 2] != 0) or not size.max() > 0:
        return None
    direction = horizontal[np.argmax(size)] / size.max()
    speeds = horizontal @ direction
    if np.abs(horizontal - speeds[:, None] * direction).max() > 1e-12 * size.max():
        return None
    return Current(profile=np.c_[z, speeds],
                   heading_deg=math.degrees(math.atan2(direction[1], direction[0])))


def _current(deck, mode, steady=False):
    """The deck's current (``steady``: a steady Current where the profile is one, else
    a grid)."""
    folder = Path(deck.folder)
    path = folder / CURRENT_FILES[mode]
    if mode == 1:
        z, velocity = read_current_profile(path)
        current = steady_profile(z, velocity) if steady else None
        return current or CurrentGrid([0.0], [0.0], z, 1.0, velocity[None, None, :, None, :])
    if mode == 2:
        z, times, velocity = read_dynamic_current(path)
        return resampled_current([0.0], [0.0], z, times, velocity[None, None])
    *grid, missing = read_4d_current(path)
    if missing:
        deck.notes.append(f"{path.name}: {missing} grid points have no line (line 6 is a "
                          "header, as MoorDyn-C reads it): zero current there")
    return resampled_current(*grid)


def _waves(deck, mode, stretching):
    folder = Path(deck.folder)
    files = WAVE_FILES[mode]
    if mode == 7:
        omega, amplitude, beta = read_wave_frequencies(folder / files[0])
        return SpectrumWaves(omega, amplitude, beta, stretching, g=deck.g)
    if mode == 2:
        components = evenly_spaced(*read_wave_frequencies(folder / files[0]))
    else:
        dt = deck.option("dtWave", DT_WAVE)
        if not dt > 0:
            raise ValueError(f"{deck.where('dtWave')}: option dtWave = {dt:g}: must be "
                             "positive (s)")
        components = elevation_spectrum(*read_wave_elevation(folder / files[0], dt), dt)
    return WaveGrid(components, *read_water_grid(folder / files[1]), stretching.depth,
                    stretching, g=deck.g)


def deck_sea(deck, bathymetry=None) -> Sea:
    """The deck's water as a :class:`~skmoor.sea.waves.Sea`: its depth (the bathymetry's
    mean depth with one), rho, g, and its WaveKin / Currents files as fields (see the
    module docstring). A ValueError names the deck line or the file line and the
    reason."""
    waves = _mode(deck, "WaveKin", (1, 2, 3, 7))
    currents = _mode(deck, "Currents", tuple(CURRENT_FILES))
    stretching = Stretching(deck.depth, bathymetry)
    fields, steady = [], None
    where = {"WaveKin": waves, "Currents": currents}
    try:
        for name, mode in where.items():
            if name == "WaveKin" and mode in WAVE_FILES:
                fields.append(_waves(deck, mode, stretching))
            if name == "Currents" and mode:
                unify = deck.option("UnifyCurrentGrid", 1.0) != 0
                if fields and isinstance(fields[0], WaveGrid) and unify:
                    fields[0].currents.append(_current(deck, mode))
                    continue
                current = _current(deck, mode, steady=True)
                if isinstance(current, Current):
                    steady = current
                else:
                    fields.append(current)
    except ValueError as err:
        raise ValueError(f"{deck.where(name)}: option {name} = {deck.options[name]}: "
                         f"{err}") from None
    return Sea(stretching.depth, rho=deck.rho, g=deck.g, current=steady, fields=fields)


def still_water(deck, bathymetry=None) -> Sea:
    """The deck's water at rest, as MoorDyn's IC solve has it (no waves, no currents): a
    :class:`~skmoor.sea.waves.Sea` of the deck's depth (the bathymetry's mean depth with
    one, as :func:`deck_sea`), rho and g. ``skmoor.build(deck, sea=still_water(deck))``
    then ``skmoor.equilibrium`` is the state MoorDyn starts its time steps from."""
    return Sea(Stretching(deck.depth, bathymetry).depth, rho=deck.rho, g=deck.g)
