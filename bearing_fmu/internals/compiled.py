"""Compiled force kernels of bearing internals: what a compiled host loop calls.

An internal whose force and Jacobian are compiled code offers ``compiled_force()`` (its
``Capabilities.compiled`` says so): a ``CompiledForce`` holding a numba ``cfunc`` of the one
signature ``KERNEL_SIG`` and the float64 array it reads, or None when this instance has none
(then the caller uses ``force_and_jacobian``). A host's compiled loop (the rotor host's Newmark
integrator, ``rotor_host.integrate.newmark_loop``) takes the kernels as first-class functions of
that signature, so one compiled loop (cached on disk) serves every internal, and evaluates a
bearing with no Python call. The loop receives the kernels' addresses (``CompiledForce.address``)
as integers and makes them callable with ``kernel_at``: a cfunc object passed to a numba
function is unboxed through Python at every call (~0.4 ms), an integer is not.

    status = kernel(data, y, z, vy, vz, omega, out)      data, out: float64 pointers

with y, z [m], vy, vz [m/s], omega [rad/s]; out[0:2] = (Fy, Fz) [N] and out[2:10] the Jacobian
J (2, 4) = dF/d(y, z, vy, vz), row-major (raw derivatives, as ``force_and_jacobian``). status 0:
evaluated, with the same numbers ``force_and_jacobian`` gives; any other value: the state is one
the internal refuses (BearingStateError), and the caller asks ``force_and_jacobian`` again for
the refusal and its message. A kernel's answer depends on the state alone (a memoryless
internal; an internal whose answer depends on its history offers none); a kernel may keep a
hint that makes its next call faster in its data (the Taylor guard's last nearest training
state). An internal that counts its evaluations (the guard's excursions) gives ``sync``: the
host calls it with the number of evaluations a compiled stretch kept (all answered 0).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numba import njit, types
from numba.core import cgutils
from numba.core.errors import NumbaExperimentalFeatureWarning
from numba.extending import intrinsic

# numba calls first-class function types experimental; this module uses the part of them that
# numba's own cfunc arguments use (a C entry point of a fixed signature): said once here, not
# at every compile
warnings.filterwarnings("ignore", message="First-class function type feature is experimental",
                        category=NumbaExperimentalFeatureWarning)

__all__ = ["KERNEL_SIG", "OUT_SIZE", "CompiledForce", "address", "advance", "as_int64", "call_kernel", "function_at",
           "kernel_at", "evaluate"]

KERNEL_SIG = types.int64(types.CPointer(types.float64), types.float64, types.float64, types.float64,
                         types.float64, types.float64, types.CPointer(types.float64))
OUT_SIZE = 10  # F (2) and J (2, 4)


@intrinsic
def address(typingctx, addr):
    """The float64 pointer at the integer address ``addr`` (an array's ``ctypes.data``)."""
    sig = types.CPointer(types.float64)(addr)

    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], context.get_value_type(signature.return_type))

    return sig, codegen


@intrinsic
def advance(typingctx, ptr, k):
    """ptr + k (float64 elements): where a kernel's data array holds its next part."""
    sig = ptr(ptr, k)

    def codegen(context, builder, signature, args):
        return builder.gep(args[0], [args[1]])

    return sig, codegen


@intrinsic
def as_int64(typingctx, ptr):
    """The same address as an int64 pointer: integer arrays (exponents) stored in a kernel's
    float64 data by their bits (``ndarray.view``)."""
    sig = types.CPointer(types.int64)(ptr)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], context.get_value_type(signature.return_type))

    return sig, codegen


def function_at(signature):
    """An intrinsic: the C function of ``signature`` (a numba signature) at an integer address,
    as a first-class function called through its C entry point (as numba calls a cfunc
    argument). ``kernel_at`` is the one for KERNEL_SIG; a host makes others for C functions it
    calls (an FMU's fmi2DoStep)."""
    fty = types.FunctionType(signature)

    @intrinsic
    def at(typingctx, addr):
        sig = fty(addr)

        def codegen(context, builder, signature, args):
            sfunc = cgutils.create_struct_proxy(fty)(context, builder)
            vp = context.get_value_type(types.voidptr)
            sfunc.c_addr = builder.inttoptr(args[0], vp)
            sfunc.py_addr = vp(None)
            sfunc.jit_addr = vp(None)
            return sfunc._getvalue()

        return sig, codegen

    return at


# The kernel (a first-class function of KERNEL_SIG) at the integer address ``addr`` (a cfunc's
# ``address``)
kernel_at = function_at(KERNEL_SIG)


@dataclass(frozen=True)
class CompiledForce:
    """An internal's compiled force: ``kernel`` (a numba cfunc of KERNEL_SIG), ``data``
    (contiguous float64, what the kernel reads; its layout is the internal's business) and
    ``sync`` (None, or callable(n): n evaluations answered by the kernel were kept)."""

    kernel: object
    data: np.ndarray
    sync: object = None

    def __post_init__(self):
        if self.data.dtype != np.float64 or not self.data.flags.c_contiguous:
            raise ValueError("CompiledForce.data must be a contiguous float64 array")

    @property
    def address(self) -> int:
        """The kernel's C entry point, for ``kernel_at``."""
        return int(self.kernel.address)


@njit(cache=True)
def call_kernel(kernel_address, data, y, z, vy, vz, omega, out):
    """One call of the kernel at ``kernel_address`` (``CompiledForce.address``) from Python: its
    status, ``out`` (float64 (OUT_SIZE,)) filled. About 1 us, a third of a ``force_and_jacobian``
    of the force map (the Python FMU's step of a memoryless internal)."""
    kernel = kernel_at(kernel_address)
    return kernel(address(data.ctypes.data), y, z, vy, vz, omega, address(out.ctypes.data))


def evaluate(cf: CompiledForce, y: float, z: float, vy: float, vz: float, omega: float):
    """One call of the kernel from Python (tests, contract checks): (status, F (2,), dF/dq
    (2, 2), dF/dv (2, 2))."""
    out = np.zeros(OUT_SIZE)
    status = call_kernel(cf.address, cf.data, float(y), float(z), float(vy), float(vz), float(omega), out)
    J = out[2:].reshape(2, 4)
    return int(status), out[:2].copy(), J[:, :2].copy(), J[:, 2:].copy()
