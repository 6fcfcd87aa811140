"""The linear internal (``linear.py``) as a compiled-force kernel (``internals.compiled``).

data: y0, z0, omega0, Fy0, Fz0, Kyy, Kyz, Kzy, Kzz, Cyy, Cyz, Czy, Czz (Lund's K, C).
"""

from __future__ import annotations

import math

import numpy as np
from numba import carray, cfunc

from ..compiled import KERNEL_SIG


def pack(y0, z0, omega0, F0, K, C) -> np.ndarray:
    """The linear model as the float64 array ``linear_kernel`` reads."""
    return np.array([y0, z0, omega0, *np.ravel(F0), *np.ravel(K), *np.ravel(C)], dtype=np.float64)


@cfunc(KERNEL_SIG, cache=True)
def linear_kernel(dp, y, z, vy, vz, omega, op):
    """F = F0 - K (q - q0) - C v in the order ``Linear.force`` sums it; status 1 for what it
    refuses: a non-finite input, another speed than omega0, a non-finite force."""
    d = carray(dp, 13)
    out = carray(op, 10)
    if not (math.isfinite(y) and math.isfinite(z) and math.isfinite(vy) and math.isfinite(vz)
            and math.isfinite(omega)):
        return 1
    if abs(omega - d[2]) > 1e-9 * max(abs(d[2]), 1.0):
        return 1
    dy, dz = y - d[0], z - d[1]
    fy = d[3] - d[5] * dy - d[6] * dz - d[9] * vy - d[10] * vz
    fz = d[4] - d[7] * dy - d[8] * dz - d[11] * vy - d[12] * vz
    if not (math.isfinite(fy) and math.isfinite(fz)):
        return 1
    out[0] = fy
    out[1] = fz
    for i in range(2):
        for j in range(2):
            out[2 + 4 * i + j] = -d[5 + 2 * i + j]
            out[4 + 4 * i + j] = -d[9 + 2 * i + j]
    return 0
