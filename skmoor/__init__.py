"""skmoor: nonlinear dynamics of moored floating structures on scikit-fem.

The data flow: case (TOML) or MoorDyn deck -> model (a network of points, lines and
bodies, and the System that couples them) -> solver (statics, modes, dynamics) ->
Results -> export / plots / animation.

    import skmoor
    case = skmoor.paper_case()              # or "case.toml", or a MoorDyn deck "lines.dat"
    model = skmoor.build(case)
    results = skmoor.simulate(model, duration=60.0)
    print(skmoor.summary(results)["amplitude"])
"""
import os as _os

from threadpoolctl import threadpool_limits as _threadpool_limits

# skmoor's matrices are small (hundreds to a few thousand unknowns): BLAS threads only add
# overhead, and under load they slow a 150 x 150 LU from 0.2 ms to 0.25 s. One thread
# unless SKMOOR_BLAS_THREADS says otherwise (this applies to the whole process).
_threadpool_limits(int(_os.environ.get("SKMOOR_BLAS_THREADS", 1)), user_api="blas")

from .bodies import bem
from .bodies.bem import Hydrodynamics
from .bodies.body import RigidBody  # noqa: E402
from .bodies.loads import BodyLoad, PointLoad
from .bodies.motion import Motion, Record, fade_in
from .bodies.radiation import PotentialFlow
from .coupling import rods
from .coupling.network import Body, LineFailure, MooringLine, Network, Point
from .coupling.system import Ends, PointMass, System
from .fem import ops
from .fem.terms import LineForm, TangentCheck, Term, check_tangent
from .io.case import Case, paper_case
from .io.deck import read_deck, write_deck
from .lines import laws
from .lines.catenary import Catenary, solve_catenary
from .lines.laws import Curve, Engineering, Paper, StaticDynamic
from .lines.line import Line, LineSet, LineType, read_line_mesh, write_line_mesh
from .lines.user_law import UserLaw
from .model.from_deck import heave_motion, read_motion
from .model.model import Model, build, from_network
from .model.openfast_motion import openfast_motion
from .post.results import Results
from .run.equilibrium import equilibrium, mooring_stiffness
from .run.first_compile import precompile
from .run.outputs import summary, write_outputs
from .run.recorder import static_results
from .run.simulate import run_case, simulate
from .sea.hydro import body_hydrodynamics, line_hydrodynamics
from .sea.seabed import Seabed, seabed_term
from .sea.waves import AiryWave, Current, JonswapWave, Sea
from .solvers.dynamics import Scheme, integrate
from .solvers.modes import eigenmodes
from .solvers.newton import ConvergenceError, DivergenceError
from .solvers.statics import solve_static

__version__ = "0.1.0"

__all__ = [
    "Case", "paper_case", "build", "Model", "simulate", "run_case", "summary",
    "write_outputs", "equilibrium", "precompile", "static_results", "Results", "LineType", "Line", "LineSet",
    "read_line_mesh", "write_line_mesh", "Catenary", "solve_catenary", "RigidBody",
    "System", "Term", "solve_static", "ConvergenceError", "eigenmodes", "integrate",
    "LineFailure", "Scheme", "DivergenceError", "BodyLoad", "PointLoad", "LineForm", "check_tangent",
    "TangentCheck", "laws", "Paper", "Engineering", "Curve", "StaticDynamic", "UserLaw", "Sea", "Current", "AiryWave", "JonswapWave",
    "line_hydrodynamics", "body_hydrodynamics", "Seabed", "seabed_term", "read_deck",
    "write_deck", "heave_motion", "read_motion", "openfast_motion", "Network", "Point", "MooringLine", "Body",
    "from_network", "mooring_stiffness", "Ends", "PointMass", "bem", "Hydrodynamics",
    "PotentialFlow", "rods", "Motion", "Record", "fade_in", "ops",
]
