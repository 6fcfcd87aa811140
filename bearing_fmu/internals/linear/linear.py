"""The linear internal: 8 Lund coefficients about a static equilibrium (order-1 baseline)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...physics.params import BearingParams
from ..base import BearingStateError, Internal, check_finite, overflow_error


@dataclass
class Linear:
    """F = F0 - K (q - q0) - C v, with Lund's K, C (positive direct terms), valid at omega0.

    Unlike Reynolds it evaluates beyond the clearance circle: the paper's linear orbits cross
    the bearing wall, and a host reports that rather than crashing. Inputs must be finite and
    omega must equal the speed the coefficients belong to.
    """

    params: BearingParams
    y0: float
    z0: float
    omega0: float
    F0: np.ndarray
    K: np.ndarray
    C: np.ndarray
    _f: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.F0 = np.asarray(self.F0, float).reshape(2)
        self.K = np.asarray(self.K, float).reshape(2, 2)
        self.C = np.asarray(self.C, float).reshape(2, 2)
        for name in ("y0", "z0", "omega0"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"Linear.{name} = {getattr(self, name)!r} is not finite")
        for name in ("F0", "K", "C"):
            if not np.all(np.isfinite(getattr(self, name))):
                raise ValueError(f"Linear.{name} has non-finite entries: {getattr(self, name).tolist()}")

    @classmethod
    def at_load(cls, internal: Internal, load, omega: float) -> "Linear":
        """Linearise ``internal`` at its static equilibrium under ``load`` (Wy, Wz) [N] at omega [rad/s]."""
        from ...physics.statics import equilibrium, linearize

        y0, z0 = equilibrium(internal, load, omega)
        K, C = linearize(internal, y0, z0, omega)
        F0 = np.asarray(internal.force(y0, z0, 0.0, 0.0, omega), float)
        return cls(internal.params, y0, z0, omega, F0, K, C)

    @classmethod
    def from_options(cls, params: BearingParams, options, context=None) -> "Linear":
        """From the registry's checked options (``internals.REGISTRY["linear"]``): linearise
        Reynolds (its grid from the reynolds options) or the force map (``linear_from = "map"``,
        the map option's file) under (load_y, load_z) at omega_lin, or take the lin_*
        coefficients as given."""
        o = options
        if o["linear_from"] == "coefficients":
            return cls(params, o["lin_y0"], o["lin_z0"], o["omega_lin"], (o["lin_Fy0"], o["lin_Fz0"]),
                       ((o["lin_Kyy"], o["lin_Kyz"]), (o["lin_Kzy"], o["lin_Kzz"])),
                       ((o["lin_Cyy"], o["lin_Cyz"]), (o["lin_Czy"], o["lin_Czz"])))
        if o["linear_from"] == "map":  # the force map: no Reynolds import or compile (milliseconds)
            from ..map.mapfile import from_options as open_map

            return cls.at_load(open_map(params, o, context), (o["load_y"], o["load_z"]), o["omega_lin"])
        from ...physics.solver.reynolds import Reynolds

        return cls.at_load(Reynolds.from_options(params, o), (o["load_y"], o["load_z"]), o["omega_lin"])

    def _check(self, y, z, vy, vz, omega) -> None:
        check_finite(y, z, vy, vz, omega)
        if abs(omega - self.omega0) > 1e-9 * max(abs(self.omega0), 1.0):
            raise BearingStateError(
                f"linear internal was linearised at omega = {self.omega0:.6g} rad/s; got omega = {omega:.6g} rad/s"
            )

    # The linear model evaluates past the clearance circle, where it means nothing physically:
    # such a state is flagged (the FMU's out_of_domain output), not refused, so a run can show it.
    last_out_of_domain = False

    def force(self, y, z, vy, vz, omega):
        self._check(y, z, vy, vz, omega)
        y, z, vy, vz = float(y), float(z), float(vy), float(vz)
        self.last_out_of_domain = math.hypot(y, z) >= self.params.CR
        dy, dz = y - self.y0, z - self.z0
        # Python floats: an overflow gives inf quietly (numpy scalars would warn), refused below
        (k00, k01), (k10, k11) = self.K.tolist()
        (c00, c01), (c10, c11) = self.C.tolist()
        f0y, f0z = self.F0.tolist()
        fy = f0y - k00 * dy - k01 * dz - c00 * vy - c01 * vz
        fz = f0z - k10 * dy - k11 * dz - c10 * vy - c11 * vz
        if not (math.isfinite(fy) and math.isfinite(fz)):  # finite inputs, K q or C v beyond 1e308 N
            raise overflow_error(self.params, y, z, vy, vz, omega)
        return float(fy), float(fz)

    def force_and_jacobian(self, y, z, vy, vz, omega):
        f = np.array(self.force(y, z, vy, vz, omega))
        return f, -self.K.copy(), -self.C.copy()

    def compiled_force(self):
        """Its force and Jacobian as a compiled kernel (``internals.compiled``)."""
        from ..compiled import CompiledForce
        from .kernels import linear_kernel, pack

        return CompiledForce(linear_kernel, pack(self.y0, self.z0, self.omega0, self.F0, self.K, self.C))

    def to_dict(self) -> dict:
        return {
            "params": self.params.as_dict(),
            "y0": self.y0, "z0": self.z0, "omega0": self.omega0,
            "F0": self.F0.tolist(), "K": self.K.tolist(), "C": self.C.tolist(),
        }

    @classmethod
    def from_dict(cls, d: dict) -> "Linear":
        return cls(BearingParams(**d["params"]), d["y0"], d["z0"], d["omega0"], d["F0"], d["K"], d["C"])
