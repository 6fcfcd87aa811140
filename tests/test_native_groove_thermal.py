"""The native map FMU's thermal ports on a grooved bore's map (docs/thermal.md, docs/fmu.md): its film
report in C from the version 4 flow tables (c/map_flows.c, a port of GroovedForceMap.film_report:
the Couette torque over the film's segments in closed form, the pressure torque from the force, the
side flow and each supply edge's inflow from the flow spline over one period, renumbered in the
other), against the Python FMU with the same map over a run whose T_supply ramps, against the Python
map internal's film_report, in Model Exchange, under the FMU Compliance Checker; a version 2 grooved
map (no flow tables) refuses thermal by name; a host scene on the native FMU equals the Python FMU
route.

The map: the shipped paper_2groove.json (64 x 32 x 64) subsampled to 8 x 8 x 8 (every 9th s, 4th phi,
8th beta: the same axes' end points, the shipped values), so that its C tables compile in a second;
the shipped map's own build is measured in docs/studies/2026-11-26-groove-flows.md. The bearing:
bearing_paper_2groove.toml with bearing_paper_vg46.toml's [oil] (the shipped grooved bearing has none).
Helpers: tests/test_native_fmu_thermal.py.
"""

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")

from bearing_fmu.physics.params import BearingParams  # noqa: E402

from test_native_fmu_thermal import GRID, compliance_check, model_exchange_check, run  # noqa: E402
from test_native_map_thermal import RAMP, check_against_python  # noqa: E402
from thermal_runs import native_equals_python  # noqa: E402

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
SHIPPED = MODELS / "maps" / "paper_2groove.json"


def grooved_oil_bearing(folder: Path) -> Path:
    """bearing_paper_2groove.toml with the VG 46 oil law instead of its 50 mPa s (a file in ``folder``)."""
    oil = (MODELS / "bearing_paper_vg46.toml").read_text().split("[oil]")[1]
    text = (MODELS / "bearing_paper_2groove.toml").read_text()
    text = "\n".join(line for line in text.splitlines() if not line.startswith("mu_Pa_s"))
    path = folder / "bearing_2groove_vg46.toml"
    path.write_text(text + "\n[oil]" + oil)
    return path


def coarse_map(folder: Path) -> Path:
    """The shipped two-groove map subsampled to 8 x 8 x 8 (module docstring), with its flow tables."""
    from bearing_fmu.internals.map.groovemap import grooved_from_data, save_grooved_map

    t = grooved_from_data(SHIPPED, json.loads(SHIPPED.read_text()))
    idx = np.ix_(np.arange(0, 64, 9), np.arange(0, 32, 4), np.arange(0, 64, 8))
    return save_grooved_map(dataclasses.replace(t, H=t.H[idx], Q=t.Q[idx], coefficients=None, flow_coefficients=None),
                            folder / "paper_2groove_8.json")


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """(the bearing file, its parameters, the coarse version 4 map)."""
    folder = tmp_path_factory.mktemp("groove_thermal")
    bearing = grooved_oil_bearing(folder)
    return bearing, BearingParams.from_toml(bearing), coarse_map(folder)


@pytest.fixture(scope="module")
def groove3(files, tmp_path_factory, native_build_cache):
    """FMI version -> (the native map FMU of the grooved VG 46 bearing on the coarse map, starting
    with thermal = true, its model description)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    bearing, params, path = files
    folder, out = tmp_path_factory.mktemp("native_groove"), {}
    for version in (2, 3):
        def build(target, version=version):
            return build_native_fmu(target, "map", map=path, bearing=params, fmi_version=version, compiler="cc",
                                    thermal=True)
        fmu = native_build_cache(folder / f"map_2groove_fmi{version}.fmu", build, [bearing, path],
                                 ("grooved thermal", "map", version))
        out[version] = (fmu, fmpy.read_model_description(str(fmu)))
    return out


@pytest.fixture(scope="module")
def python_groove(files, tmp_path_factory):
    """The Python FMU with the coarse map bundled and the grooved VG 46 bearing's bore and oil as its
    defaults (test_native_fmu_thermal.run sets D, L, CR, mu and the oil: the bore is these)."""
    from bearing_fmu.fmu.build import build_fmu

    _bearing, params, path = files
    return build_fmu(tmp_path_factory.mktemp("python_groove") / "bearing.fmu", surrogate=[path], bearing=params)


def internal_of(files):
    """The Python map internal on the coarse map for the FMU's (D, L, CR, mu) with the grooved bore."""
    from bearing_fmu.internals.map.mapfile import open_map

    _bearing, bore, path = files
    return lambda params: open_map(path, dataclasses.replace(params, geometry=bore.geometry))


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_grooved_map_equals_the_python_fmu(groove3, python_groove, files, version):
    """The native grooved map FMU with thermal on over a Co-Simulation run whose T_supply ramps 45 ->
    67 C: T_eff, mu_eff, P_loss, Q_side, the force and its tangent equal the Python FMU's with the same
    map within RTOL = 1e-12 of each output's largest value (c/map_flows.c is GroovedForceMap.film_report's
    operations in their order; the oil law and heat balance the ones tests/test_native_fmu_thermal.py
    checks; measured: every output the same bits). And the Python map internal's film_report at each
    state (its force at the file's mu): P_loss its friction power times mu_eff / mu, Q_side its side
    flow, within 1e-13 relative (test_native_map_thermal.py's check_against_python)."""
    check_against_python(*groove3[version], python_groove, files[2].name, internal_of(files))


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_grooved_map_model_exchange_state_and_derivative(groove3, files, version):
    """Model Exchange: T_eff the state, der(T_eff) the heat balance's rate from the Python grooved map
    internal's film report, mu_eff and the force at T (test_native_fmu_thermal.py's checks, 1e-12)."""
    model_exchange_check(*groove3[version], version, internal_of(files))


@pytest.mark.slow
@pytest.mark.parametrize("interface", ["me", "cs"])
def test_grooved_map_compliance_checker_with_thermal_on(groove3, interface, tmp_path):
    """The FMU Compliance Checker on the native grooved map FMU (FMI 2.0) with thermal on, T_supply
    ramped 40 -> 60 C while the journal circles: 0 warnings and 0 errors; T_eff moves."""
    compliance_check(groove3[2][0], interface, tmp_path)


@pytest.mark.slow
def test_several_internals_with_a_grooved_map(groove3, files, tmp_path, native_build_cache):
    """An FMU of several internals (reynolds and the grooved map, c/bn_parts.c) with internal = 'map'
    runs the thermal model of the native grooved map FMU: the same bits over the ramped CS run (the
    map's data section holds its flow tables beside the Reynolds solver's)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    bearing, params, path = files
    both = native_build_cache(tmp_path / "reynolds_map_2groove.fmu",
                              lambda target: build_native_fmu(target, "reynolds,map", map=path, bearing=params,
                                                              compiler="cc", options=GRID),
                              [bearing, path], ("grooved thermal", "reynolds,map"))
    md = fmpy.read_model_description(str(both))
    assert np.array_equal(run(both, md, ramp=RAMP, internal="map"), run(*groove3[2], ramp=RAMP))


@pytest.mark.slow
def test_grooved_map_sources_compile_without_a_warning(groove3, tmp_path):
    """The grooved map FMU's sources (map_flows.c with its flow tables) under gcc and zig's clang with
    -Wall -Wextra -Wpedantic -Werror, as test_native_platforms.py's full-bore map (the full bore's
    Couette torque, unused here, is left out: an unused static function is a warning)."""
    from test_native_platforms import sources_compile_without_a_warning

    sources_compile_without_a_warning(Path(fmpy.extract(str(groove3[2][0]))), tmp_path)


@pytest.mark.slow  # 0.7 s: the shipped map read, two models generated
def test_a_grooved_map_without_flow_tables_refuses_thermal(files, tmp_path):
    """A version 2 grooved map (the coarse map with its flow keys dropped): a native map FMU starting
    with thermal = true is refused before anything is compiled, naming the file and why (the Python
    map's film_flow_why: rebuild it); without thermal, the parameter thermal says why it stays false
    and no flow table is compiled in. The version 4 map's header has the flow spline over one period
    (8 attitudes + 3), the edges' renumbering over the turn's 2 periods, its 4 supply edges and 2 film
    segments (the two 160 deg pads); for a
    bearing without an oil law it leaves them out (models.map.GROOVED_NO_OIL_WHY: 2.5 times the force's
    coefficients, of no use without the law)."""
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.fmu.native.codegen import native_model

    _bearing, params, path = files
    data = json.loads(path.read_text())
    for key in ("Q", "flow_edges_deg", "flow_meaning"):
        data.pop(key)
    old = tmp_path / "v2.json"
    old.write_text(json.dumps({**data, "version": 2}))
    with pytest.raises(ValueError, match=r"thermal = true needs the film's flows and the bearing's oil law: the "
                                         r"grooved map file .*v2.json has no flow tables \(format version 2"):
        build_native_fmu(tmp_path / "x.fmu", "map", map=old, bearing=params, compiler="cc", thermal=True)
    assert not (tmp_path / "x.fmu").exists()
    model = native_model("map", params, map=old)
    thermal = next(v for v in model.variables if v.name == "thermal")
    assert "not in this native FMU (the grooved map file" in thermal.description
    assert "#define BN_FILM_FLOW 0" in model.config_h and "MAP_QC" not in model.data_h
    assert "der(T_eff)" not in {v.name for v in model.variables}
    model = native_model("map", params, map=path)
    assert "#define BN_FILM_FLOW 1" in model.config_h and "der(T_eff)" in {v.name for v in model.variables}
    for line in ("#define MAP_NQ 5", "#define MAP_NQP 11", "#define MAP_N_EDGES 4", "#define MAP_N_FILM 2",
                 "#define MAP_QTURNS 2", "MAP_QIMG[10] = {0, 1, 2, 3, 4, 0, 3, 4, 1, 2};"):
        assert line in model.data_h
    # a bearing without an oil law, with which thermal = true is refused anyway: the tables are left out
    from bearing_fmu.fmu.native.generators.map import GROOVED_NO_OIL_WHY

    model = native_model("map", dataclasses.replace(params, oil=None), map=path)
    thermal = next(v for v in model.variables if v.name == "thermal")
    assert GROOVED_NO_OIL_WHY in thermal.description and "MAP_QC" not in model.data_h


@pytest.mark.slow
def test_a_scene_on_the_native_grooved_map_with_a_supply_temperature(files, tmp_path):
    """The paper rotor on two-groove bearings with ISO VG 46 supplied at 40 C, a run-up 22 -> 30 Hz in
    4 ms on the coarse grooved map through the native map FMU's thermal ports (refused before: its film
    report was not in C) equals the run through the Python FMU to round-off (1e-12 of each signal's
    largest value: the same film report, oil law and lag, the tests above), its thermal records too
    (T_eff, mu_eff, P_loss, Q_side over time)."""
    from rotor_host.model.speed import SpeedProfile
    from rotor_host.scenes.scene import load_scene

    bearing, _params, path = files
    (tmp_path / "rotor.toml").write_text((MODELS / "rotor_paper_2groove.toml").read_text().replace(
        '"bearing_paper_2groove.toml"', json.dumps(str(bearing))))
    scene_text = (MODELS / "scenes" / "paper_2groove_22hz.toml").read_text().replace(
        'rotor = "../rotor_paper_2groove.toml"', 'rotor = "rotor.toml"\nsupply_temperature_C = 40.0').replace(
        '"../maps/paper_2groove.json"', json.dumps(str(path)))
    (tmp_path / "scene.toml").write_text(scene_text)
    scene = dataclasses.replace(load_scene(tmp_path / "scene.toml"), speed_profile=SpeedProfile((0.0, 0.004),
                                                                                               (22.0, 30.0)))
    scene = scene.with_internal("map", options={"map": {"map": str(path)}}, t_end_s=0.004)
    out = native_equals_python(scene, tmp_path)
    assert out["native"]["speed_hz"][-1] == pytest.approx(30.0)


@pytest.mark.slow
def test_a_partial_arc_map_equals_the_python_fmu(tmp_path, native_build_cache):
    """A 180 deg arc (the lower half, 90 .. 270 deg; the paper bearing with VG 46): its map's period is
    the whole turn (no renumbering of edges), its two supply edges of opposite signs and its one film
    segment; a tiny map (4 x 8 x 8 on Reynolds 32 x 4, its own values: the equality needs no accuracy)
    through the native FMU with thermal on equals the Python FMU and the Python map internal's
    film_report as the grooved map above (check_against_python; measured: every output the same bits)."""
    import math

    from bearing_fmu.fmu.build import build_fmu
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.internals.map.groovemap import save_grooved_map, tabulate_grooved
    from bearing_fmu.physics.bore.geometry import Geometry

    vg46 = BearingParams.from_toml(MODELS / "bearing_paper_vg46.toml")
    arc = dataclasses.replace(vg46, geometry=Geometry(arc=(math.radians(90.0), math.radians(270.0))))
    path = save_grooved_map(tabulate_grooved(arc, n_eps=4, n_phi=8, n_beta=8, n_theta=32, n_x=4), tmp_path / "arc.json")
    fmu = native_build_cache(tmp_path / "map_arc.fmu",
                             lambda target: build_native_fmu(target, "map", map=path, bearing=arc, compiler="cc",
                                                             thermal=True),
                             [path], ("grooved thermal", "map", "arc", repr(arc)))
    python_fmu = build_fmu(tmp_path / "python_arc.fmu", surrogate=[path], bearing=arc)
    md = fmpy.read_model_description(str(fmu))
    from bearing_fmu.internals.map.mapfile import open_map

    check_against_python(fmu, md, python_fmu, path.name,
                         lambda params: open_map(path, dataclasses.replace(params, geometry=arc.geometry)),
                         rise_K=4.0)  # 4.9 K measured (a 180 deg film)
