"""The native Reynolds FMU's peak pressure and its angle (c/reynolds_peak.c rs_peak_pressure, a port
of ``Reynolds.peak_pressure`` and ``film.peak_pressure``): the outputs ``peak_pressure`` [Pa] and
``peak_pressure_angle`` [rad], as the Python FMU's.

Expected values: the Python Reynolds internal's ``peak_pressure`` at the same state, grid and bore
(the C solver's field is the Python one's bit for bit, so the peak is too: compared to 1e-12); with
the thermal model on, the Python internal's at the effective viscosity the FMU reports (the field
is linear in mu at a fixed state); 0 for an internal without a pressure field (the Python FMU's).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.fmu.native.solver_lib import NativeReynolds, solver_library
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from test_native_reynolds import BORES, PAPER, random_states

fmpy = pytest.importorskip("fmpy")

ROOT = Path(__file__).resolve().parents[1]
VG46 = ROOT / "rotor_host" / "bundled" / "bearing_paper_vg46.toml"
GRID = {"n_theta": 32, "n_x": 6}
IN = ("y", "z", "vy", "vz", "omega")
PEAK = ("peak_pressure", "peak_pressure_angle")
RTOL = 1e-12


@pytest.fixture(scope="module")
def lib(tmp_path_factory):
    return solver_library(tmp_path_factory.mktemp("native_peak_lib"))


@pytest.mark.parametrize("grid", [(32, 2), (48, 6), (40, 10)])
@pytest.mark.parametrize("bore", list(BORES))
def test_solver_peak_equals_python(lib, bore, grid):
    """Every bore, n_x = 2 (one cell per half: the cell's row), 6 and 10 (the even parabola through the two
    rows nearest the mid-plane): the C solver's peak and angle are the Python solver's at random states."""
    params = BearingParams(**PAPER, geometry=BORES[bore])
    py, c = Reynolds(params, *grid), NativeReynolds(lib, params, *grid)
    pressurised = 0
    for state in random_states(params, 12, 5):
        want, got = py.peak_pressure(*state), c.peak_pressure(*state)
        pressurised += want[0] > 0.0  # a film drawn apart everywhere (a partial arc opening): 0 at the angle
        assert abs(got[0] - want[0]) <= RTOL * want[0] and abs(got[1] - want[1]) <= RTOL, (state, got, want)
    assert pressurised >= 8  # the comparison is not 0 == 0


def _fmus(folder, native_build_cache, params):
    from bearing_fmu.fmu.native.build import build_native_fmu

    out = {}
    for version in (2, 3):
        def build(target, version=version):
            return build_native_fmu(target, "reynolds", bearing=params, fmi_version=version, compiler="cc",
                                    options=GRID)
        path = native_build_cache(folder / f"reynolds_peak_fmi{version}.fmu", build, [VG46],
                                  ("peak", "reynolds", version, tuple(GRID.items())))
        out[version] = (path, fmpy.read_model_description(str(path)))
    return out


@pytest.fixture(scope="module")
def fmus(tmp_path_factory, native_build_cache):
    """FMI version -> (the native Reynolds FMU of the VG 46 bearing, its model description)."""
    return _fmus(tmp_path_factory.mktemp("native_peak"), native_build_cache, BearingParams.from_toml(VG46))


def _states(params, n=5, seed=3):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        e, a, w = rng.uniform(0.1, 0.9), rng.uniform(-math.pi, math.pi), rng.uniform(50.0, 400.0)
        v = rng.normal(0.0, 0.2, 2) * w * params.CR
        out.append((e * params.CR * math.cos(a), e * params.CR * math.sin(a), v[0], v[1], w))
    return out


def _initialising(path, md, version: int, name: str):
    """(a Co-Simulation instance of the FMU at ``path`` in Initialization Mode, its Real getter, its
    Real setter), FMI 2 or 3."""
    from fmpy.fmi2 import FMU2Slave
    from fmpy.fmi3 import FMU3Slave

    cls = FMU3Slave if version == 3 else FMU2Slave
    f = cls(guid=md.guid, unzipDirectory=fmpy.extract(str(path)), modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=name)
    f.instantiate()
    get, put = (f.getFloat64, f.setFloat64) if version == 3 else (f.getReal, f.setReal)
    if version == 3:
        f.enterInitializationMode(startTime=0.0)
    else:
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
    return f, get, put


@pytest.mark.parametrize("thermal", [False, True])
@pytest.mark.parametrize("version", [2, 3])
def test_fmu_peak_equals_python(fmus, version, thermal):
    """Co-Simulation steps at a few states: the outputs peak_pressure [Pa] and peak_pressure_angle [rad] are
    the Python Reynolds internal's at the state (thermal on: at the viscosity mu_eff the FMU reports); the
    declared units are the Python FMU's, and the dependencies the force's."""
    params = BearingParams.from_toml(VG46)
    path, md = fmus[version]
    var = {v.name: v for v in md.modelVariables}
    assert [(var[n].causality, var[n].unit) for n in PEAK] == [("output", "Pa"), ("output", "rad")]
    deps = {u.variable.name: sorted(d.name for d in u.dependencies) for u in md.outputs}
    assert deps["peak_pressure"] == deps["Fy"] and deps["peak_pressure_angle"] == deps["Fy"]
    vr = {n: v.valueReference for n, v in var.items()}
    f, get, put = _initialising(path, md, version, "peak")
    f.setBoolean([vr["thermal"]], [thermal])
    f.exitInitializationMode()
    try:
        t = 0.0
        for state in _states(params):
            put([vr[n] for n in IN], list(state))
            f.doStep(t, 1e-4)
            t += 1e-4
            peak, angle, mu_eff, fy = get([vr[n] for n in (*PEAK, "mu_eff", "Fy")])
            at = params if not thermal else BearingParams(D=params.D, L=params.L, CR=params.CR, mu=mu_eff,
                                                          geometry=params.geometry)
            want = Reynolds(at, GRID["n_theta"], GRID["n_x"]).peak_pressure(*state)
            assert (mu_eff != params.mu) == thermal
            assert abs(peak - want[0]) <= 1e-10 * want[0] and abs(angle - want[1]) <= 1e-10, (state, peak, want)
            assert fy != 0.0
    finally:
        f.terminate()
        f.freeInstance()


def test_map_fmu_has_no_field(tmp_path, native_build_cache):
    """A native FMU whose internal has no pressure field (the map) declares the peak outputs, always 0,
    with no dependencies (as the Python FMU's outputs for such an internal)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    paper_map = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
    path = native_build_cache(tmp_path / "map_peak.fmu",
                              lambda target: build_native_fmu(target, "map", map=paper_map, compiler="cc"),
                              [paper_map], ("peak", "map"))
    md = fmpy.read_model_description(str(path))
    deps = {u.variable.name: [d.name for d in u.dependencies] for u in md.outputs}
    assert deps["peak_pressure"] == [] and deps["peak_pressure_angle"] == []
    out = fmpy.simulate_fmu(str(path), stop_time=2e-3, output_interval=1e-3,
                            start_values={"y": 2e-5, "z": -4e-5, "omega": 138.0}, output=["Fy", *PEAK])
    assert np.all(out["Fy"] != 0.0) and np.all(out["peak_pressure"] == 0.0) and np.all(out["peak_pressure_angle"] == 0.0)


# ----------------------------------------------------------------------------- the circumferential groove

GROOVE_D, GROOVE_L, GROOVE_CR, GROOVE_MU, WIDTH, PS = 0.040, 0.045, 42e-6, 0.02, 0.005, 200e3


def grooved(ps=PS) -> BearingParams:
    from bearing_fmu.physics.bore.geometry import Geometry

    return BearingParams(D=GROOVE_D, L=GROOVE_L, CR=GROOVE_CR, mu=GROOVE_MU,
                         geometry=Geometry(circumferential_groove=WIDTH, supply_pressure=ps))


def grooved_states(n=15, seed=4):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        e, a, w = rng.uniform(0.05, 0.95), rng.uniform(0.0, 2.0 * math.pi), rng.uniform(20.0, 600.0)
        v = rng.uniform(-1.0, 1.0, 2) * w * GROOVE_CR
        out.append((e * GROOVE_CR * math.cos(a), e * GROOVE_CR * math.sin(a), v[0], v[1], w))
    return out


@pytest.mark.parametrize("grid", [(32, 4), (40, 10)])
@pytest.mark.parametrize("ps", [0.0, 50e3, PS])
def test_solver_lands_equal_python(lib, ps, grid):
    """The C solver on a bore fed by a circumferential groove (rs_set_lands: one land, p_s on its inner
    row, in the right-hand side and the adjoint) against the Python Reynolds internal (its geometry
    kernel on the lands): force, Jacobian, film report (the lands' length, inflow = side flow) and peak
    to round-off (1e-12 relative; the full-circle cells are computed in another order, so not bit for bit)."""
    params = grooved(ps)
    py, c = Reynolds(params, *grid), NativeReynolds(lib, params, *grid)
    for state in grooved_states():
        for a, b in zip(py.force_and_jacobian(*state), c.force_and_jacobian(*state)):
            np.testing.assert_allclose(b, a, rtol=0.0, atol=1e-12 * np.max(np.abs(a)))
        r = py.film_report(*state)
        want = [r.couette_torque_Nm, r.pressure_torque_Nm, r.friction_power_W, r.inflow_m3_s, r.side_flow_m3_s]
        np.testing.assert_allclose(c.film_report(*state), want, rtol=1e-12)
        assert r.inflow_m3_s == r.side_flow_m3_s  # the groove delivers what leaves by the ends (film.py)
        (pa, ta), (pb, tb) = py.peak_pressure(*state), c.peak_pressure(*state)
        assert abs(pb - pa) <= 1e-12 * pa and abs(tb - ta) <= 1e-12 and pa >= ps


def test_solver_lands_need_two_cells_per_land(lib):
    with pytest.raises(ValueError, match="n_x >= 4"):
        NativeReynolds(lib, grooved(), 32, 2)


@pytest.fixture(scope="module")
def grooved_fmus(tmp_path_factory, native_build_cache):
    """FMI version -> (the native Reynolds FMU of the grooved bearing, its model description)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    folder, out = tmp_path_factory.mktemp("native_groove"), {}
    for version in (2, 3):
        def build(target, version=version):
            return build_native_fmu(target, "reynolds", bearing=grooved(), fmi_version=version, compiler="cc",
                                    options=GRID)
        path = native_build_cache(folder / f"reynolds_groove_fmi{version}.fmu", build, [],
                                  ("groove", "reynolds", version, tuple(GRID.items()), WIDTH, PS))
        out[version] = (path, fmpy.read_model_description(str(path)))
    return out


@pytest.mark.parametrize("version", [2, 3])
def test_grooved_fmu_equals_python(grooved_fmus, version):
    """The native FMU of the grooved bearing: its parameters circumferential_groove [m] and supply_pressure
    [Pa] start at the bearing's; force, K, C and the peak pressure equal the Python Reynolds internal's on
    the same bore (1e-12). (Its thermal model with an oil law: tests/test_native_heat_balance.py.)"""
    path, md = grooved_fmus[version]
    var = {v.name: v for v in md.modelVariables}
    assert float(var["circumferential_groove"].start) == WIDTH and float(var["supply_pressure"].start) == PS
    assert var["circumferential_groove"].unit == "m" and "no [oil] law" in var["thermal"].description
    vr = {n: v.valueReference for n, v in var.items()}
    direct = Reynolds(grooved(), GRID["n_theta"], GRID["n_x"])
    f, get, put = _initialising(path, md, version, "groove")
    f.exitInitializationMode()
    names = ("Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz", *PEAK)
    try:
        t = 0.0
        for state in grooved_states(5, 9):
            put([vr[n] for n in IN], list(state))
            f.doStep(t, 1e-4)
            t += 1e-4
            got = np.array(get([vr[n] for n in names]))
            F, dq, dv = direct.force_and_jacobian(*state)
            K, C = -dq, -dv
            want = np.array([F[0], F[1], *K.ravel(), *C.ravel()])
            np.testing.assert_allclose(got[:10], want, rtol=0.0, atol=1e-12 * np.max(np.abs(want)))
            pk = direct.peak_pressure(*state)
            assert abs(got[10] - pk[0]) <= 1e-12 * pk[0] and abs(got[11] - pk[1]) <= 1e-12
    finally:
        f.terminate()
        f.freeInstance()


def test_grooved_fmu_compliance_checker(grooved_fmus, tmp_path):
    """The FMU Compliance Checker simulates the grooved native FMU (FMI 2.0, CS and ME) with the journal
    circling: 0 warnings and 0 errors."""
    import subprocess

    from conftest import compliance_checker

    checker = compliance_checker()
    path, md = grooved_fmus[2]
    rows = ["time,y,z,vy,vz,omega"]
    w, r = 300.0, 0.3 * GROOVE_CR
    for k in range(11):
        t = 1e-3 * k
        rows.append(f"{t!r},{r * math.cos(w * t)!r},{-r * math.sin(w * t) - r!r},{-r * w * math.sin(w * t)!r},"
                    f"{-r * w * math.cos(w * t)!r},{w!r}")
    (tmp_path / "in.csv").write_text("\n".join(rows) + "\n")
    for interface in ("cs", "me"):
        log = tmp_path / f"check_{interface}.log"
        done = subprocess.run(["env", "-i", str(checker), "-h", "1e-4", "-s", "0.01", "-k", interface, "-i",
                               str(tmp_path / "in.csv"), "-o", str(tmp_path / "out.csv"), "-e", str(log), str(path)],
                              capture_output=True, text=True, timeout=300, check=False)
        text = log.read_text()
        summary = text[text.index("FMU check summary:"):]
        assert done.returncode == 0, summary
        assert "FMU reported:\n\t0 warning(s) and error(s)" in summary, summary
        assert "0 Warning(s)" in summary and "0 Error(s)" in summary, summary


def test_grooved_fmu_refuses_thermal_by_name(grooved_fmus):
    """thermal = true on the grooved native FMU of a bearing without an oil law: initialisation fails naming
    the law (not the groove, whose thermal model the native FMU has: tests/test_native_heat_balance.py), and it
    does not send the user to the internal it already is."""
    path, _md = grooved_fmus[2]
    lines = []
    with pytest.raises(Exception):
        fmpy.simulate_fmu(str(path), stop_time=1e-3, step_size=1e-3, start_values={"thermal": True},
                          debug_logging=True, logger=lambda *args: lines.append(args[-1].decode()))
    text = " ".join(lines)
    assert "needs the oil's viscosity law" in text and "half the rise" not in text, text
    assert "or internal = 'reynolds'" not in text, text
