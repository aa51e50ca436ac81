"""Calls from compiled code to the generated C functions of user terms, by address.

The compiled time step calls each user LineForm's and pointwise load's generated kernel
(:mod:`skmoor.fem.form_compiler`: ``step_kernel``, ``step_load``, numba ``cfunc``s) through
its address, an integer, and so does a user law's reported tension: the compiled caller
then takes plain arrays (its code and numba's disk cache serve every form alike, and a
call from Python costs no typing of function objects). Pointers are passed as addresses
(``array.ctypes.data``).
"""
from __future__ import annotations

from llvmlite import ir
from numba import errors, typeof, types
from numba.core import cgutils
from numba.extending import intrinsic

_DOUBLE = ir.DoubleType().as_pointer()
_INT = ir.IntType(64)


def _pointers(builder, values, kinds, argtypes=None):
    """The call's arguments: addresses (or C pointers, of ``argtypes``) cast to the C
    signature's pointers ('d': double*, 'i': int64*), other values as they are ('-')."""
    out = []
    for k, (value, kind) in enumerate(zip(values, kinds)):
        pointer = {"d": _DOUBLE, "i": _INT.as_pointer()}.get(kind)
        if pointer is None:
            out.append(value)
        elif argtypes is not None and isinstance(argtypes[k], types.CPointer):
            out.append(builder.bitcast(value, pointer))
        else:
            out.append(builder.inttoptr(value, pointer))
    return out


@intrinsic
def call_form(typingctx, address, u, ud, ndofs, t, ints, floats, R, K, C, tangent):
    """step_kernel(u, ud, ndofs, t, ints, floats, R, K, C, tangent) of the C function at
    ``address`` (:data:`skmoor.fem.form_compiler.STEP_SIGNATURE`); arrays by address (or
    as C pointers)."""
    signature = types.void(address, u, ud, ndofs, t, ints, floats, R, K, C, tangent)

    def codegen(context, builder, sig, args):  # ndofs, tangent: int64; t: float64
        function = ir.FunctionType(ir.VoidType(), [_DOUBLE, _DOUBLE, _INT, ir.DoubleType(),
                                                   _INT.as_pointer(), _DOUBLE, _DOUBLE,
                                                   _DOUBLE, _DOUBLE, _INT])
        target = builder.inttoptr(args[0], function.as_pointer())
        builder.call(target, _pointers(builder, args[1:], "dd--idddd-", sig.args[1:]))
        return context.get_dummy_value()

    return signature, codegen


@intrinsic
def call_load(typingctx, address, z, out):
    """step_load(z, out) of the C function at ``address``
    (:data:`skmoor.fem.form_compiler.POINTWISE_SIGNATURE`); arrays by address."""
    signature = types.void(address, z, out)

    def codegen(context, builder, sig, args):
        function = ir.FunctionType(ir.VoidType(), [_DOUBLE, _DOUBLE])
        target = builder.inttoptr(args[0], function.as_pointer())
        builder.call(target, _pointers(builder, args[1:], "dd"))
        return context.get_dummy_value()

    return signature, codegen


@intrinsic
def advanced(typingctx, pointer, count):
    """``pointer`` moved ``count`` items along its buffer (a C pointer, as ``carray``
    takes it: a packed buffer's pieces as arrays without numba's reshape helper)."""
    def codegen(context, builder, sig, args):
        return builder.gep(args[0], [args[1]])

    return pointer(pointer, types.int64), codegen


@intrinsic
def call_compiled(typingctx, function, address, arguments, result):
    """``function(*arguments)`` through ``address``, the native entry of its compilation for
    exactly these argument types (:func:`compiled_address`), returning a value of
    ``result``'s type (a value of it: False, 0, 0.0; None for nothing): the caller's machine
    code calls the callee without linking it in, so numba optimizes and emits the callee's
    code once, not again with every calling level, and the caller compiles without it (in
    another process, as :mod:`skmoor.run.first_compile` does). Where the callee is compiled
    already its result type is checked. Its errors propagate as a direct call's."""
    dispatcher = function.dispatcher
    argtypes = tuple(arguments.types)
    restype = types.unliteral(result)
    compiled = dispatcher.overloads.get(argtypes)
    if compiled is not None and compiled.signature.return_type != restype:
        raise errors.TypingError(
            f"{dispatcher.py_func.__name__} returns {compiled.signature.return_type}, not "
            f"{restype} as its caller expects")

    def codegen(context, builder, sig, args):
        values = [builder.extract_value(args[2], i) for i in range(len(argtypes))]
        kind = context.call_conv.get_function_type(restype, argtypes)
        target = builder.inttoptr(args[1], kind.as_pointer())
        status, value = context.call_conv.call_function(builder, target, restype, argtypes,
                                                         values)
        with cgutils.if_unlikely(builder, status.is_error):
            context.call_conv.return_status_propagate(builder, status)
        return value

    return restype(function, types.int64, arguments, result), codegen


def argument_types(arguments):
    """numba's types of ``arguments`` (Python values, or numba types as they are)."""
    return tuple(a if isinstance(a, types.Type) else typeof(a) for a in arguments)


def compiled_address(function, *arguments):
    """The address (int) of ``function``'s native entry compiled for the numba types of
    ``arguments`` (Python values, or numba types), for :func:`call_compiled`."""
    argtypes = argument_types(arguments)
    function.compile(argtypes)
    result = function.overloads[argtypes]
    return result.library.get_pointer_to_function(result.fndesc.llvm_func_name)
