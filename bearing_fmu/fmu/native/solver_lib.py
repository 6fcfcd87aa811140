"""The native FMU's Reynolds solver (c/reynolds_solver.c, with its film report c/reynolds_film.c)
and its oil law and film temperature (c/oil_thermal.c) alone: compiled into a small shared
library with zig (the compiler and flags of the FMU builds, ``compile``) and called through
ctypes, so that they can be compared with the Python internal (``physics.solver.reynolds.Reynolds``,
``physics.solver.film``, ``physics.oil``, ``physics.thermal``) state by state (tests/test_native_reynolds.py,
tests/test_native_film.py, tests/test_native_thermal.py, benchmarks/bench_native_reynolds.py).

    lib = solver_library(tmp_dir)
    solver = NativeReynolds(lib, params, n_theta=64, n_x=8, cavitation="reynolds")
    F, dFq, dFv = solver.force_and_jacobian(y, z, vy, vz, omega)
"""

from __future__ import annotations

import ctypes
import hashlib
import os
from pathlib import Path

import numpy as np

from ...physics.params import BearingParams
from ...physics.solver.reynolds import DEFAULT_N_THETA, DEFAULT_N_X
from .compile import C_FLAGS, run_compiler, zig_cc

C_DIR = Path(__file__).resolve().parent / "c"
HOST_TARGET = "native"  # zig cc -target native: this machine
SOURCES = ("py_mod.h", "reynolds_solver.h", "reynolds_kernels.c", "film_friction.h", "reynolds_film.c",
           "reynolds_solver.c", "reynolds_peak.c", "oil_thermal.h", "oil_thermal.c")

__all__ = ["NativeOil", "NativeReynolds", "bore_arrays", "lands_of", "solver_library"]


def solver_library(folder: Path) -> ctypes.CDLL:
    """Compile c/reynolds_solver.c (with its kernels and film report) and c/oil_thermal.c with their
    API exported (RS_EXPORT) into ``folder`` and load it;
    the library is named by a hash of the sources and flags, so a folder kept between runs
    compiles again only when they change."""
    folder = Path(folder).resolve()  # the compiler runs elsewhere (compile.run_compiler)
    folder.mkdir(parents=True, exist_ok=True)
    cmd = [*C_FLAGS, "-fPIC", "-shared", "-DRS_EXPORT"]
    h = hashlib.sha256(" ".join(cmd).encode())
    for name in SOURCES:
        h.update(name.encode() + b"\0" + (C_DIR / name).read_bytes())
    out = folder / f"reynolds_solver_{h.hexdigest()[:12]}.so"
    if not out.is_file():
        part = folder / f"{out.stem}.{os.getpid()}.part"
        run_compiler([*zig_cc(), "-target", HOST_TARGET, *cmd, "-I", str(C_DIR),
                      *(str(C_DIR / name) for name in SOURCES if name.endswith(".c")), "-o", str(part), "-lm"],
                     "zig cc (the Reynolds solver alone)")
        os.replace(part, out)
    lib = ctypes.CDLL(str(out))
    d, i, p = ctypes.c_double, ctypes.c_int, ctypes.c_void_p
    lib.rs_bytes.restype = ctypes.c_size_t
    lib.rs_bytes.argtypes = [i, i]
    lib.rs_create.restype = p
    lib.rs_create.argtypes = [p, i, i, i, i, d, d, d, d, i, p, p, p, i, d, d, d, ctypes.c_char_p, ctypes.c_size_t]
    lib.rs_call.restype = i
    lib.rs_call.argtypes = [p, d, d, d, d, d, i]
    lib.rs_results.restype = None
    lib.rs_results.argtypes = [p, p]
    lib.rs_forget.restype = None
    lib.rs_forget.argtypes = [p]
    lib.rs_film_report.restype = None
    lib.rs_film_report.argtypes = [p, d, d, d, d, d, p]
    lib.rs_set_lands.restype = i
    lib.rs_set_lands.argtypes = [p, d, d, ctypes.c_char_p, ctypes.c_size_t]
    lib.rs_peak_pressure.restype = None
    lib.rs_peak_pressure.argtypes = [p, p]
    lib.ot_oil_of.restype = i
    lib.ot_oil_of.argtypes = [p, i, *[d] * 15, ctypes.c_char_p, ctypes.c_size_t]
    lib.ot_mu.restype = d
    lib.ot_mu.argtypes = [p, d]
    lib.ot_film_temperature.restype = i
    lib.ot_film_temperature.argtypes = [p, *[d] * 8, i, d, d, p, ctypes.c_char_p, ctypes.c_size_t]
    lib.rs_call_many.restype = i
    lib.rs_call_many.argtypes = [p, p, i, i, p]
    return lib


def bore_arrays(params: BearingParams) -> tuple:
    """(nseg, edges [rad], fixed (int32), supply [Pa], lobes, preload, lobe_offset, lobe_angle [rad]) of
    the bore, as the C solver takes them (nseg = 0: the full bore, also with a circumferential groove:
    ``lands_of``); from ``Geometry.segments``."""
    g = params.geometry
    if g.is_full_bore or g.circumferential_groove:
        return 0, np.zeros(1), np.zeros(1, np.int32), np.zeros(1), 1, 0.0, 0.5, 0.0
    segs, fixed, supply = g.segments()
    return (len(segs), np.array([a for a, _b in segs]), np.array(fixed, np.int32), np.array(supply, float),
            g.lobes, g.preload, g.lobe_offset, g.lobe_angle)


def lands_of(params: BearingParams) -> tuple[float, float]:
    """(width [m], supply pressure [Pa]) of the bore's circumferential groove, (0, 0) without one: the C
    solver's rs_set_lands (physics/solver/lands.py)."""
    g = params.geometry
    return (float(g.circumferential_groove), float(g.supply_pressure)) if g.circumferential_groove else (0.0, 0.0)


class NativeReynolds:
    """The C solver for one bearing and grid, with the Python internal's call signatures (the
    state is assumed checked: finite, inside the wall)."""

    def __init__(self, lib: ctypes.CDLL, params: BearingParams, n_theta: int | None = None, n_x: int | None = None,
                 cavitation: str = "reynolds", warm_start: bool = True):
        self.lib = lib
        self.n_theta = DEFAULT_N_THETA if n_theta is None else int(n_theta)
        self.n_x = DEFAULT_N_X if n_x is None else int(n_x)
        self._bore = bore_arrays(params)  # kept alive: the solver copies what it needs at creation
        nseg, edges, fixed, supply, lobes, preload, offset, angle = self._bore
        self._mem = ctypes.create_string_buffer(lib.rs_bytes(self.n_theta, self.n_x) + 16)
        base = ctypes.addressof(self._mem)
        aligned = (base + 15) // 16 * 16
        msg = ctypes.create_string_buffer(512)
        self._s = lib.rs_create(aligned, self.n_theta, self.n_x, int(cavitation == "reynolds"), int(bool(warm_start)),
                                params.D, params.L, params.CR, params.mu, nseg, edges.ctypes.data,
                                fixed.ctypes.data, supply.ctypes.data, lobes, preload, offset, angle, msg, 512)
        if not self._s:
            raise ValueError(f"native Reynolds: {msg.value.decode()}")
        width, p_in = lands_of(params)
        if width and lib.rs_set_lands(self._s, width, p_in, msg, 512):
            raise ValueError(f"native Reynolds: {msg.value.decode()}")
        self._out = np.zeros(22)

    def _call(self, y, z, vy, vz, omega, want_jac: bool) -> np.ndarray:
        status = self.lib.rs_call(self._s, float(y), float(z), float(vy), float(vz), float(omega), int(want_jac))
        if status:
            raise RuntimeError(f"native Reynolds: status {status} at {(y, z, vy, vz, omega)!r}")
        self.lib.rs_results(self._s, self._out.ctypes.data)
        return self._out

    def force(self, y, z, vy, vz, omega) -> tuple[float, float]:
        out = self._call(y, z, vy, vz, omega, False)
        return float(out[0]), float(out[1])

    def force_and_jacobian(self, y, z, vy, vz, omega):
        out = self._call(y, z, vy, vz, omega, True)
        return out[0:2].copy(), out[2:6].reshape(2, 2).copy(), out[6:10].reshape(2, 2).copy()

    def omega_derivative(self, y, z, vy, vz, omega) -> np.ndarray:
        """dF/domega [N s/rad] (2,), from the same adjoints (the Python internal has no such output)."""
        return self._call(y, z, vy, vz, omega, True)[20:22].copy()

    def film_report(self, y, z, vy, vz, omega) -> np.ndarray:
        """(Couette torque, pressure torque [N m], friction power [W], inflow, side flow [m^3/s]) of
        the film at a state (c/reynolds_film.c; ``Reynolds.film_report``'s), after a force call there."""
        self._call(y, z, vy, vz, omega, False)
        out = np.zeros(5)
        self.lib.rs_film_report(self._s, float(y), float(z), float(vy), float(vz), float(omega), out.ctypes.data)
        return out

    def peak_pressure(self, y, z, vy, vz, omega) -> tuple[float, float]:
        """(p_peak [Pa], theta_peak [rad]) of the film at a state (c/reynolds_peak.c rs_peak_pressure;
        ``Reynolds.peak_pressure``'s), after a force call there."""
        self._call(y, z, vy, vz, omega, False)
        out = np.zeros(2)
        self.lib.rs_peak_pressure(self._s, out.ctypes.data)
        return float(out[0]), float(out[1])

    def counts(self) -> dict:
        """As ``Reynolds.counts``: calls, factorizations, warm starts, cold fallbacks."""
        self.lib.rs_results(self._s, self._out.ctypes.data)
        c = self._out[16:20]
        return {"calls": int(c[0]), "passes": int(c[1]), "warm_starts": int(c[2]), "cold_fallbacks": int(c[3])}

    def call_many(self, states: np.ndarray, want_jac: bool = True) -> np.ndarray:
        """(n, 10) rows F, dF/dq, dF/dv (row-major) at the (n, 5) states, in one C loop."""
        states = np.ascontiguousarray(states, float)
        out = np.zeros((states.shape[0], 10))
        bad = self.lib.rs_call_many(self._s, states.ctypes.data, states.shape[0], int(want_jac), out.ctypes.data)
        if bad:
            raise RuntimeError(f"native Reynolds: {bad} of {states.shape[0]} calls failed")
        return out

    def forget(self) -> None:
        self.lib.rs_forget(self._s)


class _OtOil(ctypes.Structure):  # c/oil_thermal.h ot_oil
    _fields_ = [("law", ctypes.c_int), ("c", ctypes.c_double * 3), ("T_min", ctypes.c_double),
                ("T_max", ctypes.c_double), ("density", ctypes.c_double), ("heat_capacity", ctypes.c_double),
                ("rise_factor", ctypes.c_double), ("outflow_share", ctypes.c_double),
                ("ambient_W_K", ctypes.c_double), ("T_ambient", ctypes.c_double)]


class NativeOil:
    """The oil law and the film temperature in C (c/oil_thermal.c) from the FMU's oil parameters
    ``values`` (a dict of ``fmu.ports`` names: oil_law, oil_nu_1 .. oil_rise_factor, oil_outflow_share,
    oil_ambient_loss, oil_T_ambient)."""

    LAWS = ("none", "walther", "vogel")

    def __init__(self, lib: ctypes.CDLL, values: dict):
        self.lib = lib
        self._oil = _OtOil()
        why = ctypes.create_string_buffer(512)
        names = ("oil_nu_1", "oil_T_1", "oil_nu_2", "oil_T_2", "oil_vogel_a", "oil_vogel_b", "oil_vogel_c",
                 "oil_T_min", "oil_T_max", "oil_density", "oil_heat_capacity", "oil_rise_factor", "oil_outflow_share",
                 "oil_ambient_loss", "oil_T_ambient")
        if lib.ot_oil_of(ctypes.byref(self._oil), self.LAWS.index(values["oil_law"]),
                         *[float(values[n]) for n in names], why, 512):
            raise ValueError(why.value.decode())

    def mu(self, T_K: float) -> float:
        return self.lib.ot_mu(ctypes.byref(self._oil), float(T_K))

    def film_temperature(self, params: BearingParams, report, T_supply_K: float, T_old_K: float | None = None,
                         dt_s: float = 0.0) -> tuple[float, float, float]:
        """As ``physics.thermal.film_temperature`` (the same arguments: ``report`` a FilmReport)."""
        out = np.zeros(3)
        why = ctypes.create_string_buffer(512)
        if self.lib.ot_film_temperature(ctypes.byref(self._oil), params.mu, params.R, params.CR, params.L,
                                        report.friction_power_W, report.inflow_m3_s, report.side_flow_m3_s,
                                        float(T_supply_K), int(T_old_K is not None),
                                        0.0 if T_old_K is None else float(T_old_K), float(dt_s), out.ctypes.data,
                                        why, 512):
            raise ValueError(why.value.decode())
        return float(out[0]), float(out[1]), float(out[2])
