"""From a case or a MoorDyn deck to one kind of model: a :class:`~skmoor.coupling.network.Network`
of points, lines and bodies, built into a :class:`~skmoor.coupling.system.System`.

:func:`build` takes a :class:`~skmoor.io.case.Case`, a :class:`~skmoor.io.deck.Deck` or a path
(``.toml`` case or MoorDyn deck). A case is either the paper's parametric layout (sag
ratio, chord angle, box: it generates the anchors, the fairleads on the body and the
lines, with the draft from vertical equilibrium, paper Eq. 1) or the explicit tables
``[[points]]``, ``[[lines]]``, ``[[bodies]]`` (see :mod:`skmoor.inputs`).
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..coupling.build import build_system
from ..coupling.checks import check_network
from ..coupling.network import Network
from ..numerics.validation import user_stacklevel
from .from_case import explicit_network, paper_network

SOLVER_DEFAULTS = {"duration": 200.0, "dt": 0.05, "output_interval": 0.1,
                   "scheme": "generalized-alpha", "rho_inf": 0.9, "steady_periods": 5}


@dataclass
class Model:
    """A built network: ``system`` (the reduced equations), ``lines`` (LineSet, one line
    per network line, in order), ``network`` (points, lines, bodies), ``catenaries`` (the
    analytic catenary of each line between its ends as given, None where there is none),
    ``settings`` (solver, damping, load: the case's, or defaults for a deck), ``name``,
    ``depth`` (m), ``draft`` (m, the paper layout's), ``source`` (the Case or Deck) and
    ``positions`` (each point's position in the reference state, m: the free points
    settled on catenaries)."""

    name: str
    system: object
    lines: object
    network: Network
    catenaries: list
    settings: dict
    depth: float
    draft: float | None = None
    source: object = None
    notes: list = field(default_factory=list)
    positions: dict = field(default_factory=dict)  # point name -> reference position, m
    added: list = field(default_factory=list)  # the terms given to add(), in order

    @property
    def case(self):
        """The Case the model was built from (None for a deck)."""
        from ..io.case import Case
        return self.source if isinstance(self.source, Case) else None

    @property
    def body(self):
        """The first dynamic body's RigidBody, or None."""
        return self.system.body

    @property
    def forcing_period(self) -> float | None:
        omega = self.settings.get("load", {}).get("omega")
        return 2 * np.pi / omega if omega else None

    def __post_init__(self):
        self.settings["solver"] = {**SOLVER_DEFAULTS, **self.settings.get("solver", {})}

    @property
    def solver(self) -> dict:
        """The solver settings (defaults filled in; change them here or in settings)."""
        return self.settings["solver"]

    @property
    def damping(self) -> dict:
        return self.settings.get("damping", {"ratio": 0.0})

    def add(self, term):
        """Add a :class:`~skmoor.fem.terms.Term` (a LineForm, PointLoad, BodyLoad, ...) to the
        model's equations, with its mass: it acts in statics, modes and dynamics alike.
        A PointLoad's ``point``, a BodyLoad's ``body`` or the ``bodies`` of a term on a
        pair of bodies (a :class:`~skmoor.coupling.joints.BodyPin`) may be names. Returns the term."""
        kind = getattr(term, "acts_on", None)
        if kind == "body pairs":
            names = [b.name for b in self.network.bodies if b.kind == "dynamic"]
            pair = []
            for index in getattr(term, "bodies", ()):
                if isinstance(index, str):
                    if index not in names:
                        raise ValueError(f"Model.add {type(term).__name__}.bodies: no dynamic "
                                         f"body {index!r} (have {names or 'none'})")
                    index = names.index(index)
                pair.append(index)
            term.bodies = tuple(pair)
        if kind in ("points", "bodies"):
            attribute = "point" if kind == "points" else "body"
            names = ([p.name for p in self.network.points if p.kind == "free"] if kind == "points"
                     else [b.name for b in self.network.bodies if b.kind == "dynamic"])
            index = getattr(term, attribute)
            if isinstance(index, str):
                if index not in names:
                    what = "free point" if kind == "points" else "dynamic body"
                    raise ValueError(f"Model.add {type(term).__name__}.{attribute}: no {what} "
                                     f"{index!r} (have {names or 'none'})")
                setattr(term, attribute, names.index(index))
        self.system.add_term(term)
        self.added.append(term)
        return term


def build(source, *, motion=None, sea=None, rotations=None, law=None) -> Model:
    """The model of a Case, a Deck or a path to either (``.toml``: a case; else a deck).
    motion: fn(t) -> coupled-DOF displacements (see :mod:`skmoor.coupling.network`); sea: a
    :class:`~skmoor.sea.waves.Sea` for a deck (default: still water of its depth);
    rotations: 'small' (default) or 'exact' for a deck's free bodies (a case sets it per
    body, ``rotations`` in ``[body]`` / ``[[bodies]]``); law: a
    :class:`~skmoor.lines.laws.Law` (a :class:`~skmoor.lines.user_law.UserLaw` of yours)
    for every line, in place of the case's or deck's laws."""
    if law is not None:
        from ..lines.laws import Law

        if not isinstance(law, Law):
            raise ValueError(f"build law: expected a skmoor Law (such as skmoor.UserLaw), "
                             f"got {type(law).__name__}")
        return _with_law(source, law, motion=motion, sea=sea, rotations=rotations)
    from ..io.case import Case
    from ..io.deck import Deck, read_deck

    if isinstance(source, (str, Path)):
        path = Path(source)
        if path.is_dir():
            raise ValueError(f"build: {path} is a folder; give a case file (.toml) or a "
                             "MoorDyn deck")
        source = Case.from_toml(path) if path.suffix == ".toml" else read_deck(path)
    if isinstance(source, Deck):
        from .from_deck import deck_network, default_time_step
        network, settings = deck_network(source, motion=motion, sea=sea,
                                         rotations=rotations or "small")
        as_given = settings["solver"].get("start") == "reference"  # TmaxIC = 0
        try:
            model = from_network(network, name=source.source, settings=settings,
                                 source=source, notes=list(source.notes), settle=not as_given)
        except ValueError as err:
            raise _on_deck_line(source, err) from None
        if "dt" not in settings["solver"]:
            model.settings["solver"]["dt"] = default_time_step(model)
        return model
    if not isinstance(source, Case):
        raise ValueError(f"build: expected a Case, a Deck or a path, got {type(source).__name__}")
    if rotations is not None:
        raise ValueError("build rotations: a case sets its bodies' rotations in the case "
                         "file (rotations in [body] or [[bodies]])")
    if "points" in source.data:
        network = explicit_network(source)
        if motion is not None:
            network.motion = motion
        return from_network(network, name=source.name, settings=_settings(source),
                            source=source)
    return _paper_layout(source, motion)


def _with_law(source, law, **options) -> Model:
    """:func:`build` of ``source`` with every line type's law replaced by ``law`` (the
    points where the first build put them)."""
    import dataclasses

    model = build(source, **options)
    network = model.network
    network.strain_law = law
    for line in network.lines:
        line.line_type = dataclasses.replace(line.line_type, law=law)
    system, lineset, _, positions = build_system(network, positions=model.positions)
    return dataclasses.replace(model, system=system, lines=lineset, positions=positions)


def _on_deck_line(deck, err) -> ValueError:
    """A network error about 'line lineN' or 'point pointN' told at its deck line."""
    import re

    message = str(err)
    match = re.match(r"(line|point) (line|point)(\d+)(: )?", message)
    if not match:
        return ValueError(f"{deck.source}: {message}")
    table = deck.lines if match.group(2) == "line" else deck.points
    entry = table[int(match.group(3)) - 1]
    section = "LINES" if match.group(2) == "line" else "POINTS"
    return ValueError(f"{deck.source} line {entry.where}: {section} {entry.id}: "
                      f"{message[match.end():]}")


def from_network(network: Network, *, name="network", settings=None, draft=None,
                 source=None, notes=(), settle=True) -> Model:
    """Build a Network into a Model (statics not yet solved: see :func:`skmoor.equilibrium`).
    Impossible input is refused first, suspicious input warned about (:mod:`skmoor.coupling.checks`).
    settle: the free points' reference positions settled on catenaries
    (:func:`~skmoor.coupling.build.settle_points`), else where the network gives them."""
    warned = _checked(network)
    given = None if settle else {p.name: network.global_position(p) for p in network.points}
    system, lineset, catenaries, positions = build_system(network, given)
    return Model(name, system, lineset, network, catenaries, dict(settings or {}),
                 network.depth, draft, source,
                 list(notes) + warned + network.notes + _statics_notes(network), positions)


def _statics_notes(network) -> list:
    """A note when the sea bed has friction that the static solve leaves out (its
    ``static_friction`` None): the static state is the frictionless one."""
    bed = network.seabed
    if bed is None or not (bed.mu_axial or bed.mu_lateral) or bed.static_friction:
        return []
    return ["the static state is frictionless: the sea bed's friction acts in the time "
            "loop only (Seabed static_friction='as-laid', or seabed.static_friction in a "
            "case file, puts it in the statics as MoorPy's CB does)"]


def _checked(network) -> list:
    """check_network's warnings, also issued as Python warnings."""
    found = check_network(network)
    for text in found:
        warnings.warn(text, UserWarning, stacklevel=user_stacklevel())
    return found


def _settings(case) -> dict:
    return {"solver": case.solver, "damping": case.damping, "load": case.load}


# ------------------------------------------------------------ the paper's layout


def _paper_layout(case, motion=None) -> Model:
    network, catenaries, draft = paper_network(case, motion)
    warned = _checked(network)
    system, lineset, _, positions = build_system(network, positions={
        p.name: network.global_position(p) for p in network.points})
    return Model(case.name, system, lineset, network, catenaries, _settings(case),
                 network.depth, draft, case, notes=warned + _statics_notes(network),
                 positions=positions)


# ------------------------------------------------------------ the explicit tables
