"""The native Taylor FMU's thermal ports (docs/thermal.md, docs/fmu.md): its film report in C from the
surrogate file's film fit (c/taylor_film.c, a port of Taylor.film_report behind
DomainGuard.film_report), against the Python FMU with the same surrogate file over a run whose
T_supply ramps, against the Python Taylor internal's film_report, in Model Exchange, under the FMU
Compliance Checker; outside the fitted domain with domain_action = fallback (an FMU of the taylor
and reynolds internals) the Reynolds report blended in as the Python guard does; a version 1
surrogate file (no film fit) refuses thermal by name. The surrogate: tests/conftest.py
taylor_film_file (the ISO VG 46 paper bearing at 44 Hz, its film fitted to the Reynolds solver).
The helpers: tests/test_native_fmu_thermal.py.
"""

import math

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")

from test_native_fmu_thermal import (
    GRID,
    RTOL,
    VG46,
    by_version,
    check_reports,
    compliance_check,
    model_exchange_check,
    parameters,
    run,
)

from bearing_fmu.physics.params import BearingParams

RAMP = 2.0  # K per step: T_supply 45 -> 67 C over the run


@pytest.fixture(scope="module")
def taylor3(tmp_path_factory, native_build_cache, taylor_film_file):
    """FMI version -> (the native Taylor FMU of the VG 46 bearing on the film-fitted surrogate,
    starting with thermal = true, its model description)."""
    return by_version(tmp_path_factory.mktemp("native_taylor_thermal"), native_build_cache, "taylor",
                      [taylor_film_file], surrogate=taylor_film_file, thermal=True)


@pytest.fixture(scope="module")
def python_fmu(tmp_path_factory, code_cache, taylor_film_file):
    """The Python FMU with the film-fitted surrogate bundled."""
    from bearing_fmu.fmu.build import build_fmu

    return build_fmu(tmp_path_factory.mktemp("py_taylor") / "bearing.fmu", surrogate=[taylor_film_file])


def orbit(md, n=12, speed=0.05):
    """The journal on a widening circle about the surrogate's expansion point (the native FMU's start
    y, z), 0.05 .. 0.16 CR, its velocity ``speed`` omega CR, at the surrogate's speed omega."""
    s = {v.name: float(v.start) for v in md.modelVariables if v.name in ("y", "z", "omega", "CR")}
    w, CR, out = s["omega"], s["CR"], []
    for k in range(n):
        a, r = 0.4 * k, (0.05 + 0.01 * k) * CR
        out.append((s["y"] + r * math.cos(a), s["z"] + r * math.sin(a), -speed * w * CR * math.sin(a),
                    speed * w * CR * math.cos(a), w))
    return out


def python_run(python_fmu, md, film, states, **strings):
    """The Python FMU's outputs over ``states`` on the Taylor internal with ``film``'s surrogate."""
    return run(python_fmu, fmpy.read_model_description(str(python_fmu)), python=True, native_md=md, ramp=RAMP,
               states=states, strings={"internal": "taylor", "surrogate": film.name, **strings})


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_taylor_equals_the_python_fmu(taylor3, python_fmu, taylor_film_file, version):
    """The native Taylor FMU with thermal on over a Co-Simulation run whose T_supply ramps 45 -> 67 C:
    T_eff, mu_eff, P_loss, Q_side, the force and its tangent equal the Python FMU's with the same
    surrogate file within RTOL = 1e-12 of each output's largest value (round-off: the C film report
    is Taylor.film_report's operations in the same order, but the fit's basis is summed in another
    order than numpy's matrix product, the force's monomials as internal_taylor.c sums them; the oil
    law and heat balance the ones the Reynolds comparison checks; measured: 5.3e-16 at most, T_eff,
    mu_eff and P_loss the same bits). And the Python Taylor internal's film_report at each state:
    P_loss its friction power times mu_eff / mu, Q_side its side flow, within 1e-12 relative."""
    from bearing_fmu.internals.taylor import Taylor

    path, md = taylor3[version]
    states = orbit(md)
    got = run(path, md, ramp=RAMP, states=states)
    want = python_run(python_fmu, md, taylor_film_file, states)
    scale = np.max(np.abs(want), axis=0)
    assert np.max(np.abs(got - want) / scale) <= RTOL
    check_reports(got, states, Taylor.from_file(taylor_film_file), parameters(md)["mu"], 1e-12, 2.0)


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_taylor_model_exchange_state_and_derivative(taylor3, taylor_film_file, version):
    """Model Exchange of the native Taylor FMU: as test_native_fmu_thermal.py's
    test_model_exchange_state_and_derivative, the rate and the force against the Python Taylor
    internal's film report and force (within 1e-12)."""
    from bearing_fmu.internals.taylor import Taylor

    path, md = taylor3[version]
    model_exchange_check(path, md, version, lambda params: Taylor.from_file(taylor_film_file, params),
                         state=orbit(md)[3])


@pytest.mark.slow
@pytest.mark.parametrize("interface", ["me", "cs"])
def test_taylor_compliance_checker_with_thermal_on(taylor3, interface, tmp_path):
    """The FMU Compliance Checker on the native Taylor FMU with thermal on, T_supply ramped 40 -> 60 C
    in its input file while the journal circles its expansion point at 0.1 CR (inside the fitted
    domain: no warning): 0 warnings and 0 errors from the FMU and the checker; T_eff moves."""
    path, md = taylor3[2]
    start = {v.name: float(v.start) for v in md.modelVariables if v.name in ("y", "z", "CR")}
    compliance_check(path, interface, tmp_path, orbit=(start["y"] / start["CR"], start["z"] / start["CR"], 0.1))


@pytest.mark.slow
def test_fallback_outside_the_domain_equals_the_python_fmu(taylor3, python_fmu, taylor_film_file,
                                                          tmp_path_factory, native_build_cache):
    """An FMU of the taylor and reynolds internals with domain_action = fallback, the journal's speed
    rising from inside the fitted domain to 1.1 and 1.3 times its velocity bound (the guard's
    distance 0 < d < 0.1, the blending band, and beyond it): the thermal outputs and the force equal
    the Python FMU's (its guard's film_report: the Reynolds report on the same 32 x 4 grid, blended
    with the surrogate's) within RTOL (measured: 2.8e-15 at most, Cyy; T_eff, mu_eff, P_loss the same
    bits); with internal = 'taylor' inside the domain, the single native Taylor FMU's bits."""
    from bearing_fmu.internals.taylor import Taylor

    path, md = by_version(tmp_path_factory.mktemp("taylor_fallback"), native_build_cache, "taylor,reynolds",
                          [taylor_film_file], surrogate=taylor_film_file, thermal=True,
                          options={**GRID, "domain_action": "fallback"})[2]
    inside = orbit(md)
    assert np.array_equal(run(path, md, ramp=RAMP, states=inside), run(*taylor3[2], ramp=RAMP, states=inside))
    states = [*inside[:4], *orbit(md, 8, speed=0.31)[4:6], *orbit(md, 8, speed=0.39)[6:8]]
    t = Taylor.from_file(taylor_film_file)
    d = [t.domain_distance(*s[:4]) for s in states]
    assert max(d[:4]) <= 0.0 and 0.0 < min(d[4:6]) and max(d[4:6]) < 0.1 and 0.1 < min(d[6:]) < 0.5, d
    got = run(path, md, ramp=RAMP, states=states)
    want = python_run(python_fmu, md, taylor_film_file, states, domain_action="fallback")
    scale = np.max(np.abs(want), axis=0)
    assert np.max(np.abs(got - want) / scale) <= RTOL


def test_a_version_1_surrogate_refuses_thermal(surrogate_file, tmp_path):
    """A version 1 surrogate file (the force alone): a native Taylor FMU starting with thermal = true
    is refused before anything is compiled, naming why (the Python internal's film_flow_why); without
    thermal its thermal parameter says why it stays false and the build has no film report."""
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.fmu.native.codegen import native_model

    with pytest.raises(ValueError, match=r"thermal = true needs the film's flows and the bearing's oil law: the "
                                         rf"surrogate file {surrogate_file} has no film fit \(format version 1"):
        build_native_fmu(tmp_path / "x.fmu", "taylor", surrogate=surrogate_file, compiler="cc", thermal=True)
    model = native_model("taylor", None, surrogate=surrogate_file)
    thermal = next(v for v in model.variables if v.name == "thermal")
    assert f"not in this native FMU (the surrogate file {surrogate_file} has no film fit" in thermal.description
    assert "#define BN_FILM_FLOW 0" in model.config_h and "TAY_FILM_COEF" not in model.data_h
    assert "der(T_eff)" not in {v.name for v in model.variables}


def test_a_version_1_surrogate_beside_reynolds(surrogate_file):
    """An FMU of the taylor and reynolds internals with a version 1 surrogate (bn_parts.c): the
    thermal model runs with internal = 'reynolds'; with internal = 'taylor' initialisation refuses
    it by the file's why (BN_FLOW_WHY_taylor: the Python internal's film_flow_why)."""
    from bearing_fmu.fmu.native.several import several_model

    both = several_model("taylor,reynolds", None, surrogate=surrogate_file)
    assert "#define BN_FLOWS_TAYLOR 0" in both.config_h and "#define BN_FLOWS_REYNOLDS 1" in both.config_h
    why = next(line for line in both.config_h.splitlines() if line.startswith("#define BN_FLOW_WHY_taylor "))
    assert f"the surrogate file {surrogate_file} has no film fit (format version 1" in why


def test_the_film_fit_is_compiled_in_exactly(tmp_path):
    """A version 2 file (test_taylor_flows.py's made-up film fit): the header holds the fit's
    coefficients as exact decimal literals (J_s's row then J_i's), the film report compiled
    (BN_FLOWS_TAYLOR 1), the oil law of the bearing given kept (the thermal model's)."""
    import dataclasses
    import re

    from test_taylor_flows import made_up

    from bearing_fmu.fmu.native.codegen import native_model

    sur, path = made_up(tmp_path)
    params = dataclasses.replace(sur.params, oil=BearingParams.from_toml(VG46).oil)
    model = native_model("taylor", params, surrogate=path)
    body = re.search(r"TAY_FILM_COEF\[(\d+)\] = \{(.*?)\};", model.data_h, re.DOTALL)
    values = np.array([float(v) for v in body.group(2).split(",")])
    assert int(body.group(1)) == sur.film.coef.size and np.array_equal(values, sur.film.coef.ravel())
    assert "#define BN_FLOWS_TAYLOR 1" in model.config_h and "#define BN_FILM_FLOW 1" in model.config_h
    assert model.params.oil is not None and "der(T_eff)" in {v.name for v in model.variables}


def test_every_native_internal_with_the_film_flows_has_its_report_in_c():
    """The scene checks only the registry capability (rotor_host/scenes/scene.py check_supply): every
    native internal with the film's flows has its film report in C (a data file without them is
    refused by the FMU at initialisation, by name)."""
    from bearing_fmu.fmu.native.catalogue import NATIVE
    from bearing_fmu.internals import registry

    assert all(NATIVE[name].film_report for name in registry.having(film_flow=True, native=True))


@pytest.mark.slow
def test_host_scene_through_the_native_taylor_fmu(taylor_film_file, tmp_path):
    """The shipped 44 Hz VG 46 scene (oil at 40 C), 3 ms, on the film-fitted surrogate through the
    native Taylor FMU's thermal ports (refused before: its film report was not in C) equals the run
    through the Python FMU and the in-process run (LaggedThermal on the guarded surrogate) within
    1e-10 of each signal's largest value: not to the bit, as the native Reynolds and map runs are
    (tests/test_thermal_host.py), since the C force of the surrogate rounds differently (its
    monomials summed as dot products, ~5e-16, test_taylor_equals_the_python_fmu) and the host's
    Newton iteration stops within its tolerance of either. Measured: native - Python 4.2e-11 (Fy),
    the same runs without the supply temperature 2.4e-11; native - in-process 2.7e-11; the run at
    the file's isothermal viscosity differs by 1.4e-2 of the largest y."""
    from test_thermal_host import VG46_SCENE
    from thermal_runs import check_native, run_routes

    from rotor_host.scenes.scene import load_scene

    scene = load_scene(VG46_SCENE).with_internal("taylor", options={"taylor": {"surrogate": taylor_film_file}},
                                                 t_end_s=0.003)
    out = run_routes(scene, tmp_path)
    check_native(out, 1e-10, 1e-10)
