"""The bearing FMU in a second, independent FMI engine: libcosim (OSP) through libcosimpy.

(a) The bearing FMU alone in a libcosim execution: inputs set through libcosim's initial values
    and then its override manipulator; Fy, Fz equal the direct library call.
(b) The bearing FMU coupled to a journal-mass FMU (examples/journal_mass_fmu.py, plain
    pythonfmu) in libcosim's own fixed-step master: the journal dropped at the bearing centre
    settles at the static equilibrium of bearing_fmu.physics.statics.
(c) The same loop with a too large step diverges, as the one-step force lag of an explicit
    (Jacobi) master predicts.
(d) The native FMU (bearing_fmu/native: the force map compiled to C, Model Exchange and
    Co-Simulation in one archive) alone: Fy, Fz equal the map internal called directly; and in
    the closed loop with the journal mass, where it settles at the map's static equilibrium.

The FMUs are built once per module into tmp; the bearing FMU's code cache
(BEARING_FMU_CACHE_DIR, where numba's cache lives) is the session's (tests/conftest.py: kept
between runs), so the Reynolds kernels compile in the first run only (~6 s).
"""

import math
import time
from pathlib import Path

import numpy as np
import pytest

# libcosimpy is a test dependency (pip install 'bearing-fmu[test]'): missing, the tests fail
from libcosimpy._internal import get_last_error_message, libcosimc  # noqa: E402

libcosimc()  # its bundled libcosimc library loads here, or the module fails naming why

from libcosimpy.CosimEnums import CosimExecutionState  # noqa: E402
from libcosimpy.CosimExecution import CosimExecution  # noqa: E402
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level  # noqa: E402
from libcosimpy.CosimManipulator import CosimManipulator  # noqa: E402
from libcosimpy.CosimObserver import CosimObserver  # noqa: E402
from libcosimpy.CosimSlave import CosimLocalSlave  # noqa: E402

from bearing_fmu.physics.params import PAPER_BEARING as P  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OMEGA = 2 * math.pi * 22.0
W = 16.7  # N, the paper rotor's load per bearing; the load vector is (0, -W)
# The journal mass of the loop. Lighter than W/g on purpose: with the one-step force lag the
# explicit loop is stable only for h < m / max eig(C_film) (C ~ 1.0e4, 1.6e4 N s/m here), i.e.
# 3.0e-5 s for 0.5 kg, so 1e-5 s is stable with margin and 1e-4 s and 5e-5 s fail quickly
# (with W/g = 1.70 kg the limit would be 1.04e-4 s, right at 1e-4 s). The settling time is set
# by the film's half-frequency whirl mode (decay ~25 1/s, 70 rad/s), nearly independent of m.
MASS = 0.5
NS = 1_000_000_000  # libcosim counts time in integer nanoseconds

log_output_level(CosimLogLevel.WARNING)  # libcosimc logs every FMU load at INFO


def _load_example():
    import importlib.util

    spec = importlib.util.spec_from_file_location("_journal_mass_example", ROOT / "examples" / "journal_mass_fmu.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def fmus(tmp_path_factory, code_cache):
    """(bearing.fmu, JournalMass.fmu); the bearing's code cache is the session's (``code_cache``
    sets BEARING_FMU_CACHE_DIR)."""
    from bearing_fmu.fmu.build import build_fmu

    out = tmp_path_factory.mktemp("libcosim_fmus")
    return build_fmu(out / "bearing.fmu"), _load_example().build(out / "JournalMass.fmu")


MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"  # the shipped force map of the paper bearing's L/D


@pytest.fixture(scope="module")
def native_map(tmp_path_factory, native_build_cache):
    """The native FMU of the map internal with the shipped map compiled in (one C compile, again
    only when the sources or the map change: tests/conftest.py ``native_build_cache``)."""

    from bearing_fmu.fmu.native.build import build_native_fmu

    return native_build_cache(tmp_path_factory.mktemp("libcosim_native") / "native_map.fmu",
                              lambda target: build_native_fmu(target, "map", map=MAP, platforms=["linux64"]), [MAP],
                              ("map", "linux64"))


@pytest.fixture(scope="module")
def map_internal():
    """The map internal called in this process: what the native FMU must give."""
    from bearing_fmu.internals import registry as internals

    return internals.create("map", P, {"map": str(MAP)})


@pytest.fixture(scope="module")
def reynolds():
    from bearing_fmu.physics.solver.reynolds import Reynolds

    return Reynolds(P)


def _add(execution, fmu, name):
    index = execution.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name=name))
    assert index >= 0, f"libcosim could not load {fmu}"
    refs = {v.name.decode(): v.reference for v in execution.slave_variables(index)}
    return index, refs


# ----------------------------------------------------------------------------- (a) the bearing alone


def test_bearing_force_in_libcosim_equals_reynolds(fmus, reynolds):
    bearing_fmu, _ = fmus
    h = 1e-4
    ex = CosimExecution.from_step_size(round(h * NS))
    b, vb = _add(ex, bearing_fmu, "bearing")  # default parameters: Reynolds, paper bearing, 128 x 16
    observer = CosimObserver.create_last_value()
    assert ex.add_observer(observer)
    manipulator = CosimManipulator.create_override()
    assert ex.add_manipulator(manipulator)
    names = ("y", "z", "vy", "vz", "omega")
    read = lambda: dict(zip(("Fy", "Fz", "eccentricity"),  # noqa: E731
                            observer.last_real_values(b, [vb["Fy"], vb["Fz"], vb["eccentricity"]])))

    # 1: inputs as libcosim initial values (applied in initialisation mode), then 3 steps
    s1 = (10e-6, -40e-6, 1e-3, -2e-4, OMEGA)  # eccentricity 0.46, moving
    for n, v in zip(names, s1):
        assert ex.real_initial_value(b, vb[n], v)
    assert ex.step(3)
    assert ex.status().current_time == 3 * round(h * NS)
    got = read()
    # expected: the library called directly in this process, same bearing and default grid
    assert (got["Fy"], got["Fz"]) == pytest.approx(reynolds.force(*s1), rel=1e-12)
    assert got["eccentricity"] == pytest.approx(math.hypot(s1[0], s1[1]) / P.CR, rel=1e-14)

    # 2: new inputs through libcosim's real-value setter (override manipulator) mid-run
    s2 = (-25e-6, -55e-6, -3e-4, 8e-4, 0.5 * OMEGA)
    assert manipulator.slave_real_values(b, [vb[n] for n in names], list(s2))
    assert ex.step(2)
    got = read()
    assert (got["Fy"], got["Fz"]) == pytest.approx(reynolds.force(*s2), rel=1e-12)
    assert (got["Fy"], got["Fz"]) != pytest.approx(reynolds.force(*s1), rel=1e-3)  # it did change
    print(f"\nlibcosim bearing force: {got['Fy']!r}, {got['Fz']!r}; direct: {reynolds.force(*s2)}")
    del ex


# ----------------------------------------------------------------------------- (b), (c) bearing + journal mass


def _loop(fmus, h, m=MASS, load=(0.0, -W)):
    """The two FMUs (bearing, journal mass) connected in a libcosim fixed-step execution: journal
    state -> bearing inputs, film force -> journal inputs; the journal starts at rest at the
    bearing centre."""
    bearing_fmu, mass_fmu = fmus
    ex = CosimExecution.from_step_size(round(h * NS))
    b, vb = _add(ex, bearing_fmu, "bearing")
    j, vj = _add(ex, mass_fmu, "journal")
    assert ex.real_initial_value(b, vb["omega"], OMEGA)  # omega is not connected: held constant
    assert ex.boolean_initial_value(b, vb["compute_tangent"], False)  # only Fy, Fz are used
    for n, v in (("m", m), ("Wy", load[0]), ("Wz", load[1]), ("y0", 0.0), ("z0", 0.0)):
        assert ex.real_initial_value(j, vj[n], v)
    for n in ("y", "z", "vy", "vz"):
        assert ex.connect_real_variables(j, vj[n], b, vb[n]) == 0  # returns 0 / -1, not a bool
    for n in ("Fy", "Fz"):
        assert ex.connect_real_variables(b, vb[n], j, vj[n]) == 0
    observer = CosimObserver.create_last_value()
    assert ex.add_observer(observer)
    return ex, observer, (b, vb), (j, vj)


def _settle(fmus, h, t_end, chunk=1e-3):
    """Run the closed loop to t_end; (history rows (t, y, z, Fy, Fz) every chunk, wall time [s])."""
    ex, observer, (b, vb), (j, vj) = _loop(fmus, h)
    t0 = time.perf_counter()
    n_chunk = round(chunk / h)
    history = []
    for k in range(round(t_end / chunk)):
        assert ex.step(n_chunk), f"libcosim step failed at t = {k * chunk:.4f} s: {ex.status()}"
        y, z = observer.last_real_values(j, [vj["y"], vj["z"]])
        fy, fz = observer.last_real_values(b, [vb["Fy"], vb["Fz"]])
        history.append(((k + 1) * chunk, y, z, fy, fz))
    wall = time.perf_counter() - t0
    assert ex.status().current_time == round(t_end / h) * round(h * NS)
    del ex
    return np.array(history), wall


@pytest.mark.slow
def test_closed_loop_in_libcosim_settles_at_the_static_equilibrium(fmus, reynolds):
    """End to end (slow: 20 000 libcosim steps of the Python FMU on the default grid, 8-11 s).
    The quick loop keeps its parts: the Python FMU's force in libcosim (a), the same loop with a
    Python bearing FMU that diverges (c), and the closed loop that settles with the native map
    FMU (d)."""
    from bearing_fmu.physics.statics import equilibrium

    h, chunk, t_end = 1e-5, 1e-3, 0.2
    # expected: Newton on the Reynolds force alone (no co-simulation, no dynamics)
    y_eq, z_eq = equilibrium(reynolds, (0.0, -W), OMEGA)
    hist, wall = _settle(fmus, h, t_end, chunk)  # (t, y, z, Fy, Fz) every chunk
    err = np.hypot(hist[:, 1] - y_eq, hist[:, 2] - z_eq) / P.CR
    t, y, z, fy, fz = hist[-1]
    print(f"\nlibcosim loop h = {h:g} s, m = {MASS} kg, {t_end} s simulated in {wall:.1f} s wall "
          f"({1e6 * wall * h / t_end:.0f} us/step)\n"
          f"settled  y/CR = {y / P.CR:.5f}, z/CR = {z / P.CR:.5f}, F = ({fy:.4f}, {fz:.4f}) N\n"
          f"equilib. y/CR = {y_eq / P.CR:.5f}, z/CR = {z_eq / P.CR:.5f}; distance {err[-1]:.2e} CR "
          f"(at 0.05 s: {err[49]:.2e}, 0.1 s: {err[99]:.2e})")
    assert err[0] > 0.15  # it started far away (the centre is 0.21 CR from the equilibrium)
    assert err[-20:].max() < 0.01  # settled: within 1 % of CR over the last 20 ms
    assert err[-1] < err[99] < err[49]  # and still approaching
    # the film carries the load: F + W = m a -> 0 (|a| ~ 1e-3 m/s^2 in the residual whirl)
    assert (fy, fz) == pytest.approx((0.0, W), abs=0.02)


@pytest.mark.parametrize("h", [1e-4, 5e-5])
def test_closed_loop_with_too_large_a_step_diverges(fmus, h):
    """libcosim's fixed-step master is Jacobi: in [t_n, t_n+1] the journal gets the force the
    bearing computed from the state at t_n-1. For the linearised loop (film stiffness K and
    damping C at the equilibrium, semi-implicit Euler in the journal) that one-step lag limits
    the step to h < m / max eig(C) = 3.0e-5 s for m = 0.5 kg (spectral radius per step 1.81 at
    1e-4 s, 1.28 at 5e-5 s). With the force of the current state (a Gauss-Seidel master) the
    limit would be 2 m / max eig(C) = 6.1e-5 s: 5e-5 s fails only because of the lag."""
    ex, observer, (b, vb), (j, vj) = _loop(fmus, h)
    n = round(0.01 / h)
    ok = True
    for k in range(n):
        ok = ex.step(1)
        if not ok:
            break
    status = ex.status()
    y, z = observer.last_real_values(j, [vj["y"], vj["z"]])
    message = get_last_error_message()
    del ex
    # the journal is thrown against the wall within a few ms; the bearing FMU then discards
    # the step (eccentricity >= 1) and libcosim stops the execution with an error
    assert not ok and CosimExecutionState(status.state) == CosimExecutionState.ERROR
    assert "bearing: Step not complete" in message, message  # the slave that discarded
    assert k < n // 2, f"diverged only after {k} steps"
    assert math.hypot(y, z) >= P.CR
    print(f"\nh = {h:g} s: libcosim stopped after {k} steps at e = {math.hypot(y, z) / P.CR:.2f}")


# ----------------------------------------------------------------------------- (d) the native FMU


def test_native_fmu_force_in_libcosim_equals_the_map_internal(native_map, map_internal):
    """The native FMU (C, no Python) in libcosim: inputs as initial values, then through the
    override manipulator; Fy, Fz equal the map internal called in this process (the native FMU
    equals it to 1e-12 relative: tests/test_native_fmu.py). libcosim loads the Co-Simulation
    interface of the two in the archive; it ignores FMI 2.0 enumerations (it logs a warning for
    internal_enum), so a libcosim user sets the String parameters."""
    h = 1e-4
    ex = CosimExecution.from_step_size(round(h * NS))
    b, vb = _add(ex, native_map, "native")
    assert "internal_enum" not in vb and "internal" in vb  # libcosim 0.x: enumerations not supported
    observer = CosimObserver.create_last_value()
    assert ex.add_observer(observer)
    manipulator = CosimManipulator.create_override()
    assert ex.add_manipulator(manipulator)
    names = ("y", "z", "vy", "vz", "omega")
    s1 = (10e-6, -40e-6, 1e-3, -2e-4, OMEGA)
    for n, v in zip(names, s1):
        assert ex.real_initial_value(b, vb[n], v)
    assert ex.string_initial_value(b, vb["internal"], "map")  # its one internal, by name (accepted)
    assert ex.step(3)
    got = observer.last_real_values(b, [vb["Fy"], vb["Fz"]])
    assert got == pytest.approx(map_internal.force(*s1), rel=1e-12)
    s2 = (-25e-6, -55e-6, -3e-4, 8e-4, 2.5 * OMEGA)  # another speed: the map holds every one
    assert manipulator.slave_real_values(b, [vb[n] for n in names], list(s2))
    assert ex.step(2)
    got = observer.last_real_values(b, [vb["Fy"], vb["Fz"]])
    assert got == pytest.approx(map_internal.force(*s2), rel=1e-12)
    assert got != pytest.approx(map_internal.force(*s1), rel=1e-3)  # it did change
    del ex


@pytest.mark.slow
def test_native_fmu_closed_loop_in_libcosim_settles_at_the_map_equilibrium(fmus, native_map, map_internal):
    """The native map FMU and the journal mass in libcosim's fixed-step master (the loop of (b),
    its stable step 1e-5 s, 0.1 s): the journal dropped at the bearing centre approaches the
    static equilibrium of the map internal (bearing_fmu.physics.statics, no co-simulation)."""
    from bearing_fmu.physics.statics import equilibrium

    h, t_end = 1e-5, 0.1
    y_eq, z_eq = equilibrium(map_internal, (0.0, -W), OMEGA)
    hist, wall = _settle((native_map, fmus[1]), h, t_end)
    err = np.hypot(hist[:, 1] - y_eq, hist[:, 2] - z_eq) / P.CR
    print(f"\nlibcosim native map loop h = {h:g} s: {t_end} s in {wall:.1f} s wall "
          f"({1e6 * wall * h / t_end:.0f} us/step, journal mass FMU included); distance to the equilibrium "
          f"{err[0]:.3f} CR at 1 ms, {err[49]:.2e} at 50 ms, {err[-1]:.2e} CR at {t_end} s")
    assert err[0] > 0.15  # it started far away (the centre is ~0.2 CR from the equilibrium)
    assert err[-1] < 0.05 and err[-1] < err[49] < err[9]  # and approaches it, as the Reynolds loop of (b) does
    assert np.all(np.hypot(hist[:, 1], hist[:, 2]) < P.CR)  # never near the wall
