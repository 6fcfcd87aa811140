"""The Taylor surrogate's film fit (bearing_fmu/surrogates/film.py, bearing_fmu/fitting/flows.py):
the film's side flow and inflow by the force map's reduction, two fitted functions J_s, J_i of
(eps, beta); the friction in closed form from the surrogate's force (film.full_bore_friction).

Independent reference: the Reynolds solver's own film report (``Reynolds.film_report``, validated
against Raimondi & Boyd in tests/test_film.py) at held-out random states and the Reynolds effective
temperature (``physics.thermal.effective_temperature``) at the static equilibrium. The surrogates
are fitted here to the ISO VG 46 paper bearing (rotor_host/bundled/bearing_paper_vg46.toml) on the solver's
default 128 x 16 grid, order 5 over a disc of 0.3 CR about the equilibrium under 16.7 N and
|v| <= 0.3 omega CR, 500 designed training states (docs/studies/2026-11-26-taylor-flows.md).
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals import registry
from bearing_fmu.internals.cases import OMEGA_22HZ, surrogate_file
from bearing_fmu.internals.taylor.guard import DomainGuard
from bearing_fmu.internals.registry import BearingStateError
from bearing_fmu.internals.taylor import Taylor
from bearing_fmu.physics.solver.film import flow_scale, full_bore_friction
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.surrogates.film import FilmFit, n_features
from bearing_fmu.surrogates.surrogate import load_surrogate, save_surrogate

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
VG46 = MODELS / "bearing_paper_vg46.toml"
T_SUPPLY = 313.15  # 40 C


# ----------------------------------------------------------------------------- made-up film fits (fast)

def made_up(tmp_path, name="film.json"):
    """The contract's order-2 surrogate (made-up force) with a made-up film fit: J_s = 0.2 + 0.1 eps,
    J_i = 0.3 cos(beta) (the file and the evaluation, not the accuracy)."""
    sur = load_surrogate(surrogate_file(tmp_path))
    coef = np.zeros((2, n_features(2, 1)))
    coef[0, 0], coef[0, 3], coef[1, 1] = 0.2, 0.1, 0.3  # features: eps^i (1, cos, sin)
    sur.film = FilmFit(2, 1, coef, (0.0, 0.0), {"note": "made up"})
    return sur, save_surrogate(sur, tmp_path / name)


def test_a_film_fit_round_trips_and_gives_the_reduced_flows(tmp_path):
    sur, path = made_up(tmp_path)
    d = json.loads(path.read_text())
    assert d["version"] == 2 and d["film"]["degree"] == 2
    t = Taylor.from_file(path)
    assert t.film_flow_why == "" and registry.film_flow_of(registry.get("taylor"), t) == ""
    np.testing.assert_array_equal(t.surrogate.film.coef, sur.film.coef)
    P, om = PAPER_BEARING, OMEGA_22HZ
    st = (0.1 * P.CR, -0.45 * P.CR, 0.02 * om * P.CR, -0.01 * om * P.CR)
    rep = t.film_report(*st, om)
    # by hand: eps, a = eps omega - 2 v_t / CR, c = 2 v_r / CR (forcemap.reduced), the map's formulas
    e = math.hypot(st[0], st[1])
    vr, vt = (st[2] * st[0] + st[3] * st[1]) / e, (-st[2] * st[1] + st[3] * st[0]) / e
    eps, a, c = e / P.CR, e / P.CR * om - 2 * vt / P.CR, 2 * vr / P.CR
    r, q0 = math.hypot(a, c), flow_scale(P)
    assert rep.side_flow_m3_s == pytest.approx(r * q0 * (0.2 + 0.1 * eps), rel=1e-12)
    assert rep.inflow_m3_s == pytest.approx(abs(om * q0 * (1 + eps) / 2 - r * q0 * 0.3 * a / r), rel=1e-12)
    tc, tp, power = full_bore_friction(P, *st, om, t.force(*st, om))
    assert (rep.couette_torque_Nm, rep.pressure_torque_Nm, rep.friction_power_W) == (tc, tp, power)


def test_a_version_1_file_loads_without_flows_and_says_how_to_get_them(tmp_path):
    path = surrogate_file(tmp_path)  # the contract's file: no film fit
    assert json.loads(path.read_text())["version"] == 1
    t = Taylor.from_file(path)
    why = registry.film_flow_of(registry.get("taylor"), t)
    assert f"the surrogate file {path} has no film fit (format version 1" in why
    assert "`bearing-fmu fit` or `rotor-host fit`" in why and "benchmarks/add_film.py" in why
    with pytest.raises(ValueError, match="film_report: the surrogate file .* has no film fit"):
        t.film_report(0.0, -0.3 * PAPER_BEARING.CR, 0.0, 0.0, OMEGA_22HZ)
    guard = DomainGuard(t)
    assert registry.film_flow_of(registry.get("taylor"), guard) == why
    _sur, new = made_up(tmp_path)  # the film fit added: the force is the file's, to the bit
    st = (0.1 * PAPER_BEARING.CR, -0.4 * PAPER_BEARING.CR, 1e-3, -2e-3)
    assert Taylor.from_file(new).force(*st, OMEGA_22HZ) == t.force(*st, OMEGA_22HZ)


@pytest.mark.parametrize("damage, expected", [
    (lambda d: d.pop("film"), r"key 'version' is 2: missing key 'film'"),
    (lambda d: d.__setitem__("version", 1), r"key 'version' is 1: key 'film' belongs to version 2 only"),
    (lambda d: d["film"]["coef"]["J_i"].pop(), r"film: coef: key 'J_i' must be a list of 9 numbers"),
    (lambda d: d["film"].__setitem__("harmonics", 99), r"film: degree 2 must be <= 12, harmonics 99 <= 24"),
    (lambda d: d["film"]["coef"]["J_s"].__setitem__(0, "x"), r"film: coef: key 'J_s'"),
])
def test_a_damaged_film_fit_is_refused_by_key(tmp_path, damage, expected):
    _sur, path = made_up(tmp_path)
    d = json.loads(path.read_text())
    damage(d)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(d))
    with pytest.raises(ValueError, match=rf"surrogate file '{bad}': .*{expected}"):
        load_surrogate(bad)


def test_the_guard_does_for_the_film_report_what_it_does_for_the_force(tmp_path):
    # outside the fitted domain: discard refuses, warn gives the surrogate's value (warned), fallback
    # the Reynolds report (beyond the blending band); inside: the surrogate's report
    from bearing_fmu.physics.solver.reynolds import Reynolds

    sur, _path = made_up(tmp_path)
    P, om = PAPER_BEARING, OMEGA_22HZ
    inside = (0.1 * P.CR, -0.4 * P.CR, 0.0, 0.0)
    outside = (0.1 * P.CR, -0.4 * P.CR, 0.33 * om * P.CR, 0.0)  # |v| 10 % beyond v_max 0.3
    rey = Reynolds(P, n_theta=32, n_x=4)
    guards = {a: DomainGuard(Taylor(sur), a, truth=lambda: rey, on_warn=lambda m: None)
              for a in ("warn", "fallback", "discard")}
    t = Taylor(sur)
    for g in guards.values():
        assert g.film_report(*inside, om) == t.film_report(*inside, om)
    with pytest.raises(BearingStateError, match="beyond the surrogate's fitted domain"):
        guards["discard"].film_report(*outside, om)
    heard = []
    guards["warn"]._on_warn = heard.append
    assert guards["warn"].film_report(*outside, om) == t.film_report(*outside, om) and len(heard) == 1
    assert guards["fallback"].film_report(*outside, om) == rey.film_report(*outside, om)
    far = (0.1 * P.CR, -0.4 * P.CR, 0.6 * om * P.CR, 0.0)  # beyond domain_limit 0.5: always refused
    with pytest.raises(BearingStateError, match="more than domain_limit"):
        guards["fallback"].film_report(*far, om)


# ----------------------------------------------------------------------------- fitted to Reynolds (slow)

@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """{speed_hz: surrogate file} of the VG 46 paper bearing, fitted on first use."""
    from bearing_fmu.fitting import FitRecipe, fit_condition

    folder, out = tmp_path_factory.mktemp("taylor_flows"), {}
    params = BearingParams.from_toml(VG46)

    def get(hz: float) -> Path:
        if hz not in out:
            res = fit_condition(FitRecipe(load_y=0.0, load_z=-16.7, speed_hz=hz, order=5, ecc_max=0.8, v_max=0.3,
                                          radius=0.3, n_train=500, n_test=200, prune=False),
                                params=params, bias_variance=False)
            assert set(res.report["film"]) >= {"test_rel_median", "test_rel_p95", "test_rel_max"}
            out[hz] = save_surrogate(res.surrogate, folder / f"vg46_{hz:g}hz.json")
        return out[hz]

    return get


def held_out_errors_vs_reynolds(params: BearingParams, guard, n: int, seed: int = 2026) -> np.ndarray:
    """(n, 3): |Taylor / Reynolds - 1| of the inflow, side flow and friction power at n random states
    inside the fitted domain (uniform over the training discs, kept where the guard says inside)."""
    from bearing_fmu.physics.solver.reynolds import Reynolds

    s, om, rey, P = guard.taylor.surrogate, guard.omega, Reynolds(params), params
    rng = np.random.default_rng(seed)
    err = []
    while len(err) < n:
        r, a, rv, b = 0.3 * math.sqrt(rng.uniform()), rng.uniform(0, 2 * math.pi), 0.3 * math.sqrt(
            rng.uniform()), rng.uniform(0, 2 * math.pi)
        st = (s.y0 + r * math.cos(a) * P.CR, s.z0 + r * math.sin(a) * P.CR, rv * math.cos(b) * om * P.CR,
              rv * math.sin(b) * om * P.CR)
        if not guard.in_domain(*st):
            continue
        A, B = guard.film_report(*st, om), rey.film_report(*st, om)
        assert set(A.as_dict()) == set(B.as_dict())
        err.append([abs(A.inflow_m3_s / B.inflow_m3_s - 1), abs(A.side_flow_m3_s / B.side_flow_m3_s - 1),
                    abs(A.friction_power_W / B.friction_power_W - 1)])
    return np.array(err)


@pytest.mark.slow
def test_the_film_report_follows_reynolds_at_held_out_states(fitted):
    """200 random states inside the fitted domain at 22 Hz (uniform over the training discs, seed
    2026, kept where the guard says inside), the guarded Taylor surrogate's film report against
    the Reynolds solver's on the same grid. Measured (relative errors):

                   median   p95      max
    inflow         1.1e-3   3.3e-3   5.8e-3
    side flow      2.6e-5   8.4e-5   1.9e-4
    friction power 3.0e-4   1.7e-3   3.9e-3   (closed form from the fitted force: its error)

    Bounds: about twice the measured figures."""
    P = BearingParams.from_toml(VG46)
    e = held_out_errors_vs_reynolds(P, DomainGuard(Taylor.from_file(fitted(22.0)), "discard"), 200)
    bounds = {"median": (2.5e-3, 1e-4, 1e-3), "p95": (7e-3, 2e-4, 4e-3), "max": (1.2e-2, 1e-3, 1e-2)}
    for name, got in (("median", np.median(e, 0)), ("p95", np.percentile(e, 95, 0)), ("max", e.max(0))):
        assert np.all(got < bounds[name]), (name, got)


def check_t_eff(params: BearingParams, fitted, speeds_hz) -> None:
    """T_eff under 16.7 N, oil at T_SUPPLY, of the guarded surrogate file ``fitted(hz)`` against the
    Reynolds solver's at each speed: within 2e-3 K, and the film heats by more than 0.3 K."""
    from bearing_fmu.physics.thermal import effective_temperature

    for hz in speeds_hz:
        om = 2 * math.pi * hz
        g = DomainGuard(Taylor.from_file(fitted(hz)), "discard")
        a = effective_temperature(params, (0.0, -16.7), om, T_SUPPLY, internal=g)
        b = effective_temperature(params, (0.0, -16.7), om, T_SUPPLY)
        assert a.T_eff_K == pytest.approx(b.T_eff_K, abs=2e-3), hz
        assert a.T_eff_K > T_SUPPLY + 0.3  # the film heats


@pytest.mark.slow
def test_t_eff_from_taylor_equals_reynolds_at_three_speeds(fitted):
    """T_eff of the VG 46 paper bearing under 16.7 N, oil at 40 C, at 22, 33 and 44 Hz: the Taylor
    surrogate fitted at each speed (its film report and equilibrium at mu(T) by the exact scaling
    F ~ mu, physics.thermal) against the Reynolds solver's. Measured: T_eff 313.835, 314.139,
    314.440 K; Taylor - Reynolds -5.7e-5, -3.9e-4, -5.8e-4 K. Bound 2e-3 K: twice the root's
    tolerance (1e-3 K); the film fit's share is smaller (at the equilibrium P and Q agree to
    about 1e-3, which moves the 0.7-1.3 K of T_eff - T_supply by about 1e-3 K)."""
    check_t_eff(BearingParams.from_toml(VG46), fitted, (22.0, 33.0, 44.0))


@pytest.mark.slow
def test_demo_json_reports_the_flows_of_the_taylor_internal(fitted, capsys):
    """``bearing-fmu demo --json --internal taylor --surrogate FILE``: the record's friction, flows,
    T_eff and mu_eff from the surrogate, against the Reynolds record within the bounds above."""
    from bearing_fmu.cli import main

    common = ["demo", "--json", "--bearing", str(VG46), "--speed-hz", "22", "--supply-c", "40"]
    assert main(common + ["--internal", "taylor", "--surrogate", str(fitted(22.0))]) == 0
    tay = json.loads(capsys.readouterr().out)
    assert main(common) == 0
    rey = json.loads(capsys.readouterr().out)
    assert tay["internal"] == "taylor" and rey["internal"] == "reynolds"
    assert tay["T_eff_K"] == pytest.approx(rey["T_eff_K"], abs=2e-3)
    assert tay["mu_eff_Pa_s"] == pytest.approx(rey["mu_eff_Pa_s"], rel=1e-4)
    for key, rel in (("inflow_m3_s", 1e-2), ("side_flow_m3_s", 1e-3), ("friction_power_W", 1e-2),
                     ("eccentricity", 1e-2)):
        assert tay[key] == pytest.approx(rey[key], rel=rel), key
    # a version 1 file: refused by name, exit code 2
    assert main(["demo", "--internal", "taylor", "--surrogate", str(surrogate_file(Path(fitted(22.0)).parent))]) == 2
    assert "has no film fit" in capsys.readouterr().err


@pytest.mark.slow
def test_a_scene_with_a_supply_temperature_runs_on_taylor(fitted, tmp_path):
    """The shipped 44 Hz VG 46 scene (oil at 40 C), 5 ms, on the 44 Hz surrogate: in-process
    (LaggedThermal on its film report) and through the Python FMU's thermal ports the same to
    round-off (measured 2e-12 of the force); against the Reynolds run within the surrogate's force
    error (measured 6e-4 of the largest force over 10 ms; bound 2e-3). A version 1 file through the
    FMU's thermal ports is refused at initialisation naming the file."""
    import dataclasses

    from rotor_host.coupling.cosim import FMUError
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(MODELS / "scenes" / "paper_vg46_44hz.toml")
    from thermal_runs import check_three_runs, three_runs

    out = three_runs(scene, "taylor", {"taylor": {"surrogate": str(fitted(44.0))}}, 0.005, tmp_path)
    check_three_runs(out, reynolds_rtol=2e-3)
    d = json.loads(fitted(44.0).read_text())  # the same file as before the film fit: version 1
    d["version"] = 1
    d.pop("film")
    old = tmp_path / "old.json"
    old.write_text(json.dumps(d))
    with pytest.raises(FMUError, match=r"thermal = true needs .* has no film fit \(format version 1"):
        run_scene(dataclasses.replace(scene.with_internal("taylor", options={"taylor": {"surrogate": str(old)}},
                                                          t_end_s=0.001), via="fmu"), tmp_path / "old")

