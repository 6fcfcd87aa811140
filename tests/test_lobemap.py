"""The lobed bore's force map (internals/map/lobemap.py, docs/forcemap.md, "Lobed bores"): the sum of
one partial-arc map per lobe, exact for lobes separated by ambient grooves.

Independent references: the lobed bore's own Reynolds solver (validated against Lund & Thomsen's
elliptical bearing, tests/test_geometry_validation.py), whose answer the reduction must reproduce to
round-off on the solver itself, and to the partial-arc map's interpolation error through the map;
central differences for the Jacobian.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.base import BearingStateError
from bearing_fmu.internals.map.lobemap import LobedForceMap, lobe_arc, lobe_cells, lobed_problem, map_params
from bearing_fmu.internals.map.mapfile import load_any_map, open_map
from bearing_fmu.internals.map.tables import scale
from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

BUNDLED = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
LEMON = BearingParams.from_toml(BUNDLED / "bearing_paper_lemon.toml")
SHIPPED = BUNDLED / "maps" / "paper_lemon.json"
OMEGA = 2.0 * math.pi * 22.0


def _rot(a):
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def _states(P, n, seed, e_hi=0.9):
    """Journal anywhere within e_hi CR of the centre, speeds of both signs, velocities up to 1.5 CR omega."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        e, phi = P.CR * e_hi * math.sqrt(rng.uniform()), rng.uniform(-math.pi, math.pi)
        om = rng.choice([-1.0, 1.0]) * OMEGA * rng.uniform(0.2, 3.0)
        v = rng.normal(size=2) * P.CR * abs(om) * rng.uniform(0, 1.5)
        out.append((e * math.cos(phi), e * math.sin(phi), float(v[0]), float(v[1]), float(om)))
    return out


def _lobe_frames(P, y, z, vy, vz):
    """Per lobe: (alpha_k, the journal state in the arc's frame), from the geometry's own numbers (the
    preload point, C_pad), independently of ``LobedForceMap``."""
    g = P.geometry
    d = g.pad_clearance(P.CR) - P.CR
    tp = g.preload_points()[0]
    shift = d * np.array([-math.sin(tp), math.cos(tp)])  # e' = Rot(-alpha) e + d u(theta_p,0)
    out = []
    for k in range(g.lobes):
        a = 2 * math.pi * k / g.lobes
        e, v = _rot(-a) @ (y, z) + shift, _rot(-a) @ (vy, vz)
        out.append((a, (*e, *v)))
    return out


def test_the_lemon_is_the_sum_of_its_lobes_on_the_solver_itself():
    """The lemon's Reynolds 128 x 16 and the lobe arc's Reynolds 63 x 16 (62 film cells, the lemon's on
    each lobe): the force and the flows are the lobes' sum to round-off (the grooves decouple the lobes,
    and the cells coincide); so the reduction adds no error of its own."""
    arc, grid = map_params(LEMON)
    assert grid == (63, 16) and arc.CR == pytest.approx(LEMON.CR / (1 - 0.5))
    assert arc.geometry.arc == pytest.approx((math.radians(-80.0), math.radians(80.0)))
    lemon, lobe = Reynolds(LEMON, 128, 16), Reynolds(arc, *grid)
    # the arc's film cells are lobe 0's cells of the lemon, and lobe 1's turned by 180 deg
    cells = LEMON.geometry.theta_grid(128)
    film = cells.left[~cells.fixed]
    arc_film = lobe._grid.left[~lobe._grid.fixed]
    for k in range(2):
        own = np.sort(np.mod(film[LEMON.geometry.lobe_of(film + 1e-9) == k] - k * math.pi + math.pi, 2 * math.pi))
        np.testing.assert_allclose(own, np.sort(np.mod(arc_film + math.pi, 2 * math.pi)), rtol=0, atol=1e-12)
    for x in _states(LEMON, 6, 5):
        F = np.array(lemon.force(*x))
        rep = lemon.film_report(*x)
        Fs, q_in, q_s = np.zeros(2), 0.0, 0.0
        for a, s in _lobe_frames(LEMON, *x[:4]):
            Fs += _rot(a) @ np.array(lobe.force(*s, x[4]))
            r = lobe.film_report(*s, x[4])
            q_in, q_s = q_in + r.inflow_m3_s, q_s + r.side_flow_m3_s
        np.testing.assert_allclose(Fs, F, rtol=0, atol=1e-11 * np.abs(F).max())
        assert q_in == pytest.approx(rep.inflow_m3_s, rel=1e-10) and q_s == pytest.approx(rep.side_flow_m3_s, rel=1e-10)


@pytest.fixture(scope="module")
def lemon_map():
    return open_map(SHIPPED, LEMON)


def test_the_shipped_map_is_the_lemon_lobe_and_reproduces_reynolds(lemon_map):
    """Through the map the lemon's force is the lobes' arc map errors summed, nothing else: F_map -
    F_Reynolds equals sum_k Rot(alpha_k) (F_arcmap - F_arcReynolds) to round-off (the reduction exact),
    and that interpolation error is the 3-D maps' (docs/forcemap.md: against the solver at random states
    median 5e-5, p95 6e-4 of max(|F|, S omega) measured at 300 states by benchmarks/lobemap_study.py)."""
    assert isinstance(lemon_map, LobedForceMap)
    table = load_any_map(SHIPPED)
    assert table.Q is not None and lemon_map.film_flow_why == ""  # the thermal model's flows
    arc, grid = map_params(LEMON)
    assert (table.n_theta, table.n_x) == grid  # its truth is the lemon's default grid on each lobe
    lemon, lobe = Reynolds(LEMON, 128, 16), Reynolds(arc, *grid)
    errs = []
    for x in _states(LEMON, 40, 7):
        F, Fr = np.array(lemon_map.force(*x)), np.array(lemon.force(*x))
        parts = sum(_rot(a) @ (np.array(lemon_map.map.force(*s, x[4])) - np.array(lobe.force(*s, x[4])))
                    for a, s in _lobe_frames(LEMON, *x[:4]))
        np.testing.assert_allclose(F - Fr, parts, rtol=0, atol=1e-10 * np.abs(Fr).max())
        errs.append(np.linalg.norm(F - Fr) / max(np.linalg.norm(Fr), scale(LEMON) * abs(x[4])))
    assert np.median(errs) < 2e-4 and max(errs) < 2e-2, (np.median(errs), max(errs))


def test_jacobian_and_flows(lemon_map):
    """The analytic Jacobian (each lobe's turned back) against central differences of the map's force;
    the film report's flows and friction against the lemon's Reynolds report (to the maps' interpolation
    error, as the force), with the inflow entering at the grooves' edges only (each lobe fed by its
    groove) and, at a static state, at least the side flow (the rest leaves at the trailing edges)."""
    rey = Reynolds(LEMON, 128, 16)
    for y, z, vy, vz, om in _states(LEMON, 6, 11, e_hi=0.7):
        F, Jq, Jv = lemon_map.force_and_jacobian(y, z, vy, vz, om)
        x = np.array([y, z, vy, vz])
        for j, h in enumerate((1e-9 * LEMON.CR,) * 2 + (1e-9 * LEMON.CR * abs(om),) * 2):
            dx = np.zeros(4)
            dx[j] = h
            fd = (np.array(lemon_map.force(*(x + dx), om)) - np.array(lemon_map.force(*(x - dx), om))) / (2 * h)
            an = (Jq if j < 2 else Jv)[:, j % 2]
            np.testing.assert_allclose(an, fd, rtol=0, atol=1e-6 * np.abs(np.hstack([Jq, Jv * abs(om)])).max()
                                       / (1.0 if j < 2 else abs(om)))
        rm, rr = lemon_map.film_report(y, z, vy, vz, om), rey.film_report(y, z, vy, vz, om)
        np.testing.assert_allclose([rm.inflow_m3_s, rm.side_flow_m3_s, rm.friction_torque_Nm],
                                   [rr.inflow_m3_s, rr.side_flow_m3_s, rr.friction_torque_Nm], rtol=1e-2)
    for y, z in ((0.0, -0.3 * LEMON.CR), (0.2 * LEMON.CR, 0.1 * LEMON.CR)):
        rm = lemon_map.film_report(y, z, 0.0, 0.0, OMEGA)
        assert rm.inflow_m3_s >= rm.side_flow_m3_s * (1 - 1e-3) > 0


def test_compiled_kernel_is_the_internal(lemon_map):
    """The compiled kernel (what the host's compiled loop calls) gives force_and_jacobian's numbers to the
    bit, and status 1 where the internal refuses."""
    from bearing_fmu.internals.compiled import evaluate

    cf = lemon_map.compiled_force()
    for x in _states(LEMON, 8, 13):
        status, F, Jq, Jv = evaluate(cf, *x)
        F0, Jq0, Jv0 = lemon_map.force_and_jacobian(*x)
        assert status == 0 and np.array_equal(F, F0) and np.array_equal(Jq, Jq0) and np.array_equal(Jv, Jv0)
    assert evaluate(cf, 0.0, -1.0 * LEMON.CR, 0.0, 0.0, OMEGA)[0] == 1
    assert evaluate(cf, 0.0, 0.0, math.inf, 0.0, OMEGA)[0] == 1


def test_beyond_a_lobe_is_refused(lemon_map):
    """The map covers the journal within eps_max C_pad of every lobe's centre; farther it refuses by
    name (the lemon's Reynolds solver takes it to its wall, sideways up to 2 CR)."""
    with pytest.raises(BearingStateError, match="centre of lobe 1"):
        lemon_map.force(0.0, -1.0 * LEMON.CR, 0.0, 0.0, OMEGA)  # 0.9 CR ... 1.0 C_pad from lobe 1's centre
    with pytest.raises(BearingStateError, match="not finite"):
        lemon_map.force(math.nan, 0.0, 0.0, 0.0, OMEGA)
    lemon_map.force(1.5 * LEMON.CR, 0.0, 0.0, 0.0, OMEGA)  # sideways, beyond CR, within the lobes


def _lobed(**kw):
    return dataclasses.replace(LEMON, geometry=dataclasses.replace(LEMON.geometry, **kw))


@pytest.mark.parametrize("kw, match", [
    (dict(grooves=()), "with 0 groove"),
    (dict(grooves=(math.radians(80.0), math.radians(260.0))), "lies in no groove"),
    (dict(grooves=(math.radians(95.0), math.radians(265.0))), "different offsets"),
    (dict(supply_pressure=1e5), "supply_pressure_kPa = 100"),
], ids=["no grooves", "grooves off the boundaries", "unequal lobes", "supply pressure"])
def test_lobed_bores_without_separating_grooves_are_refused(kw, match, tmp_path):
    """Lobes whose films connect (no groove over a boundary) have no exact lobe sum: refused by name,
    by the map command (exit 2 as a ValueError) and by the internal."""
    from bearing_fmu.internals.map.build import command

    P = _lobed(**kw)
    assert match in lobed_problem(P.geometry)
    f = tmp_path / "b.toml"
    g = P.geometry.as_table()
    f.write_text("[bearing]\nD_mm = 31.0\nL_mm = 20.0\nCR_um = 90.0\nmu_Pa_s = 0.05\n[geometry]\n"
                 + "".join(f"{k} = {json.dumps(v)}\n" for k, v in g.items()))
    with pytest.raises(ValueError, match=match):
        command(bearing=f, output=tmp_path / "m.json", quiet=True)
    with pytest.raises(ValueError, match=match):
        LobedForceMap(P, load_any_map(SHIPPED))


def test_lobe_geometry_and_grids():
    """The lobe arc from the geometry (lemon: -80 .. 80 deg, C_pad = 2 CR; a three-lobe bore turned by
    its lobe_angle), and a lemon grid whose lobes get unequal cells refused by name."""
    tri = dataclasses.replace(LEMON, geometry=Geometry(lobes=3, preload=0.4, lobe_angle=math.radians(10.0),
                                                       grooves=tuple(math.radians(a) for a in (70.0, 190.0, 310.0)),
                                                       groove_width=math.radians(30.0)))
    arc = lobe_arc(tri)
    assert np.degrees(arc.geometry.arc) == pytest.approx((-35.0, 55.0))  # lead -50 deg, + 15 deg (half a groove); span 120 - 30
    assert lobe_cells(LEMON, 128) == 62 and lobe_cells(tri, 96) == 30  # 6 groove cells (each split by its boundary)
    with pytest.raises(ValueError, match="n_theta = 127"):
        lobe_cells(LEMON, 127)
    # the three-lobe bore's sum holds on its solver too (one state)
    P3 = tri
    arc3, grid3 = map_params(P3, (96, 8))
    x = (0.2 * P3.CR, -0.3 * P3.CR, 0.01, -0.02, OMEGA)
    F = np.array(Reynolds(P3, 96, 8).force(*x))
    lobe = Reynolds(arc3, *grid3)
    d = P3.geometry.pad_clearance(P3.CR) - P3.CR
    tp = P3.geometry.preload_points()[0]
    Fs = np.zeros(2)
    for k in range(3):
        a = 2 * math.pi * k / 3
        e, v = _rot(-a) @ x[:2] + d * np.array([-math.sin(tp), math.cos(tp)]), _rot(-a) @ x[2:4]
        Fs += _rot(a) @ np.array(lobe.force(*e, *v, x[4]))
    np.testing.assert_allclose(Fs, F, rtol=0, atol=1e-11 * np.abs(F).max())


def test_map_command_builds_the_lobe_map_and_the_store_finds_it(tmp_path, monkeypatch, capsys):
    """`bearing-fmu map --bearing LEMON` builds the lobe arc's map through the row builder (a tiny one
    here), into the store; run again it is found there; the map internal opens it for the lemon."""
    from bearing_fmu.internals.map.build import command

    monkeypatch.setenv("BEARING_FMU_MAP_STORE", str(tmp_path / "store"))
    out = tmp_path / "lemon.json"
    kw = dict(bearing=BUNDLED / "bearing_paper_lemon.toml", output=out, resolution=(4, 8), n_phi=4, grid=(24, 4),
              workers=1, quiet=True)
    assert command(**kw) == 0
    text = capsys.readouterr().out
    assert "its map is the lobes' partial arc" in text and "10 cells on the arc as on each lobe" in text
    table = load_any_map(out)
    assert table.geometry.arc is not None and (table.n_theta, table.n_x) == (11, 4)
    assert isinstance(open_map(out, LEMON), LobedForceMap)
    assert command(**kw) == 0 and "found in the map store" in capsys.readouterr().out
    with pytest.raises(ValueError, match="--grid: n_theta = 25"):
        command(**{**kw, "grid": (25, 4)})


@pytest.mark.slow
@pytest.mark.parametrize("speed_hz, mass_kg", [(None, None), (30.0, 4e-3)], ids=["scene 22 Hz 8.5 g", "30 Hz 4 g"])
def test_closed_loop_against_reynolds(speed_hz, mass_kg, tmp_path):
    """Issue 35's check: the lemon scene, and one of the test's own (30 Hz, 4 g), with the shipped map
    against the same scene on the lemon's Reynolds 128 x 16 called directly: orbit RMS <= 0.05 % CR
    (measured 0.003 % CR, docs/forcemap.md)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("lobemap_study", BUNDLED.parents[1] / "benchmarks" / "lobemap_study.py")
    study = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(study)
    err, _t_rey, _t_map, s_rey, s_map = study.closed_loop(BUNDLED / "scenes" / "paper_lemon_22hz.toml", SHIPPED,
                                                          (128, 16), speed_hz, mass_kg)
    assert s_rey == s_map == "ok"
    assert err["orbit_rms_pct_cr"] <= 0.05, err


@pytest.mark.slow
@pytest.mark.native
def test_the_native_map_fmu_sums_the_lobes_like_the_python_internal(tmp_path):
    """rotor-host run --native on the lemon scene (the native map FMU of the shipped lobe map, c/internal_map.c
    summing the lobes) follows the run with the Python internal called in-process: forces equal to ~1e-14
    (tests/test_native_fmu.py compares them at random states to 1e-12), so the orbits to 1e-9 CR."""
    from rotor_host.cli import main
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    scene_file = BUNDLED / "scenes" / "paper_lemon_22hz.toml"
    assert main(["run", str(scene_file), "--internal", "map", "--via", "fmu", "--native", "--t-end", "0.01", "--out",
                 str(tmp_path), "--no-plots", "--quiet"]) == 0
    native = np.load(tmp_path / "paper_lemon_22hz_map_native.npz")
    direct = run_scene(load_scene(scene_file).with_internal("map", via="direct", t_end_s=0.01), tmp_path, stem="direct")
    assert direct.ok and len(native["t"]) == len(direct.arrays["t"]) == 101
    for key in ("y", "z"):
        assert np.max(np.abs(native[key] - direct.arrays[key])) < 1e-9 * LEMON.CR


def lemon_oil_bearing(folder: Path) -> Path:
    """bearing_paper_lemon.toml with bearing_paper_vg46.toml's [oil] law instead of its 50 mPa s."""
    oil = (BUNDLED / "bearing_paper_vg46.toml").read_text().split("[oil]")[1]
    text = "\n".join(line for line in (BUNDLED / "bearing_paper_lemon.toml").read_text().splitlines()
                     if not line.startswith("mu_Pa_s"))
    path = folder / "bearing_lemon_vg46.toml"
    path.write_text(text + "\n[oil]" + oil)
    return path


@pytest.fixture(scope="module")
def native_lemon(tmp_path_factory, native_build_cache):
    """(the native map FMU of the lemon with the VG 46 oil law and thermal = true, on the shipped lobe map
    subsampled to 4 x 8 x 8 so that its C tables compile in a second; the lobe map file; the bearing)."""
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.internals.map.groovemap import save_grooved_map

    folder = tmp_path_factory.mktemp("native_lemon")
    t = load_any_map(SHIPPED)
    idx = np.ix_(np.arange(0, 40, 13), np.arange(0, 32, 4), np.arange(0, 40, 5))
    path = save_grooved_map(dataclasses.replace(t, H=t.H[idx], Q=t.Q[idx], coefficients=None, flow_coefficients=None),
                            folder / "lemon_coarse.json")
    bearing = lemon_oil_bearing(folder)
    params = BearingParams.from_toml(bearing)
    fmu = native_build_cache(folder / "map_lemon.fmu", lambda target: build_native_fmu(
        target, "map", map=path, bearing=params, fmi_version=2, compiler="cc", thermal=True), [bearing, path],
        ("lemon coarse thermal", "map"))
    return fmu, path, params


@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
@pytest.mark.native
def test_native_lobe_sum_equals_the_python_internal_and_compiles_clean(native_lemon, tmp_path):
    """Forces and Jacobians of the native map FMU (c/internal_map.c summing the lobes in kernels.lobes_force's
    order of operations) equal the Python internal's to the bit at random states; beyond a lobe's map it
    discards the step naming the lobe; its sources compile under -Wall -Wextra -Wpedantic -Werror."""
    fmpy = pytest.importorskip("fmpy")
    from test_native_fmu import DISCARD, OK, Raw, python_outputs
    from test_native_platforms import sources_compile_without_a_warning

    from test_native_fmu_thermal import parameters

    fmu, path, params = native_lemon
    md = fmpy.read_model_description(str(fmu))
    p = parameters(md)  # the FMU's D, L, CR and mu (the oil's at its start temperature)
    py = open_map(path, dataclasses.replace(params, D=p["D"], L=p["L"], CR=p["CR"], mu=p["mu"], oil=None))
    unzip = fmpy.extract(str(fmu))
    raw = Raw(fmu, unzip)
    try:
        assert raw.set("thermal", False) == OK and raw.init() == OK
        for k, st in enumerate(_states(LEMON, 20, 17)):
            assert raw.set_inputs(st) == OK and raw.step(1e-4 * k) == OK, raw.last()
            status, got = raw.outputs()
            assert status == OK and np.array_equal(got, python_outputs(py, st)), (st, got - python_outputs(py, st))
        assert raw.set_inputs((0.0, -1.0 * LEMON.CR, 0.0, 0.0, OMEGA)) == OK
        assert raw.step(1.0) == DISCARD and "from the centre of lobe 1" in raw.last()
    finally:
        raw.close()
    sources_compile_without_a_warning(Path(unzip), tmp_path)


@pytest.mark.native
def test_native_lobe_film_report_equals_the_python_internal(native_lemon):
    """The thermal model on the native lemon map FMU (c/map_flows.c: each lobe's film report in its frame,
    summed): its friction power and side flow over a spiral orbit equal the Python LobedForceMap's film
    report at each state (to 1e-13, as the grooved map's in tests/test_native_groove_thermal.py)."""
    pytest.importorskip("fmpy")
    import fmpy
    from test_native_fmu_thermal import check_reports, parameters, run, trajectory

    fmu, path, params = native_lemon
    md = fmpy.read_model_description(str(fmu))
    got = run(fmu, md, ramp=1.0)
    p = parameters(md)
    internal = open_map(path, dataclasses.replace(params, D=p["D"], L=p["L"], CR=p["CR"], mu=p["mu"], oil=None))
    check_reports(got, trajectory(), internal, p["mu"], 1e-13, 0.5)
