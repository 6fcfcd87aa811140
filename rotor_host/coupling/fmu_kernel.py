"""A bearing FMU as a compiled force kernel: its FMI calls made from compiled code.

For a bearing FMU that declares itself memoryless (``bearing_fmu.fmu.meta.memoryless_annotation``:
the native FMUs of the map and linear internals), one evaluation is fmi2SetReal (the journal
state), fmi2DoStep (the step from the step's start t over h) and fmi2GetReal (force, K, C,
eccentricity), with no FMU state saved or restored: the outputs are those of the conformant
iteration. For any other FMU that can get and set its state and runs without an execution tool
(a native Taylor or Reynolds FMU, a foreign compiled FMU: ``stateful``), the kernel makes the
conformant iteration itself, as the Python driver (``cosim.FMUBearings``) does: at the first
evaluation of a step it saves the instance's state (fmi2GetFMUstate, into the one FMU state it
reuses), before every later evaluation of that step it restores it (fmi2SetFMUstate); the same
FMI calls in the same order, so the same outputs and the same log. What the FMU keeps besides its
FMU state (the Reynolds solver's warm start) stays in the FMU, on the C side.
``fmu_force`` wraps these calls of one instance as a ``CompiledForce`` of the kernel ABI
(``bearing_fmu.internals.compiled``), so the integrator's compiled loop
(``rotor_host.integrate.newmark_loop``) calls the FMU through its C function pointers (addresses
taken once from the loaded library) with no Python per call.

The kernel reads the step's start time and size from ``clock`` (float64 (2,): t, h), which the
compiled loop writes at the start of every step, so every doStep has the arguments the Python
driver (``cosim.FMUBearings``) gives it. It returns the doStep's status when that is
fmi2Discard or worse (the compiled loop then hands the step back to Python, whose driver asks
the FMU again: a discard becomes a cut step, an error an ``FMUError``), else 0; a warning is
logged by the FMU and the outputs used, as the Python driver does. K and C (Lund's sign) are
returned as the raw derivatives dF/dq = -K, dF/dv = -C. The eccentricity output updates the
bearing's entry of ``max_eccentricity`` (its address is in the data) at every evaluation, as in
the Python driver. A stateful kernel keeps its FMU state and the start time of the step it saved
it for in ``saved`` (float64 (2,), the state pointer by its bits and t; t NaN: none saved), which
its host reads and writes between compiled chunks (``restore_saved``, ``free_saved``).
"""

from __future__ import annotations

import ctypes

import numpy as np
from numba import cfunc, types
from numba.extending import intrinsic

from bearing_fmu.internals.compiled import KERNEL_SIG, CompiledForce, address, advance, as_int64, function_at

__all__ = ["fmu_force", "restore_saved", "free_saved", "N_IN", "N_OUT"]

N_IN, N_OUT = 5, 11  # y, z, vy, vz, omega; Fy, Fz, K (4), C (4), eccentricity
# fmi2SetReal / fmi2GetReal (component, vr[], nvr, value[]) and fmi2DoStep (component, t, h,
# noSetFMUStatePriorToCurrentPoint); fmi2Status is an int, size_t is 64 bits on every platform
# the native FMU is built for (all its binaries are 64-bit)
_VALUES = function_at(types.int32(types.voidptr, types.voidptr, types.int64, types.voidptr))
_DO_STEP = function_at(types.int32(types.voidptr, types.float64, types.float64, types.int32))
# fmi2GetFMUstate (component, fmi2FMUstate *) and fmi2SetFMUstate (component, fmi2FMUstate)
_STATE_CALL = function_at(types.int32(types.voidptr, types.voidptr))

# the kernel's data (float64 slots; addresses stored by their bits); _GETS 0: memoryless
_SET, _DO, _GET, _COMP, _CLOCK, _ECC, _GETS, _SETS, _SAVED = range(9)
_VR_IN = 9  # 5 uint32 value references in 3 slots
_VR_OUT = 12  # 11 uint32 in 6 slots
_IN = 18
_OUT = _IN + N_IN
DATA_SIZE = _OUT + N_OUT


@intrinsic
def _void(typingctx, where):
    """A void pointer: to the integer address ``where``, or ``where`` itself (a typed pointer)."""
    sig = types.voidptr(where)
    integer = isinstance(where, types.Integer)

    def codegen(context, builder, signature, args):
        vp = context.get_value_type(types.voidptr)
        return builder.inttoptr(args[0], vp) if integer else builder.bitcast(args[0], vp)

    return sig, codegen


@cfunc(KERNEL_SIG, cache=True)
def _fmu_kernel(dp, y, z, vy, vz, omega, op):
    ip = as_int64(dp)
    comp = _void(ip[_COMP])
    clock = address(ip[_CLOCK])
    inb = advance(dp, _IN)
    outb = advance(dp, _OUT)
    inb[0] = y
    inb[1] = z
    inb[2] = vy
    inb[3] = vz
    inb[4] = omega
    if ip[_GETS] != 0:  # the conformant iteration: save at a step's first evaluation, else restore
        saved = address(ip[_SAVED])
        if saved[1] != clock[0]:  # (NaN: none saved) the instance is at the step's start
            status = _STATE_CALL(ip[_GETS])(comp, _void(saved))
            if status > 1:
                return status
            saved[1] = clock[0]
        else:
            status = _STATE_CALL(ip[_SETS])(comp, _void(as_int64(saved)[0]))
            if status > 1:
                return status
    set_real = _VALUES(ip[_SET])
    status = set_real(comp, _void(advance(dp, _VR_IN)), N_IN, _void(inb))
    if status > 1:
        return status
    do_step = _DO_STEP(ip[_DO])
    status = do_step(comp, clock[0], clock[1], np.int32(0))  # noSetFMUStatePriorToCurrentPoint: false
    if status > 1:
        return status
    get_real = _VALUES(ip[_GET])
    status = get_real(comp, _void(advance(dp, _VR_OUT)), N_OUT, _void(outb))
    if status > 1:
        return status
    ecc = address(ip[_ECC])
    if outb[10] > ecc[0]:
        ecc[0] = outb[10]
    op[0] = outb[0]
    op[1] = outb[1]
    for r in range(2):
        for c in range(2):
            op[2 + 4 * r + c] = -outb[2 + 2 * r + c]
            op[4 + 4 * r + c] = -outb[6 + 2 * r + c]
    return 0


def _function_address(dll, name: str) -> int:
    return int(ctypes.cast(getattr(dll, name), ctypes.c_void_p).value)


def fmu_force(dll, component: int, vr_in, vr_out, clock: np.ndarray, max_eccentricity: np.ndarray,
              k: int, saved: np.ndarray | None = None) -> CompiledForce:
    """Instance ``component`` (its address) of the FMU loaded as ``dll`` (a ctypes library) as
    a compiled force. ``vr_in`` / ``vr_out``: the value references of (y, z, vy, vz, omega) and
    (Fy, Fz, Kyy, Kyz, Kzy, Kzz, Cyy, Cyz, Czy, Czz, eccentricity); ``clock`` (t, h) [s] and
    ``max_eccentricity`` (its entry k) are read and written through their addresses, and so is
    ``saved`` (float64 (2,): (0, NaN) at first), given for a stateful FMU (module docstring): the
    caller keeps these arrays alive and in place while the kernel is used."""
    if len(vr_in) != N_IN or len(vr_out) != N_OUT:
        raise ValueError(f"fmu_force: {N_IN} input and {N_OUT} output value references expected")
    if clock.dtype != np.float64 or clock.size != 2 or max_eccentricity.dtype != np.float64:
        raise ValueError("fmu_force: clock (2,) and max_eccentricity must be float64 arrays")
    data = np.zeros(DATA_SIZE)
    ints = data[:_VR_IN].view(np.int64)
    ints[_SET] = _function_address(dll, "fmi2SetReal")
    ints[_DO] = _function_address(dll, "fmi2DoStep")
    ints[_GET] = _function_address(dll, "fmi2GetReal")
    ints[_COMP] = int(component)
    ints[_CLOCK] = clock.ctypes.data
    ints[_ECC] = max_eccentricity.ctypes.data + 8 * int(k)
    if saved is not None:
        if saved.dtype != np.float64 or saved.shape != (2,) or not saved.flags.c_contiguous:
            raise ValueError("fmu_force: saved must be a contiguous float64 (2,) array")
        ints[_GETS] = _function_address(dll, "fmi2GetFMUstate")
        ints[_SETS] = _function_address(dll, "fmi2SetFMUstate")
        ints[_SAVED] = saved.ctypes.data
    data[_VR_IN:_VR_OUT].view(np.uint32)[:N_IN] = vr_in
    data[_VR_OUT:_IN].view(np.uint32)[:N_OUT] = vr_out
    return CompiledForce(_fmu_kernel, data)


def _state_of(saved: np.ndarray) -> ctypes.c_void_p:
    return ctypes.c_void_p(int(saved[:1].view(np.int64)[0]) or None)


def restore_saved(dll, component, saved: np.ndarray, t: float | None) -> int:
    """Put the instance back into the state its kernel saved at the start of the step at ``t``
    [s] if it saved one for that step (a compiled chunk gave the step back to Python after
    evaluating it; None: restore nothing), and forget the step (the kernel saves afresh at its
    next one). Returns the fmi2Status (0 when nothing was restored)."""
    status = 0
    if t is not None and saved[1] == t and saved[:1].view(np.int64)[0]:
        status = int(dll.fmi2SetFMUstate(component, _state_of(saved)))
    saved[1] = np.nan
    return status


def free_saved(dll, component, saved: np.ndarray) -> None:
    """Free the FMU state a stateful kernel kept (before its instance is freed)."""
    state = _state_of(saved)
    if state.value:
        dll.fmi2FreeFMUstate(component, ctypes.byref(state))
    saved[0], saved[1] = 0.0, np.nan
