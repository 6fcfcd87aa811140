"""The Reynolds solver as a compiled force (``internals.compiled``): the kernel a compiled host
loop calls (the rotor host's Newmark chunks) with no Python per evaluation.

The cfunc calls the solver's own kernel (``physics.solver.reynolds_kernels.reynolds_kernel``) on the
``Reynolds`` instance's own arrays, reached through their addresses in the kernel's data: the
same code on the same memory as ``Reynolds.force_and_jacobian`` from Python, so the numbers are
the same to the bit, and the warm start (the remembered converged calls) is one and the same for
the calls from Python and those from compiled code, which keep it on the compiled side between
evaluations and steps. The refusals are the Python call's: a non-finite input or a journal at or
beyond the wall (status 1, before the solver runs), an active-set iteration that did not settle
or a non-finite result (status 2, 3); the host then asks ``force_and_jacobian`` for the error.
The calls, passes, warm starts and cold fallbacks are counted in an array of the force's own (its
address in the data: a host may run a copy of the data) and handed to the instance by ``sync``.

The full bore calls ``reynolds_kernel``; a bore with grooves, an arc or lobes its own
(``physics.solver.geometry_kernels.geometry_kernel``) on its film arrays (GEO_ARRAYS), its wall the
film closure of ``Geometry.closure`` (the largest y a + z b over its sample angles, / CR).
"""

from __future__ import annotations

import math

import numpy as np
from numba import carray, cfunc, njit, types
from numba.extending import intrinsic

from ...physics.solver.geometry_kernels import geometry_kernel
from ...physics.solver.reynolds_kernels import reynolds_kernel
from ..compiled import KERNEL_SIG, CompiledForce, as_int64

__all__ = ["ARRAYS", "GEO_ARRAYS", "reynolds_force", "COUNTS"]

# the solver's arrays in the order reynolds_kernel takes them (Reynolds.kernel_arguments names them so)
ARRAYS = ("sin_c", "cos_c", "sin_f", "cos_f", "ds", "dc", "tdiag", "rs", "qw",
          "at", "ax", "b", "db", "dat", "dax", "diag", "cxo", "cto", "act", "Lb", "Y", "S", "zb", "z2",
          "p", "pf", "rhs", "tmp", "mu_y", "mu_z", "F", "dFq", "dFv", "Ft", "info",
          "hs", "order", "nvalid", "wring")
# the data: floats, integers (by their bits), then the addresses of the arrays and of the counts
_CR, _MU, _R, _DTH, _DX, _MAX_TURN, _MAX_DLOG = range(7)
_MODE, _M, _N, _MAX_ITER, _GROW, _WARM, _WARM_CAP, _WH = range(7, 15)
_A = 15  # the address of ARRAYS[i] is in slot _A + i
COUNTS = ("calls", "passes", "warm_starts", "cold_fallbacks")
_C = _A + len(ARRAYS)
# a bore other than the full circle: its film arrays (Reynolds._geo) and the closure weights (wall_a,
# wall_b: Geometry.closure_weights), whose number is in slot _K
GEO_ARRAYS = ("H0f", "H0c", "dH0", "ct", "cx", "gy", "gz", "fixed", "psup", "F0", "rhs0", "wall_a", "wall_b")
_G = _C + 1  # _C: the address of the counts (a host may run a copy of the data)
_K = _G + len(GEO_ARRAYS)
_P_IN = _K + 1  # a circumferential groove's supply pressure [Pa] on its lands' inner rows (0: none)
DATA_SIZE = _K + 2
_IDX = {name: _A + i for i, name in enumerate(ARRAYS)} | {name: _G + j for j, name in enumerate(GEO_ARRAYS)}
_BOOL = ("act", "fixed")
_INT = ("order", "nvalid")


@intrinsic
def _void(typingctx, where):
    """The integer address ``where`` as a void pointer (numba.carray takes one with a dtype)."""
    sig = types.voidptr(where)

    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], context.get_value_type(types.voidptr))

    return sig, codegen


@njit(inline="always")
def _f(ip, i, shape):
    """ARRAYS[i] (float64) of the shape."""
    return carray(_void(ip[_A + i]), shape, np.float64)


@njit(inline="always")
def _b(ip, i, shape):
    return carray(_void(ip[_A + i]), shape, np.bool_)


@njit(inline="always")
def _i(ip, i, shape):
    return carray(_void(ip[_A + i]), shape, np.int64)


@njit(inline="always")
def _g(ip, j, shape):
    """GEO_ARRAYS[j] (float64) of the shape."""
    return carray(_void(ip[_G + j]), shape, np.float64)


@njit(inline="always")
def _finite(y, z, vy, vz, omega):
    return (math.isfinite(y) and math.isfinite(z) and math.isfinite(vy) and math.isfinite(vz)
            and math.isfinite(omega))


@njit(inline="always")
def _finish(dp, F, dFq, dFv, info, op):
    """After the solver's call: its counts (Reynolds._count), its refusals (Reynolds._run's
    checks after the call), the output."""
    counts = carray(_void(as_int64(dp)[_C]), 4, np.float64)
    counts[0] += 1.0
    counts[1] += info[3]
    counts[2] += 1.0 if info[4] != 0.0 else 0.0
    counts[3] += 1.0 if info[5] != 0.0 else 0.0
    if info[0] < 0:
        return 2  # not settled: the Python call raises
    ok = math.isfinite(F[0]) and math.isfinite(F[1])
    for r in range(2):
        for c in range(2):
            ok = ok and math.isfinite(dFq[r, c]) and math.isfinite(dFv[r, c])
    if not ok:
        return 3  # an overflowing source: refused by name in the Python call
    op[0] = F[0]
    op[1] = F[1]
    for r in range(2):
        for c in range(2):
            op[2 + 4 * r + c] = dFq[r, c]
            op[4 + 4 * r + c] = dFv[r, c]
    return 0


def _kernel(dp, y, z, vy, vz, omega, op):
    """The full bore."""
    ip = as_int64(dp)
    # check_state of the full bore (internals.base): finite, and |e| / CR < 1
    if not _finite(y, z, vy, vz, omega):
        return 1
    CR = dp[_CR]
    if math.hypot(y, z) / CR >= 1.0:
        return 1
    N, m, wh = ip[_N], ip[_M], ip[_WH]
    n = N * m
    nb = (N - 1) * m
    F, dFq, dFv, info = _f(ip, 30, 2), _f(ip, 31, (2, 2)), _f(ip, 32, (2, 2)), _f(ip, 34, 6)
    info[:] = 0.0  # as Reynolds._run: the kernel adds its passes to info[3]
    reynolds_kernel(
        ip[_MODE], True, y, z, vy, vz, omega, CR, dp[_MU], dp[_R], dp[_DTH], dp[_DX], ip[_M],
        _f(ip, 0, N), _f(ip, 1, N), _f(ip, 2, N), _f(ip, 3, N), _f(ip, 4, N), _f(ip, 5, N),
        _f(ip, 6, m), _f(ip, 7, m), _f(ip, 8, m),
        _f(ip, 9, N), _f(ip, 10, N), _f(ip, 11, N), _f(ip, 12, (4, N)), _f(ip, 13, N), _f(ip, 14, N),
        _f(ip, 15, n), _f(ip, 16, n), _f(ip, 17, n), _b(ip, 18, n), _f(ip, 19, (nb, m + 1)),
        _f(ip, 20, (nb, m)), _f(ip, 21, (m, m)), _f(ip, 22, nb), _f(ip, 23, m),
        _f(ip, 24, n), _f(ip, 25, n), _f(ip, 26, n), _f(ip, 27, n), _f(ip, 28, n), _f(ip, 29, n),
        F, dFq, dFv, _f(ip, 33, 2), info,
        ip[_MAX_ITER], ip[_GROW], ip[_WARM] != 0, ip[_WARM_CAP], dp[_MAX_TURN], dp[_MAX_DLOG],
        _f(ip, 35, (wh, 4)), _i(ip, 36, wh), _i(ip, 37, 1), _f(ip, 38, (wh, n)),
    )
    return _finish(dp, F, dFq, dFv, info, op)


def _geo_kernel(dp, y, z, vy, vz, omega, op):
    """A bore with grooves, an arc or lobes."""
    ip = as_int64(dp)
    if not _finite(y, z, vy, vz, omega):
        return 1
    CR = dp[_CR]
    k = ip[_K]
    wa, wb = _g(ip, 11, k), _g(ip, 12, k)
    closure = y * wa[0] + z * wb[0]  # Geometry.closure: float(np.max(y * a + z * b)) / CR
    for i in range(1, k):
        c = y * wa[i] + z * wb[i]
        if c > closure:
            closure = c
    if closure / CR >= 1.0:
        return 1
    N, m, wh = ip[_N], ip[_M], ip[_WH]
    n = N * m
    nb = (N - 1) * m
    F, dFq, dFv, info = _f(ip, 30, 2), _f(ip, 31, (2, 2)), _f(ip, 32, (2, 2)), _f(ip, 34, 6)
    info[:] = 0.0
    geometry_kernel(
        ip[_MODE], True, y, z, vy, vz, omega, CR, dp[_MU], dp[_R], dp[_DX], ip[_M],
        _f(ip, 0, N), _f(ip, 1, N), _f(ip, 2, N), _f(ip, 3, N), _f(ip, 4, N), _f(ip, 5, N),
        _g(ip, 0, N), _g(ip, 1, N), _g(ip, 2, N), _g(ip, 3, N), _g(ip, 4, N), _g(ip, 5, N), _g(ip, 6, N),
        carray(_void(ip[_G + 7]), N, np.bool_), _g(ip, 8, N), dp[_P_IN], _g(ip, 9, 2),
        _f(ip, 6, m), _f(ip, 7, m), _f(ip, 8, m),
        _f(ip, 9, N), _f(ip, 10, N), _f(ip, 11, N), _f(ip, 12, (4, N)), _f(ip, 13, N), _f(ip, 14, N),
        _f(ip, 15, n), _f(ip, 16, n), _f(ip, 17, n), _b(ip, 18, n), _f(ip, 19, (nb, m + 1)),
        _f(ip, 20, (nb, m)), _f(ip, 21, (m, m)), _f(ip, 22, nb), _f(ip, 23, m),
        _f(ip, 24, n), _f(ip, 25, n), _g(ip, 10, n), _f(ip, 26, n), _f(ip, 27, n), _f(ip, 28, n), _f(ip, 29, n),
        F, dFq, dFv, _f(ip, 33, 2), info,
        ip[_MAX_ITER], ip[_GROW], ip[_WARM] != 0, ip[_WARM_CAP], dp[_MAX_TURN], dp[_MAX_DLOG],
        _f(ip, 35, (wh, 4)), _i(ip, 36, wh), _i(ip, 37, 1), _f(ip, 38, (wh, n)),
    )
    return _finish(dp, F, dFq, dFv, info, op)


_KERNELS: dict = {}


def _cfunc(geo: bool):
    """The cfunc of a bore, compiled (or loaded from numba's cache) at its first use, not at import."""
    if geo not in _KERNELS:
        _KERNELS[geo] = cfunc(KERNEL_SIG, cache=True)(_geo_kernel if geo else _kernel)
    return _KERNELS[geo]


def reynolds_force(scalars: dict, arrays: dict, sync, geo: dict | None = None) -> CompiledForce:
    """The compiled force of one Reynolds instance: ``scalars`` (CR, mu, R, dth, dx, max_turn,
    max_dlog floats; mode, m, N, max_iter, grow, warm, warm_cap integers), ``arrays`` (every name
    of ARRAYS: the instance's own, used in place; the caller keeps them alive and unmoved while
    the kernel is used), ``sync(counts)`` called with the COUNTS the kernel made since the last
    sync (a float64 (4,) array, zeroed after the call); ``geo``: every name of GEO_ARRAYS for a
    bore other than the full circle (the work array rhs0 used in place as ARRAYS are; the others,
    which the kernel only reads, kept here, copied where not contiguous)."""
    data = np.zeros(DATA_SIZE)
    for i, key in enumerate(("CR", "mu", "R", "dth", "dx", "max_turn", "max_dlog")):
        data[i] = float(scalars[key])
    ints = data.view(np.int64)
    for i, key in enumerate(("mode", "m", "N", "max_iter", "grow", "warm", "warm_cap")):
        ints[_MODE + i] = int(scalars[key])
    ints[_WH] = arrays["hs"].shape[0]
    for name in ARRAYS:
        arr = arrays[name]
        want = np.bool_ if name in _BOOL else np.int64 if name in _INT else np.float64
        if arr.dtype != want or not arr.flags.c_contiguous:
            raise ValueError(f"reynolds_force: array {name} must be contiguous {np.dtype(want)}")
        ints[_IDX[name]] = arr.ctypes.data
    held = []  # the bore's arrays as the kernel reads them, alive as long as the force
    if geo is not None:
        for name in GEO_ARRAYS:
            arr = np.ascontiguousarray(geo[name], dtype=np.bool_ if name in _BOOL else np.float64)
            if name == "rhs0" and arr is not geo[name]:
                raise ValueError("reynolds_force: the work array rhs0 must be contiguous float64 (used in place)")
            held.append(arr)
            ints[_IDX[name]] = arr.ctypes.data
        ints[_K] = held[-1].size
    data[_P_IN] = float(scalars.get("p_in", 0.0))

    counts = np.zeros(len(COUNTS))
    ints[_C] = counts.ctypes.data

    def kept(_n: int, held=held) -> None:
        sync(counts)
        counts[:] = 0.0

    return CompiledForce(_cfunc(geo is not None), data, sync=kept)
