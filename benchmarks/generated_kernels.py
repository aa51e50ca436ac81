"""Hand-written kernels against the kernels generated from their forms, in the time loop.

Each effect is written once as a form; the compiled time step runs a kernel generated from
it. A hand-written numba kernel stays beside a form only where the generated one is
measurably slower in the time loop (more than 10 %). This script measures that for the
effects that keep one, the same physics run both ways in this one process:

- **Morison in a current and waves**: a 20-element chain (P1, and Hermite with EI > 0)
  in a sheared current and an Airy wave, its fairlead moved 1 m at 0.8 rad/s, for
  CREEP_STEPS steps of 0.1 s: ``LineHydroKernel`` against the kernels generated from
  ``skmoor.sea.hydro.form_terms`` (the water at the nodes evaluated in compiled code
  before them);
- **VIV lift**: the same chain on P1 lines with a lift coefficient, in the same water and
  motion: ``VortexLift``'s hand kernel and commit against those generated from
  ``skmoor.sea.viv.vortex_lift`` and its memory's update (``VortexLiftForm``);
- **bending**: a 20-element flexible riser hung from a fairlead moved 0.1 m at 0.8 rad/s,
  CREEP_STEPS steps of 0.05 s: its bending stiffness in the hand kernel of bending lines
  (``HermiteKernel``), or all but a millionth of it in a form of u'' and v'' on path
  'compiled' (the hand kernel then carries the axial force alone);
- **sea bed and Morison on bending lines**: the 200 m lazy-wave cable of
  ``benchmarks/bending.py`` (64 Hermite elements, its hang-off heaved 3 m / 12 s for 60 s,
  drag and added mass, CableDyn's penalty bed) at STEP, with ``Network.form_path`` 'auto'
  (the hand kernels: ``SeabedKernel``, ``LineHydroKernel``) and 'compiled' (the kernels
  generated from ``skmoor.sea.seabed.form_term`` and ``skmoor.sea.hydro.form_terms``);
- **creep**: a 20-element polyester chain whose fairlead is moved 1 m at 0.8 rad/s,
  under MoorDyn's viscoelastic law (``Viscoelastic``: the hand kernel of ``CreepTerm``)
  and the same law written as a ``UserLaw`` with a state rate (its generated kernel), for
  CREEP_STEPS steps of 0.1 s;
- **Syrope creep**: the same chain as MoorDyn's Syrope rope (``SyropeCreep``, the hand
  kernel rebuilding its working-curve tables) and as its user law
  (``SyropeCreep.user_law``: a rate and an update, the working curve traced as a function
  of the highest tension), pulled past its Tmax0.

The cable's and Morison's hand kernels on P1 lines are measured by
``benchmarks/user_forms.py`` (a user law and a user drag form against them).

Each pair runs the two loops one after the other, the order alternating from pair to
pair, each model built once (its kernels generated, compiled or loaded from the disk
cache before the pairs, by an untimed run of each); printed: the
median of PAIRS paired ratios generated / hand with its quartiles, and how far apart the
two runs' histories are (largest difference over the range). The two runs of an effect
solve the same equations at the solver's default tolerance along different Newton paths
(the bed's hand kernel has its own Newton matrix slope; CreepTerm takes its slopes in z
by central differences), so they agree to that tolerance, not to round-off; the tests
hold them together at a tight one.

Run: ``python benchmarks/generated_kernels.py [--pairs N] [--write-docs]`` (a few
minutes; the first run compiles the generated kernels, about a minute, then they are
cached on disk; --write-docs: the table into docs/speed.md).
"""
from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")  # one core, as the other benchmarks

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import bending  # noqa: E402
import numpy as np  # noqa: E402
from _cases import ROOT, environment, write_block  # noqa: E402

PAIRS = 7
STEP = 0.25  # s: the lazy-wave cable's converged step (docs/speed.md)
CREEP_STEPS = 3000

# the polyester chain: EA_s, EA_d (N), dampers BA (creep) and BA_D (dynamic), N s
EA_S, EA_D, BA, BA_D = 7.5e8, 1.5e9, 5e8, 2e7
EA_1 = EA_D * EA_S / (EA_D - EA_S)  # the creep spring, N
# the Syrope rope: its original working curve (strain, N), EA_Dc (N), EA_D_Lm, SYROPE IC
OWC = ([0.002, 0.01, 0.02, 0.04, 0.06], [1.7e5, 7.4e5, 1.3e6, 2.45e6, 4.39e6])
ALPHA, BETA, T_MAX0, T_MEAN0 = 1.53e8, 23.12, 1.3886e6, 4.339e5


def creep_rate(strain, rate, state, reference):
    """dz/dt: the dynamic element's tension less the creep spring's, over the dampers."""
    z, = state
    return ((EA_D * strain - (EA_1 + EA_D) * z + BA_D * rate) / (BA + BA_D),)


def creep_tension(strain, rate, state, reference):
    """The creep element's spring (in tension only) and damper, N."""
    from skmoor.fem import ops

    z, = state
    return (ops.where(strain >= 0.0, EA_1 * z, 0.0)
            + BA * creep_rate(strain, rate, state, reference)[0])


def chain(law, offset):
    """(system, static state) of the 20-element chain under ``law``, its fairlead moved
    1 m about ``offset`` m out."""
    import skmoor
    from skmoor.lines.catenary import solve_catenary

    rope = skmoor.LineType(EA=EA_S, mass=140.0, diameter=0.09, law=law)
    catenary = solve_catenary([-300.0, 0.0, -150.0], [0.0, 0.0, -5.0], rope.weight, EA_S,
                              length=336.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(catenary, rope, 20)])
    system = skmoor.System(lines, fairleads="prescribed", motion=lambda t: np.array(
        [[offset + np.sin(0.8 * t), 0.0, np.sin(0.8 * t)]]))
    return system, skmoor.solve_static(system).x


def sea_and_chain(EI=0.0, Cl=0.0):
    """(sea, lines): a sheared current and a 3 m Airy wave across it, and the 20-element
    chain (bending stiffness EI, N m2: > 0 on Hermite elements; VIV lift coefficient Cl)
    with Morison's coefficients."""
    import skmoor
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea import AiryWave, Current, Sea

    sea = Sea(150.0, current=Current(profile=[(-150.0, 0.1), (0.0, 0.8)], heading_deg=30.0),
              waves=[AiryWave(3.0, 9.0, 150.0, heading_deg=-20.0)])
    chain = skmoor.LineType(EA=EA_S, mass=140.0, diameter=0.09, Cd_n=1.2, Cd_t=0.1, Ca_n=1.0,
                            EI=EI, Cl=Cl)
    catenary = solve_catenary([-300.0, 0.0, -150.0], [0.0, 0.0, -5.0], chain.weight, EA_S,
                              length=336.0)
    return sea, skmoor.LineSet([skmoor.Line.from_catenary(catenary, chain, 20)])


def moved_chain(lines, terms):
    """(system, static state) of the chain with ``terms``, its fairlead moved 1 m at 0.8
    rad/s."""
    import skmoor

    system = skmoor.System(lines, fairleads="prescribed", terms=terms, motion=lambda t: np.array(
        [[np.sin(0.8 * t), 0.0, np.sin(0.8 * t)]]))
    return system, skmoor.solve_static(system).x


def chain_in_waves(generated, EI):
    """The chain (bending stiffness EI) in the water of :func:`sea_and_chain`, its
    fairlead moved: Morison's hand kernel (``LineHydroKernel``), or with ``generated`` the
    kernels generated from its forms (``hydro.form_terms`` on path 'compiled', the water
    evaluated at the nodes in compiled code first)."""
    from skmoor.sea import hydro

    sea, lines = sea_and_chain(EI)
    lumped = not lines.hermite
    return moved_chain(lines, hydro.form_terms(lines, sea, path="compiled", lumped_mass=lumped)
                       if generated else [hydro.line_hydrodynamics(lines, sea, lumped_mass=lumped)])


def chain_with_lift(generated):
    """The chain in waves of :func:`chain_in_waves` (P1, Morison's hand kernel) with a VIV
    lift coefficient 0.8: the lift's hand kernels (``VortexLift``), or with ``generated``
    the kernel and commit generated from its forms (``VortexLiftForm`` on path
    'compiled', the water, node chords and surface evaluated in compiled code first)."""
    from skmoor.sea import hydro
    from skmoor.sea.viv import vortex_lift_term

    sea, lines = sea_and_chain(Cl=0.8)
    return moved_chain(lines, [hydro.line_hydrodynamics(lines, sea), vortex_lift_term(
        lines, sea, rms_time=10.0, path="compiled" if generated else "auto")])


def more_bending(v, w):
    """The bending stiffness's own form, int k (X'' + u'') . v'' ds (a LinearForm)."""
    from skmoor.fem.ops import dot

    return w.k * dot(w.Xpp + w.u.hess[:, 0, 0], v.hess[:, 0, 0])


AMPLITUDE = 0.1  # m: the fairlead's motion (from 0.3 m the riser's motion is so
# sensitive that round-off parts two runs within 150 s)


def bending_riser(generated):
    """A 20-element flexible riser (EI 4e8 N m2) hung from a fairlead moved AMPLITUDE m at
    0.8 rad/s: its bending in the hand kernel of bending lines (``HermiteKernel``), or with
    ``generated`` all but a millionth of it in a form on path 'compiled'."""
    from skfem import LinearForm

    import skmoor
    from skmoor.lines.catenary import solve_catenary

    EI = 4e8
    riser = skmoor.LineType(EA=2e8, mass=150.0, diameter=0.3,
                            EI=1e-6 * EI if generated else EI)
    catenary = solve_catenary([-150.0, 0.0, -150.0], [0.0, 0.0, -5.0], riser.weight,
                              riser.EA, length=240.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(catenary, riser, 20)])
    terms = [skmoor.LineForm(LinearForm(more_bending), fields={"k": (1 - 1e-6) * EI},
                             path="compiled", lines=lines)] if generated else []
    system = skmoor.System(lines, fairleads="prescribed", terms=terms, motion=lambda t: np.array(
        [[AMPLITUDE * np.sin(0.8 * t), 0.0, AMPLITUDE * np.sin(0.8 * t)]]))
    return system, skmoor.solve_static(system).x


def creep_chain(generated):
    """The chain under the built-in Viscoelastic law, or with ``generated`` the same law
    as a UserLaw."""
    import skmoor

    if generated:
        law = skmoor.UserLaw(creep_tension, state=lambda e, T: (e * EA_D / (EA_1 + EA_D),),
                             state_rate=creep_rate, reference="static",
                             static=skmoor.Engineering(), tension_only=False)
    else:
        law = skmoor.laws.Viscoelastic(EA_dynamic=EA_D, creep_damping=BA,
                                       dynamic_damping=BA_D)
    return chain(law, 0.5)


def syrope_chain(generated):
    """The chain as a Syrope rope (MoorDyn's deck values, QUADRATIC working curves of 30
    samples) pulled past its Tmax0: the built-in SyropeCreep, or with ``generated`` its
    user law (``SyropeCreep.user_law``)."""
    from skmoor.lines import syrope

    law = syrope.syrope_law(OWC, "quadratic", 0.4, 0.5, T_MAX0, ALPHA, BETA, T_mean=T_MEAN0,
                            creep_damping=BA, dynamic_damping=BA_D)
    return chain(law.user_law() if generated else law, 2.0)


def timed_loop(system, x0, dt, duration, scheme, output):
    """(time loop s, the output(state) of every step): ``integrate`` from rest at x0."""
    from skmoor.solvers.dynamics import integrate

    out = []
    started = time.perf_counter()
    for state in integrate(system, x0, np.zeros(system.n), dt, duration, scheme=scheme,
                           report_every=1):
        out.append(output(state))
    return time.perf_counter() - started, np.array(out)


def paired(make, run, pairs):
    """Median and quartiles of ``pairs`` paired ratios of run's time loop, generated over
    hand (``make(generated)``: the model, built once each; the order alternating, after
    an untimed run of each), and the two histories' distance."""
    models = [make(False), make(True)]
    histories = [run(model)[1] for model in models]
    ratios = []
    for pair in range(pairs):
        wall = [0.0, 0.0]
        for generated in ((0, 1) if pair % 2 == 0 else (1, 0)):
            wall[generated], histories[generated] = run(models[generated])
        ratios.append(wall[1] / wall[0])
    hand, generated = histories
    apart = float(np.max(np.abs(generated - hand)) / np.ptp(hand))
    return float(np.median(ratios)), tuple(np.quantile(ratios, [0.25, 0.75])), apart


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pairs", type=int, default=PAIRS)
    parser.add_argument("--write-docs", action="store_true",
                        help="write the table into docs/speed.md")
    args = parser.parse_args(argv)
    import skmoor
    from skmoor.solvers.dynamics import Scheme

    facts = environment(["numpy", "numba", "jax"], load=True)
    print(f"commit {facts['commit']}; {facts['versions']}; {facts['machine']}")
    example = bending.load_example(tempfile.mkdtemp(prefix="skmoor-kernels-"))

    def lazy_wave(generated):
        model = bending.skmoor_model(example, "compiled" if generated else "auto")
        return model.system, skmoor.equilibrium(model).x

    def hang_off_tension(state):
        return np.linalg.norm(state.reactions[1][0])  # end A: the hang-off

    def positions(state):
        return state.x

    def chain_loop(model):
        return timed_loop(*model, 0.1, 0.1 * CREEP_STEPS, Scheme.newmark(), positions)

    rows = [("Morison in a current and waves, P1 lines (chain, node positions)",
             paired(lambda generated: chain_in_waves(generated, 0.0), chain_loop, args.pairs)),
            ("Morison in a current and waves, bending lines (chain, node positions)",
             paired(lambda generated: chain_in_waves(generated, 2e5), chain_loop, args.pairs)),
            ("VIV lift in a current and waves, P1 lines (chain, node positions)",
             paired(chain_with_lift, chain_loop, args.pairs)),
            ("bending, bending lines (flexible riser, node positions)",
             paired(bending_riser, lambda model: timed_loop(
                 *model, 0.05, 0.05 * CREEP_STEPS, Scheme.newmark(), positions), args.pairs)),
            ("sea bed and Morison, bending lines (lazy-wave cable, hang-off tension)",
             paired(lazy_wave, lambda model: timed_loop(
                 *model, STEP, bending.DURATION, Scheme.generalized_alpha(bending.RHO_INF),
                 hang_off_tension), args.pairs)),
            ("creep (viscoelastic chain, node positions)",
             paired(creep_chain, chain_loop, args.pairs)),
            ("Syrope creep (the chain past its highest tension, node positions)",
             paired(syrope_chain, chain_loop, args.pairs))]
    table = [f"- commit {facts['commit']}; {facts['versions']}; {facts['machine']}", "",
             f"| effect | time loop generated / hand, median of {args.pairs} pairs "
             "(quartiles) | histories apart |", "|---|---|---|"]
    table += [f"| {name} | **{ratio:.2f}** ({low:.2f}-{high:.2f}) | {apart:.1e} |"
              for name, (ratio, (low, high), apart) in rows]
    print()
    print("\n".join(table[2:]))
    if args.write_docs:
        write_block(ROOT / "docs" / "speed.md", "generated_kernels.py table", "\n".join(table))


if __name__ == "__main__":
    main()
