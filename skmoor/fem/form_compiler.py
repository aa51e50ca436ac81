"""User forms at compiled speed: a residual integrand traced by JAX, written out as
straight-line scalar code and compiled by numba into an element loop.

A line integrand f(v, w) is linear in the test function, f = a . v + b . v' at each
quadrature point, with a, b (3 each) functions of the state at that point: u, u', udot,
udot' (12 numbers) and the fields there. JAX traces a = f(e_c, 0), b = f(0, e_c) and their
forward-mode derivatives with respect to the 12 state numbers into a jaxpr; this module
evaluates the jaxpr symbolically on scalars (every array element becomes a named scalar,
constants folded, unused values dropped) and emits one numba function per form, cached on
disk (``SKMOOR_CACHE``, default ``~/.cache/skmoor``), that loops over elements and
quadrature points and adds the residual and the (6, 6) element blocks (on the Hermite
element of bending lines (12, 12), phi_i its cubics)

    R_i  += dx (a phi_i + b phi_i'),
    K_ij += dx (da/du phi_i phi_j + da/du' phi_i phi_j' + db/du phi_i' phi_j + db/du' phi_i' phi_j'),

(C_ij the same with udot) exactly as the built-in kernels do. On bending lines a form may
also read u'' and udot'' and act on v'' (f = a . v + b . v' + c . v''): its inputs then end
with u'' and udot'', and the loop adds c phi_i'' and the slopes in all 18 state numbers
(:func:`_hermite_scatter`). A jaxpr with a primitive not
covered here (loops, sorts, ...) raises :class:`Unsupported`; the caller then keeps JAX's
own compiler (``jax.jit``).
"""
from __future__ import annotations

import functools
import hashlib
import importlib.util
import math
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

STATE = 12  # u (3), u' (3), udot (3), udot' (3)


class Unsupported(NotImplementedError):
    """A jaxpr primitive the scalar code generator does not cover."""


def cache_directory() -> Path:
    """Where generated kernels live: $SKMOOR_CACHE/forms (default ~/.cache/skmoor/forms),
    or the temporary directory where that cannot be written."""
    path = Path(os.environ.get("SKMOOR_CACHE", Path.home() / ".cache" / "skmoor")) / "forms"
    try:
        path.mkdir(parents=True, exist_ok=True)
        return path
    except OSError:
        fallback = Path(tempfile.gettempdir()) / "skmoor-forms"
        fallback.mkdir(parents=True, exist_ok=True)
        return fallback


# --- symbolic scalar evaluation of a jaxpr

class _Code:
    """Straight-line scalar code: lines ``name = expression`` with their operands."""

    def __init__(self):
        self.lines = []  # (name, expression, operand names)
        self.names = {}  # expression -> name: one line per distinct value

    def emit(self, expression, operands):
        name = self.names.get(expression)
        if name is None:
            name = self.names[expression] = f"v{len(self.lines)}"
            self.lines.append((name, expression, [o for o in operands if isinstance(o, str)]))
        return name

    def used(self, outputs):
        """The lines the outputs need, in order (dead code dropped)."""
        needed = {o for o in outputs if isinstance(o, str)}
        keep = []
        for name, expression, operands in reversed(self.lines):
            if name in needed:
                keep.append((name, expression))
                needed.update(operands)
        return keep[::-1]


def _literal(x):
    """Source text of a number."""
    if isinstance(x, (bool, np.bool_)):
        return "True" if x else "False"
    x = float(x)
    if math.isnan(x):
        return "math.nan"
    if math.isinf(x):
        return "math.inf" if x > 0 else "-math.inf"
    return repr(x)


def _text(x):
    return x if isinstance(x, str) else _literal(x)


def _number(x):
    return not isinstance(x, str)


_UNARY = {
    "neg": ("(-{0})", lambda a: -a),
    "sqrt": ("math.sqrt({0})", lambda a: math.sqrt(a) if a >= 0 else math.nan),
    "rsqrt": ("(1.0 / math.sqrt({0}))", lambda a: 1 / math.sqrt(a)),
    "exp": ("math.exp({0})", math.exp),
    "log": ("math.log({0})", math.log),
    "log1p": ("math.log1p({0})", math.log1p),
    "expm1": ("math.expm1({0})", math.expm1),
    "tanh": ("math.tanh({0})", math.tanh),
    "sin": ("math.sin({0})", math.sin),
    "cos": ("math.cos({0})", math.cos),
    "tan": ("math.tan({0})", math.tan),
    "asinh": ("math.asinh({0})", math.asinh),
    "acosh": ("math.acosh({0})", math.acosh),
    "atanh": ("math.atanh({0})", math.atanh),
    "asin": ("math.asin({0})", math.asin),
    "acos": ("math.acos({0})", math.acos),
    "atan": ("math.atan({0})", math.atan),
    "sinh": ("math.sinh({0})", math.sinh),
    "cosh": ("math.cosh({0})", math.cosh),
    "erf": ("math.erf({0})", math.erf),
    "abs": ("abs({0})", abs),
    "sign": ("(1.0 if {0} > 0 else (-1.0 if {0} < 0 else 0.0 * {0}))", lambda a: float(np.sign(a))),
    "floor": ("np.floor({0})", math.floor),
    "ceil": ("np.ceil({0})", math.ceil),
    "not": ("(not {0})", lambda a: not a),
    "is_finite": ("math.isfinite({0})", math.isfinite),
    "logistic": ("(1.0 / (1.0 + math.exp(-{0})))", lambda a: 1 / (1 + math.exp(-a))),
    "square": ("({0} * {0})", lambda a: a * a),
    "copy": ("{0}", lambda a: a),
    "copy_p": ("{0}", lambda a: a),
    "stop_gradient": ("{0}", lambda a: a),
    "real": ("{0}", lambda a: a),
}

_BINARY = {
    "add": ("({0} + {1})", lambda a, b: a + b),
    "add_any": ("({0} + {1})", lambda a, b: a + b),
    "sub": ("({0} - {1})", lambda a, b: a - b),
    "mul": ("({0} * {1})", lambda a, b: a * b),
    "div": ("({0} / {1})", lambda a, b: a / b if b != 0 else math.copysign(math.inf, a) * math.copysign(1, b) if a != 0 else math.nan),
    "max": ("max({0}, {1})", max),
    "min": ("min({0}, {1})", min),
    "pow": ("({0} ** {1})", lambda a, b: a ** b),
    "atan2": ("math.atan2({0}, {1})", math.atan2),
    "rem": ("np.fmod({0}, {1})", math.fmod),
    "gt": ("({0} > {1})", lambda a, b: a > b),
    "lt": ("({0} < {1})", lambda a, b: a < b),
    "ge": ("({0} >= {1})", lambda a, b: a >= b),
    "le": ("({0} <= {1})", lambda a, b: a <= b),
    "eq": ("({0} == {1})", lambda a, b: a == b),
    "ne": ("({0} != {1})", lambda a, b: a != b),
    "and": ("({0} and {1})", lambda a, b: a and b),
    "or": ("({0} or {1})", lambda a, b: a or b),
    "nextafter": ("np.nextafter({0}, {1})", np.nextafter),
}


class _Evaluator:
    """Evaluates jaxprs on object arrays of scalars (names or numbers), writing _Code."""

    def __init__(self, code):
        self.code = code

    # elementwise, with constant folding and the identities x + 0, x * 1, x * 0
    def unary(self, op, a):
        template, fold = _UNARY[op]
        if _number(a):
            try:
                return fold(a)
            except (ValueError, OverflowError, ZeroDivisionError):
                pass
        if template == "{0}":
            return a
        return self.code.emit(template.format(_text(a)), [a])

    def binary(self, op, a, b):
        template, fold = _BINARY[op]
        if _number(a) and _number(b):
            try:
                return fold(a, b)
            except (ValueError, OverflowError, ZeroDivisionError):
                pass
        if op in ("add", "add_any"):
            if _number(a) and a == 0 and not isinstance(a, bool):
                return b
            if _number(b) and b == 0 and not isinstance(b, bool):
                return a
        elif op == "sub" and _number(b) and b == 0:
            return a
        elif op == "mul":
            for x, y in ((a, b), (b, a)):
                if _number(x) and not isinstance(x, bool):
                    if x == 0:
                        return 0.0
                    if x == 1:
                        return y
        elif op == "div" and _number(b) and b == 1:
            return a
        elif op == "div" and _number(a) and a == 0 and not isinstance(a, bool):
            return 0.0  # JAX's tangent of a term free of one input (0 / x, x != 0 there)
        elif op == "pow" and _number(b) and b == 2:
            return self.code.emit(f"({_text(a)} * {_text(a)})", [a])
        return self.code.emit(template.format(_text(a), _text(b)), [a, b])

    def select(self, predicate, cases):
        if _number(predicate):
            return cases[int(predicate)]
        if len(cases) != 2:
            raise Unsupported("select_n with more than two cases")
        if cases[0] == cases[1] and not isinstance(cases[0], float) or (
                _number(cases[0]) and _number(cases[1]) and cases[0] == cases[1]):
            return cases[0]
        return self.code.emit(f"({_text(cases[1])} if {_text(predicate)} else "
                              f"{_text(cases[0])})", [predicate, *cases])

    def convert(self, a, dtype, source):
        kind = np.dtype(dtype).kind
        if kind == "f" and np.dtype(source).kind == "b" and not _number(a):
            return self.code.emit(f"(1.0 if {a} else 0.0)", [a])
        if kind == "b":
            return bool(a) if _number(a) else self.code.emit(f"({a} != 0)", [a])
        if kind in "iu":
            return int(a) if _number(a) else self.code.emit(f"int({a})", [a])
        if _number(a):
            return float(a)
        return self.code.emit(f"float({a})", [a])

    def total(self, terms, op="add"):
        out = 0.0 if op == "add" else None
        for x in terms:
            out = x if out is None else self.binary(op, out, x)
        return out

    # jaxprs
    def run(self, jaxpr, consts, args):
        env = {}

        def read(v):
            if hasattr(v, "val"):  # a Literal
                return np.asarray(v.val, dtype=object) if np.ndim(v.val) else \
                    np.array(_scalar(v.val), dtype=object)
            return env[v]

        for v, c in zip(jaxpr.constvars, consts):
            env[v] = _constant(c)
        for v, a in zip(jaxpr.invars, args):
            env[v] = a
        for eqn in jaxpr.eqns:
            inputs = [read(v) for v in eqn.invars]
            outputs = self.primitive(eqn.primitive.name, inputs, eqn.params, eqn)
            for v, out in zip(eqn.outvars, outputs):
                env[v] = out
        return [read(v) for v in jaxpr.outvars]

    def call(self, closed, inputs):
        inner = getattr(closed, "jaxpr", closed)
        consts = getattr(closed, "consts", ())
        return self.run(inner, consts, inputs)

    def elementwise(self, f, *arrays):
        arrays = np.broadcast_arrays(*[np.asarray(a, dtype=object) for a in arrays])
        out = np.empty(arrays[0].shape, dtype=object)
        for index in np.ndindex(out.shape):
            out[index] = f(*[a[index] for a in arrays])
        return out

    def primitive(self, name, x, p, eqn):
        if name in _UNARY:
            return [self.elementwise(lambda a: self.unary(name, a), x[0])]
        if name == "integer_pow":
            y = p["y"]

            def power(a):
                if _number(a):
                    return a ** y
                if y == 2:
                    return self.code.emit(f"({a} * {a})", [a])
                return self.code.emit(f"({a} ** {y})", [a])
            return [self.elementwise(power, x[0])]
        if name in _BINARY:
            return [self.elementwise(lambda a, b: self.binary(name, a, b), x[0], x[1])]
        if name == "select_n":
            return [self.elementwise(lambda c, *cases: self.select(c, cases), *x)]
        if name == "clamp":
            return [self.elementwise(lambda lo, a, hi: self.binary(
                "min", self.binary("max", a, lo), hi), *x)]
        if name == "convert_element_type":
            source = eqn.invars[0].aval.dtype
            return [self.elementwise(lambda a: self.convert(a, p["new_dtype"], source), x[0])]
        if name == "broadcast_in_dim":
            shape, dims = tuple(p["shape"]), p["broadcast_dimensions"]
            tmp = [1] * len(shape)
            for i, d in enumerate(dims):
                tmp[d] = x[0].shape[i]
            return [np.broadcast_to(x[0].reshape(tmp), shape).copy()]
        if name == "reshape":
            return [x[0].reshape(tuple(p["new_sizes"]))]
        if name == "squeeze":
            return [np.squeeze(x[0], axis=tuple(p["dimensions"]))]
        if name == "expand_dims":
            return [np.expand_dims(x[0], tuple(p["dimensions"]))]
        if name == "transpose":
            return [x[0].transpose(p["permutation"])]
        if name == "rev":
            return [np.flip(x[0], tuple(p["dimensions"]))]
        if name == "slice":
            strides = p["strides"] or [1] * x[0].ndim
            index = tuple(slice(s, e, k) for s, e, k in
                          zip(p["start_indices"], p["limit_indices"], strides))
            return [x[0][index].copy()]
        if name == "dynamic_slice":
            starts = [_static_index(s, "dynamic_slice") for s in x[1:]]
            index = tuple(slice(s, s + n) for s, n in zip(starts, p["slice_sizes"]))
            return [x[0][index].copy()]
        if name == "dynamic_update_slice":
            out = x[0].copy()
            starts = [_static_index(s, "dynamic_update_slice") for s in x[2:]]
            out[tuple(slice(s, s + n) for s, n in zip(starts, x[1].shape))] = x[1]
            return [out]
        if name == "concatenate":
            return [np.concatenate(x, axis=p["dimension"])]
        if name == "stack":
            return [np.stack(x, axis=p["axis"])]
        if name == "split":
            edges = np.cumsum(p["sizes"])[:-1]
            return [part.copy() for part in np.split(x[0], edges, axis=p["axis"])]
        if name == "pad":
            return [self.pad(x[0], x[1], p["padding_config"])]
        if name == "iota":
            shape, dim = tuple(p["shape"]), p["dimension"]
            return [np.indices(shape)[dim].astype(object)]
        if name in ("reduce_sum", "reduce_max", "reduce_min", "reduce_and", "reduce_or"):
            op = {"reduce_sum": "add", "reduce_max": "max", "reduce_min": "min",
                  "reduce_and": "and", "reduce_or": "or"}[name]
            return [self.reduce(x[0], tuple(p["axes"]), op)]
        if name == "dot_general":
            return [self.dot_general(x[0], x[1], p["dimension_numbers"])]
        if name in ("pjit", "jit", "closed_call", "core_call", "remat", "checkpoint",
                    "custom_jvp_call", "custom_vjp_call", "custom_vjp_call_jaxpr"):
            closed = (p.get("jaxpr") or p.get("call_jaxpr") or p.get("fun_jaxpr"))
            if closed is None:
                raise Unsupported(f"{name} without a jaxpr")
            return self.call(closed, x[: len(getattr(closed, "jaxpr", closed).invars)])
        raise Unsupported(name)

    def pad(self, a, value, config):
        out = a
        for axis, (low, high, interior) in enumerate(config):
            if interior:
                raise Unsupported("pad with interior padding")
            if low < 0:
                out = np.take(out, range(-low, out.shape[axis]), axis=axis)
                low = 0
            if high < 0:
                out = np.take(out, range(out.shape[axis] + high), axis=axis)
                high = 0
            shape = list(out.shape)
            shape[axis] = low
            before = np.full(shape, value.item(), dtype=object)
            shape[axis] = high
            after = np.full(shape, value.item(), dtype=object)
            out = np.concatenate([before, out, after], axis=axis)
        return out

    def reduce(self, a, axes, op):
        kept = [i for i in range(a.ndim) if i not in axes]
        moved = a.transpose(kept + list(axes))
        shape = moved.shape[: len(kept)]
        flat = moved.reshape(shape + (-1,))
        out = np.empty(shape, dtype=object)
        for index in np.ndindex(shape):
            out[index] = self.total(list(flat[index]), op)
        return out

    def dot_general(self, lhs, rhs, numbers):
        (lc, rc), (lb, rb) = numbers
        lf = [i for i in range(lhs.ndim) if i not in lc and i not in lb]
        rf = [i for i in range(rhs.ndim) if i not in rc and i not in rb]
        L = lhs.transpose(list(lb) + lf + list(lc))
        R = rhs.transpose(list(rb) + rf + list(rc))
        nb = len(lb)
        batch = L.shape[:nb]
        lfree, rfree = L.shape[nb: nb + len(lf)], R.shape[nb: nb + len(rf)]
        k = int(np.prod(L.shape[nb + len(lf):], dtype=int))
        L = L.reshape(batch + lfree + (k,))
        R = R.reshape(batch + rfree + (k,))
        out = np.empty(batch + lfree + rfree, dtype=object)
        for b in np.ndindex(batch):
            for i in np.ndindex(lfree):
                for j in np.ndindex(rfree):
                    products = [self.binary("mul", L[b + i + (m,)], R[b + j + (m,)])
                                for m in range(k)]
                    out[b + i + j] = self.total(products)
        return out


def _scalar(x):
    x = np.asarray(x).item()
    return bool(x) if isinstance(x, (bool, np.bool_)) else x


def _constant(c):
    arr = np.asarray(c)
    out = np.empty(arr.shape, dtype=object)
    for index in np.ndindex(arr.shape):
        out[index] = _scalar(arr[index])
    return out


def _static_index(s, what):
    value = s.item() if isinstance(s, np.ndarray) else s
    if not _number(value):
        raise Unsupported(f"{what} with an index that depends on the state")
    return int(value)


def scalar_function(jaxpr, consts, n_inputs, name):
    """(source of ``def name(z, out)``: the jaxpr's outputs (flattened) from z (n_inputs,),
    the number of outputs, the indices of the inputs they depend on)."""
    code = _Code()
    if len(jaxpr.invars) != 1:
        raise Unsupported("a jaxpr of one input vector z was expected")
    args = [np.array([f"z{k}" for k in range(n_inputs)], dtype=object)]
    outputs = _Evaluator(code).run(jaxpr, consts, args)
    flat = np.concatenate([np.asarray(o, dtype=object).ravel() for o in outputs])
    kept = code.used(list(flat))
    names = {n for n, _ in kept}
    read = {o for n, _, operands in code.lines if n in names for o in operands}
    read.update(v for v in flat if isinstance(v, str))
    used = sorted(k for k in range(n_inputs) if f"z{k}" in read)
    body = [f"    z{k} = z[{k}]" for k in used]
    body += [f"    {n} = {e}" for n, e in kept]
    body += [f"    out[{k}] = {_text(v)}" for k, v in enumerate(flat)]
    return "\n".join(["@njit(cache=True, error_model='numpy')", f"def {name}(z, out):"]
                     + body), flat.size, used


def zero_outputs(jaxpr, consts, n_inputs):
    """The indices of the jaxpr's (flattened) outputs that are the constant 0 whatever
    the inputs: the generated element loops leave their terms out."""
    args = [np.array([f"z{k}" for k in range(n_inputs)], dtype=object)]
    outputs = _Evaluator(_Code()).run(jaxpr, consts, args)
    flat = np.concatenate([np.asarray(o, dtype=object).ravel() for o in outputs])
    return {k for k, v in enumerate(flat) if _number(v) and float(v) == 0.0}


def _inputs_code(used, hermite, NP, second=None):
    """The loops' code that fills z at quadrature point q of element e, the inputs in
    ``used`` only: u, u', udot, udot' (z 0-11; P1: phi (2, nqp) and the slope over the
    length he; Hermite: phi (2, nel, nqp, 4), see :func:`_hermite_scatter`), t (12), the
    arclength (13), the per-point fields P (14 ...) and the DOF fields D with their
    slopes (after P, 6 each); with ``second`` (Hermite) u'' and udot'' from z[second]
    on (phi (3, nel, nqp, 4): the cubics' d2/ds2 too)."""
    used, lines = set(used), []

    def interpolated(vector, value, slope, c, curvature=-1):
        # z[value], z[slope] (and z[curvature]) of component c
        if value not in used and slope not in used and curvature not in used:
            return
        if hermite:
            lines.extend([
                "s0 = s1 = s2 = 0.0", "for b in range(4):",
                f"    k = edofs[e, 3 * b + {c}]",
                f"    s0 += phi[0, e, q, b] * {vector.format('k')}",
                f"    s1 += phi[1, e, q, b] * {vector.format('k')}"]
                + [f"    s2 += phi[2, e, q, b] * {vector.format('k')}"] * (curvature in used))
            a, b = "s0", "s1"
        else:
            lines.append(f"a, b = {vector.format(f'edofs[e, {c}]')}, "
                         f"{vector.format(f'edofs[e, {3 + c}]')}")
            a, b = "phi[0, q] * a + phi[1, q] * b", "(b - a) / he"
        lines.extend([f"z[{value}] = {a}"] * (value in used)
                     + [f"z[{slope}] = {b}"] * (slope in used)
                     + [f"z[{curvature}] = s2"] * (curvature in used))

    for base, vector in ((0, "u[{}]"), (6, "ud[{}]")):
        for c in range(3):
            interpolated(vector, base + c, base + 3 + c, c,
                         -1 if second is None else second + base // 2 + c)
    lines.extend(["z[12] = t"] * (12 in used) + ["z[13] = x[e, q]"] * (13 in used))
    lines.extend(f"z[{14 + k}] = P[e, q, {k}]" for k in range(NP) if 14 + k in used)
    end = math.inf if second is None else second  # (u'' and udot'' after the D fields)
    for m in sorted({(k - 14 - NP) // 6 for k in used if 14 + NP <= k < end}):
        for c in range(3):
            interpolated(f"D[{m}, {{}}]", 14 + NP + 6 * m + c, 17 + NP + 6 * m + c, c)
    return "".join(f"            {line}\n" for line in lines)


_LOOP = '''

@njit(cache=True, error_model="numpy")
def kernel(u, ud, t, edofs, h, dx, phi, x, P, D, R, Ke, Ce, tangent):
    """Adds the form's residual into R and, with ``tangent``, its element blocks."""
    nel, nqp = dx.shape
    z = np.empty({n_inputs})
    out = np.empty({n_outputs})
    for e in range(nel):
        he = h[e]
        for q in range(nqp):
{inputs}            if tangent:
                point_tangent(z, out)
            else:
                point(z, out)
{scatter}'''

def _written_sum(zero, *parts):
    """Source of sum out[k] * factor over ``parts`` (k, factor), the k in ``zero`` left out."""
    return " + ".join(f"out[{k}] * {factor}" for k, factor in parts if k not in zero)


def _hermite_scatter(zero, rows):
    """The Hermite element's accumulation of R, Ke, Ce at one point, written out term by
    term without the derivatives in ``zero``. phi (rows, nel, nqp, 4): each element's
    cubics for the DOFs [u_i, u_i', u_j, u_j'] (local DOF 3 b + c of cubic b, component
    c) and their d/ds (and with rows 3 their d2/ds2); the integrand a . v + b . v' (+ c .
    v'') in out[0:3 rows], its slopes out[3 rows + S r + s] in the S state numbers s: u,
    u', udot, udot' (0-11) and with rows 3 u'' (12-14), udot'' (15-17)."""
    size = 3 * rows
    S = STATE + 6 * (rows - 2)
    stiffness = {0: 0, 1: 3, 2: STATE}  # where each derivative order's state starts
    rate = {0: 6, 1: 9, 2: STATE + 3}

    lines = ["            w = dx[e, q]", "            for i in range(4):"]
    for c in range(3):
        value = _written_sum(zero, *[(3 * p + c, f"phi[{p}, e, q, i]")
                                     for p in range(rows)])
        if value:
            lines.append(f"                R[edofs[e, 3 * i + {c}]] += w * ({value})")
    if len(lines) == 2:
        lines.append("                pass")
    lines += ["            if not tangent:", "                continue",
              "            for i in range(4):", "                for j in range(4):"]
    lines += [f"                    f{p}{r} = phi[{p}, e, q, i] * phi[{r}, e, q, j]"
              for p in range(rows) for r in range(rows)]
    body = []
    for c in range(3):
        for d in range(3):
            for block, start in (("Ke", stiffness), ("Ce", rate)):
                value = _written_sum(zero, *[(size + S * (3 * p + c) + start[r] + d,
                                              f"f{p}{r}")
                                             for p in range(rows) for r in range(rows)])
                if value:
                    body.append(f"                    {block}[e, 3 * i + {c}, 3 * j + {d}] "
                                f"+= w * ({value})")
    return "\n".join(lines + (body or ["                    pass"])) + "\n"


# the generated kernel behind a C signature, for the compiled time step: the step passes
# every user form's arrays packed in two flat buffers (see :func:`packed`) and calls the
# forms through one function type, so that it is compiled once for all forms
STEP_SIGNATURE = ("void(CPointer(float64), CPointer(float64), int64, float64, CPointer(int64), "
                  "CPointer(float64), CPointer(float64), CPointer(float64), CPointer(float64), "
                  "int64)")


def compiled_when_asked(kernel):
    """A getter of ``kernel`` (a Python function of :data:`STEP_SIGNATURE`'s arguments) as
    a C function, compiled on the getter's first call and kept (numba's disk cache keeps
    its machine code): a built-in kernel a run does not use costs no compile."""
    from numba import cfunc

    return functools.cache(lambda: cfunc(STEP_SIGNATURE, cache=True)(kernel))
# the packed arrays unpacked (see :func:`packed`) as C arrays at their offsets;
# ``total``: how many floats they are
_UNPACK = """    nel, nloc, nqp, NP, ND = ints[0], ints[1], ints[2], ints[3], ints[4]
    edofs = carray(advanced(ints, 5), (nel, nloc))
    nphi = {phi_size}
    h = carray(floats, (nel,))
    dx = carray(advanced(floats, nel), (nel, nqp))
    start = nel + nel * nqp
    phi = carray(advanced(floats, start), {phi_shape})
    start += nphi
    x = carray(advanced(floats, start), (nel, nqp))
    start += nel * nqp
    P = carray(advanced(floats, start), (nel, nqp, NP))
    start += nel * nqp * NP
    D = carray(advanced(floats, start), (ND, ndofs))
    total = start + ND * ndofs
"""

_STEP = '''

@cfunc("{signature}", cache=True)
def step_kernel(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """``kernel`` on the arrays packed by skmoor.fem.form_compiler.packed."""
{unpack}    nblocks = nel if tangent else 0
    kernel(carray(u_p, (ndofs,)), carray(ud_p, (ndofs,)), t, edofs, h, dx, phi, x, P, D,
           carray(R_p, (ndofs,)), carray(K_p, (nblocks, nloc, nloc)),
           carray(C_p, (nblocks, nloc, nloc)), tangent != 0)
'''

# a form with a memory: its state is per-point fields (columns of P) that change only
# when a step is accepted, to ``update``'s values from the point's inputs and the step dt
_COMMIT = '''

@njit(cache=True, error_model="numpy")
def commit(u, ud, t, edofs, h, dx, phi, x, P, D, columns, dt):
    """Writes the state's new values at each point into its columns of P."""
    nel, nqp = dx.shape
    z = np.empty({n_inputs} + 1)
    out = np.empty({n_state})
    for e in range(nel):
        he = h[e]
        for q in range(nqp):
{inputs}            z[{n_inputs}] = dt
            update(z, out)
            for k in range({n_state}):
                P[e, q, columns[k]] = out[k]


@cfunc("{signature}", cache=True)
def step_commit(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """``commit`` on the packed arrays (ints: then the state's columns of P; floats: then
    the time of the last commit, NaN before the first: dt 0 there and on a restart)."""
{unpack}    columns = carray(advanced(ints, 5 + nel * nloc), ({n_state},))
    last = floats[total]
    dt = t - last if t >= last else 0.0
    commit(carray(u_p, (ndofs,)), carray(ud_p, (ndofs,)), t, edofs, h, dx, phi, x, P, D,
           columns, dt)
    floats[total] = t
'''


def packed(edofs, h, dx, phi, x, P, D):
    """(ints, floats): a form's arrays as its ``step_kernel`` reads them, int64 [nel, nloc,
    nqp, NP, ND, edofs...] and float64 [h, dx, phi, x, P, D] (each C-ordered)."""
    (nel, nloc), nqp = edofs.shape, dx.shape[1]
    ints = np.concatenate([[nel, nloc, nqp, P.shape[2], D.shape[0]], np.ravel(edofs)])
    floats = np.concatenate([np.ravel(a) for a in (h, dx, phi, x, P, D)])
    return ints.astype(np.int64), floats.astype(float)


# a pointwise load F(q, qdot, t) on n DOFs with its derivatives, behind a C signature:
# z = [q (n), qdot (n), t], out = [F (n), dF/dq (n, n), dF/dqdot (n, n)]
POINTWISE_SIGNATURE = "void(CPointer(float64), CPointer(float64))"
_POINTWISE = '''

@cfunc("{signature}", cache=True)
def step_load(z_p, out_p):
    """``load`` on raw pointers, for the compiled time step."""
    load(carray(z_p, ({n_inputs},)), carray(out_p, ({n_outputs},)))
'''


def build_pointwise(jaxpr, consts, n_inputs, label):
    """Writes (once) and imports the numba module of a pointwise load's jaxpr (outputs F
    and its derivatives, from z = [q, qdot, t]); returns its ``step_load`` (C function
    of :data:`POINTWISE_SIGNATURE`)."""
    body, n_outputs, _ = scalar_function(jaxpr, consts, n_inputs, "load")
    source = "\n".join([f'"""Generated by skmoor.fem.form_compiler: {label} (do not edit)."""',
                        "import math", "", "import numpy as np",
                        "from numba import carray, cfunc, njit", "", "", body,
                        _POINTWISE.format(signature=POINTWISE_SIGNATURE, n_inputs=n_inputs,
                                          n_outputs=n_outputs)])
    return _load_module(source, "load")[0].step_load


def _p1_scatter(zero):
    """The P1 loop's accumulation of R, Ke, Ce at one point, written out term by term
    without the derivatives in ``zero`` (out[6 + 12 r + s]: d(a, b)_r / d(state)_s)."""
    lines = ["            w = dx[e, q]", "            for i in range(2):",
             "                si = (-1.0 if i == 0 else 1.0) / he"]
    for c in range(3):
        value = _written_sum(zero, (c, "phi[i, q]"), (3 + c, "si"))
        if value:
            lines.append(f"                R[edofs[e, 3 * i + {c}]] += w * ({value})")
    lines += ["            if not tangent:", "                continue",
              "            for i in range(2):",
              "                si = (-1.0 if i == 0 else 1.0) / he",
              "                for j in range(2):",
              "                    sj = (-1.0 if j == 0 else 1.0) / he",
              "                    pp, ps, sp_, ss = (phi[i, q] * phi[j, q], phi[i, q] * sj,",
              "                                       si * phi[j, q], si * sj)"]
    body = []
    for c in range(3):
        ra, rb = 6 + 12 * c, 6 + 12 * (3 + c)
        for d in range(3):
            for block, shift in (("Ke", 0), ("Ce", 6)):
                value = _written_sum(zero, (ra + shift + d, "pp"), (ra + shift + 3 + d, "ps"),
                              (rb + shift + d, "sp_"), (rb + shift + 3 + d, "ss"))
                if value:
                    body.append(f"                    {block}[e, 3 * i + {c}, 3 * j + {d}] "
                                f"+= w * ({value})")
    return "\n".join(lines + (body or ["                    pass"])) + "\n"


def build_kernel(residual_jaxpr, tangent_jaxpr, n_inputs, n_fields, hermite=False,
                 update_jaxpr=None, second=None):
    """Writes (once) and imports the numba module of a form (``n_fields`` per-point
    fields P); returns the module: its ``kernel`` (element loop of the P1 line element,
    or with ``hermite`` of the Hermite one) and ``step_kernel`` (the same behind
    :data:`STEP_SIGNATURE`), and its path. With ``update_jaxpr`` (a memory's new values
    from z and the step dt, z[n_inputs]) also ``commit`` and ``step_commit`` (see
    :data:`_COMMIT`). ``second`` (Hermite): a form of the second derivatives too, u''
    and udot'' at z[second:second + 6] (see :func:`_hermite_scatter`)."""
    point, n_point, used = scalar_function(*residual_jaxpr, n_inputs, "point")
    tangent, n_tangent, used_too = scalar_function(*tangent_jaxpr, n_inputs, "point_tangent")
    sizes = (9, 9 + 9 * (STATE + 6)) if second is not None else (6, 6 + 6 * STATE)
    if (n_point, n_tangent) != sizes:
        raise Unsupported(f"unexpected output sizes {n_point}, {n_tangent}")
    rows = 3 if second is not None else 2
    phi = dict(phi_size=f"{rows} * nel * nqp * 4" if hermite else "2 * nqp",
               phi_shape=f"({rows}, nel, nqp, 4)" if hermite else "(2, nqp)")
    parts = ['"""Generated by skmoor.fem.form_compiler: one user form (do not edit)."""',
             "import math", "", "import numpy as np", "from numba import carray, cfunc, njit",
             "", "from skmoor.fem.native_calls import advanced", "", "", point, "", "", tangent,
             _LOOP.format(n_inputs=n_inputs, n_outputs=n_tangent,
                          inputs=_inputs_code(set(used) | set(used_too), hermite, n_fields,
                                              second),
                          scatter=_hermite_scatter(zero_outputs(*tangent_jaxpr, n_inputs),
                                                   3 if second is not None else 2)
                          if hermite else _p1_scatter(zero_outputs(*tangent_jaxpr, n_inputs))),
             _STEP.format(signature=STEP_SIGNATURE, unpack=_UNPACK.format(**phi))]
    if update_jaxpr is not None:
        update, n_state, used = scalar_function(*update_jaxpr, n_inputs + 1, "update")
        parts += ["", "", update, _COMMIT.format(
            signature=STEP_SIGNATURE, n_inputs=n_inputs, n_state=n_state,
            inputs=_inputs_code(set(used) - {n_inputs}, hermite, n_fields, second),
            unpack=_UNPACK.format(**phi))]
    return _load_module("\n".join(parts), "form")


def _load_module(source, kind):
    """(module, path) of generated source: written once to the cache directory, imported
    under a name of its digest (numba's disk cache finds it again by that name)."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    path = cache_directory() / f"{kind}_{digest}.py"
    if not path.exists():
        temporary = path.with_suffix(f".{os.getpid()}.tmp")
        temporary.write_text(source)
        temporary.replace(path)
    name = f"skmoor_{kind}_{digest}"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        try:  # the C wrapper compiles as the module loads
            spec.loader.exec_module(module)
        except Exception as error:  # numba's typing and lowering errors
            del sys.modules[name]
            raise Unsupported(f"numba: {str(error).strip().splitlines()[0][:120]}") from error
    return sys.modules[name], path
