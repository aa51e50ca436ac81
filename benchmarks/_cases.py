"""Shared set-up of the benchmarks: the chain case, its fairlead motion, and a
MoorDyn-style input deck that MoorDyn v2 and CableDyn both read.

The chain is the 50 m case of the OrcaFlex chain set (MoorDyn's validation, as
examples/decks/chain_50m.dat): D 0.252 m (volume-equivalent), 390 kg/m, EA 1.674e9 N,
Cd 1.37, Ca 1.0, CdAx 0.64, CaAx 0, anchor on the bed 400 m from the fairlead, 410 m of
unstretched chain, fairlead at the free surface; MoorDyn's bottom kBot 1e5 Pa/m,
cBot 1e4 Pa s/m.
"""
from __future__ import annotations

import contextlib
import importlib.metadata
import os
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
# skmoor from the source tree; the peers' set-up from the tests (which mirror the packages)
_TESTS = ROOT / "tests"
_FOLDERS = sorted(p for p in _TESTS.iterdir() if any(p.glob("test_*.py"))) if _TESTS.is_dir() else []
for _path in (ROOT, _TESTS, *_FOLDERS):
    if str(_path) not in sys.path:
        sys.path.insert(0, str(_path))

CHAIN = dict(diameter=0.252, mass=390.0, EA=1.674e9)
HYDRO = dict(Cd_n=1.37, Ca_n=1.0, Cd_t=0.64, Ca_t=0.0)  # MoorDyn's Cd, Ca, CdAx, CaAx
KBOT, CBOT = 1e5, 1e4  # sea-bed pressure per metre of penetration (Pa/m) and per m/s
DEPTH, SPAN, LENGTH = 50.0, 400.0, 410.0  # m
HEAVE, PERIOD = 2.0, 10.0  # fairlead heave amplitude (m) and period (s)
RAMP = PERIOD  # s, the heave amplitude rises smoothly from 0 over the first period
FAIRLEAD = np.zeros(3)  # m, where the chain's fairlead rests (the origin)


def chain_type(BA=0.0):
    """The chain as a skmoor LineType: submerged weight from the volume-equivalent D,
    drag and added-mass coefficients, internal (axial) damping BA (N s)."""
    # skmoor's imports here: a peer's whole process (benchmarks/scaling.py) need not
    from skmoor.lines.line import LineType

    return LineType(**CHAIN, **HYDRO, BA=BA)


def chain_catenary():
    """Static state of the 50 m chain: anchor at (-SPAN, 0, -DEPTH), fairlead at the
    origin, on a frictionless sea bed at -DEPTH (analytic catenary with touchdown)."""
    from skmoor.lines.catenary import solve_catenary

    lt = chain_type()
    return solve_catenary([-SPAN, 0.0, -DEPTH], [0.0, 0.0, 0.0], lt.weight, lt.EA,
                          length=LENGTH, seabed_z=-DEPTH)


def heave(t):
    """Fairlead heave z(t), velocity and acceleration (m, m/s, m/s2):
    HEAVE sin(w t) times a ramp (1 - cos(pi t / RAMP)) / 2 over the first RAMP seconds,
    so motion, velocity and acceleration all start from zero."""
    w, p = 2 * np.pi / PERIOD, np.pi / RAMP
    s, c = np.sin(w * t), np.cos(w * t)
    if t < RAMP:
        r, r1, r2 = (1 - np.cos(p * t)) / 2, p / 2 * np.sin(p * t), p**2 / 2 * np.cos(p * t)
    else:
        r, r1, r2 = 1.0, 0.0, 0.0
    return (HEAVE * s * r, HEAVE * (w * c * r + s * r1),
            HEAVE * (-w**2 * s * r + 2 * w * c * r1 + s * r2))


def heave_at(times):
    """:func:`heave`'s z and velocity at an array of times (m, m/s), vectorized."""
    t = np.asarray(times, float)
    w, p = 2 * np.pi / PERIOD, np.pi / RAMP
    s, c = np.sin(w * t), np.cos(w * t)
    ramping = t < RAMP
    r = np.where(ramping, (1 - np.cos(p * t)) / 2, 1.0)
    r1 = np.where(ramping, p / 2 * np.sin(p * t), 0.0)
    return HEAVE * s * r, HEAVE * (w * c * r + s * r1)


def line_deck(path, *, code, catenary, line_type, n_segments, dt, duration, depth,
              kBot=KBOT, cBot=CBOT, rho_inf=0.9):
    """Write a one-line deck (MoorDyn v2 format) for ``code`` 'moordyn' or 'cabledyn':
    anchor Fixed, fairlead Coupled, the line type's internal damping BA (N s), drag and
    added-mass coefficients, no bending, time step dt (s), the bottom at ``depth`` with
    kBot, cBot; CableDyn's generalized-alpha spectral radius rho_inf. The two readers
    differ only in the OPTIONS rows they accept. Returns the path."""
    num = lambda v: repr(float(v))  # noqa: E731  (numpy 2 scalars repr as np.float64(...))
    a, f = [num(v) for v in catenary.anchor], [num(v) for v in catenary.fairlead]
    lt = line_type
    row = "  ".join(num(v) for v in (lt.diameter, lt.mass, lt.EA, lt.BA, 0.0, lt.Cd_n,
                                         lt.Ca_n, lt.Cd_t, lt.Ca_t))
    options = [(num(dt), "dtM"), (num(lt.g), "g"), (num(lt.rho_water), "WtrDnsty"),
               (num(depth), "WtrDpth"), (num(kBot), "kBot"), (num(cBot), "cBot")]
    if code == "moordyn":
        options += [("0", "writeLog"), ("100.0", "TmaxIC"), ("1e-9", "threshIC"),
                    ("1", "disableOutput"), ("1", "disableOutTime")]
    elif code == "cabledyn":
        options += [(num(duration), "TMax"), (num(rho_inf), "rhoInf")]
    else:
        raise ValueError(f"line_deck code: {code!r} is not 'moordyn' or 'cabledyn'")
    rows = "\n".join(f"{value}  {name}" for value, name in options)
    text = f"""skmoor benchmark: one line, written by benchmarks/_cases.py
---------------------- LINE TYPES ----------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name)  (m)  (kg/m)  (N)  (N-s/-)  (N-m^2)  (-)  (-)  (-)  (-)
line  {row}
---------------------- POINTS --------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#)  (word)  (m)  (m)  (m)  (kg)  (m^3)  (m^2)  (-)
1  Fixed  {a[0]}  {a[1]}  {a[2]}  0  0  0  0
2  Coupled  {f[0]}  {f[1]}  {f[2]}  0  0  0  0
---------------------- LINES ---------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)  (#)  (#)  (m)  (-)  (-)
1  line  1  2  {num(catenary.L)}  {int(n_segments)}  -
---------------------- OPTIONS -------------------------------------
{rows}
---------------------- OUTPUTS -------------------------------------
---------------------- END -----------------------------------------
"""
    Path(path).write_text(text)
    return Path(path)


@contextlib.contextmanager
def quiet():
    """Silence the C-level stdout and stderr of the peers (MoorDyn prints its set-up, and
    its nodes when it blows up; the failure itself is reported from the exception)."""
    sys.stdout.flush()
    sys.stderr.flush()
    null = os.open(os.devnull, os.O_WRONLY)
    saved = [os.dup(1), os.dup(2)]
    try:
        os.dup2(null, 1)
        os.dup2(null, 2)
        yield
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (null, *saved):
            os.close(fd)


@contextlib.contextmanager
def inside(directory):
    """Work in ``directory`` (the peers may write files into the current directory)."""
    previous = os.getcwd()
    os.chdir(directory)
    try:
        yield
    finally:
        os.chdir(previous)


def write_block(path, name, text) -> bool:
    """Replace what stands between ``<!-- NAME -->`` and ``<!-- end of NAME -->`` in the
    file ``path`` (a page whose numbers this script makes) by ``text``; False (and a
    message) when the file has no such block."""
    start, end = f"<!-- {name} -->", f"<!-- end of {name} -->"
    path = Path(path)
    page = path.read_text()
    if start not in page or end not in page:
        print(f"{path}: no {start} ... {end} block; not written")
        return False
    head, rest = page.split(start, 1)
    path.write_text(f"{head}{start}\n{text.strip()}\n{end}{rest.split(end, 1)[1]}")
    print(f"wrote {name} into {path}")
    return True


def version(package):
    """The installed version of ``package``, or 'not installed'."""
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def environment(packages, load=False):
    """The facts at the top of a benchmark's report: the commit (and whether skmoor/ has
    uncommitted changes), the versions of Python and ``packages``, the machine (with its
    load average at the start when ``load``)."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as info:
            cpu = next(line.split(":", 1)[1].strip() for line in info if "model name" in line)
    except (OSError, StopIteration):
        pass
    try:
        commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--", "skmoor"],
                               capture_output=True, text=True, check=True).stdout.strip()
        commit += " (skmoor/ has uncommitted changes)" if dirty else ""
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    machine = f"{cpu}, {os.cpu_count()} cores"
    machine += (f", load average {os.getloadavg()[0]:.1f} at the start (other jobs share it; "
                "ratios, not times, carry over)" if load
                else f", {platform.system()} {platform.release()}")
    return {
        "commit": commit,
        "versions": ", ".join([f"Python {platform.python_version()}"]
                              + [f"{p} {version(p)}" for p in packages]),
        "machine": machine,
    }
