"""The Python FMU refuses what FMI refuses (issue 38 item 4; docs/fmu.md, "FMI status").

A doStep from another time than where the last step ended (memoryless internals excepted: they
declare any point allowed), a restored state that is damaged or holds a value out of its range,
fmpy's simulate_fmu retrying a discarded step with the same inputs; start values that agree with
the bearing file and with ``bearing-fmu demo``; the memoryless declaration the host reads. The
non-finite inputs refused at fmi2SetReal: tests/test_fmi_status.py. Every call through fmpy's
raw ctypes function (``tests.test_fmi_status.Raw``), so the exact fmi2Status is seen.
"""

import ctypes
import hashlib
import json
import math
import os
import subprocess
import sys
import textwrap

import pytest
from conftest import restore_state, serialised_state

from tests.test_fmi_status import DISCARD, ERROR, LINEAR, OK, OMEGA, STATE, linear_force, raw  # noqa: F401 (raw)

CR = 90e-6  # the session FMU's default bearing: the paper's
INSIDE = (0.12 * CR, -0.42 * CR, 0.0, 0.0, OMEGA)  # the fixture surrogate's fitted domain (tests/test_fmu.py)


def test_step_from_another_time_is_an_error_unless_the_internal_is_memoryless(raw):
    # the Taylor internal keeps a state (its excursions; out_of_domain is in the FMU state)
    r = raw()
    assert set(r.initialise(internal="taylor").values()) == {OK}
    assert r.step(0.0, 1e-4, INSIDE) == OK
    n = len(r.messages)
    assert r.step(0.0, 1e-4) == ERROR  # the same step again, without restoring the state
    assert [m.split("PyObject_CallMethod ")[-1] for m in r.errors(n)] == [
        "doStep: currentCommunicationPoint = 0.0 s is not where the last step ended (t = 0.0001 s; the start time "
        "before the first step): restore an FMU state to step from another time"]
    assert r.step(3e-4, 1e-4) == ERROR  # a gap
    assert r.step(1e-4 + 1e-17, 1e-4) == OK  # round-off of the master's clock
    saved = ctypes.c_void_p()
    assert r.call("fmi2GetFMUstate", ctypes.byref(saved)) == OK  # at t = 2e-4
    assert r.step(2e-4, 1e-4) == OK
    assert r.call("fmi2SetFMUstate", saved) == OK and r.step(2e-4, 1e-4) == OK  # restored: from its time
    assert r.call("fmi2FreeFMUstate", ctypes.byref(saved)) == OK
    # the linear internal (thermal off) is memoryless: any currentCommunicationPoint
    lin = raw()
    assert set(lin.initialise(**LINEAR).values()) == {OK}
    for t in (0.0, 0.0, 5.0, 1e-4):
        assert lin.step(t, 1e-4, STATE) == OK
    assert lin.get("Fy") == (OK, linear_force(*STATE[:4])[0])


def _blob(payload: list, checksum: str | None = None) -> bytes:
    """A serialised state as the FMU writes it (pyslave/state.py: the JSON and its SHA-256)."""
    return json.dumps(payload + [checksum or hashlib.sha256(json.dumps(payload).encode()).hexdigest()]).encode()


def test_a_restored_state_is_checked_and_a_damaged_one_refused(raw):
    r = raw()
    assert set(r.initialise(**LINEAR).values()) == {OK}
    assert r.step(0.0, 1e-4, STATE) == OK
    good = serialised_state(r)
    *payload, checksum = json.loads(good)
    tag, t, values, own = payload
    assert own == []  # no states of its own (a tilting pad's: tests/test_pad_fmu.py)
    assert tag == "bearing_fmu.fmu.slave/4" and t == 1e-4
    y = values.index(STATE[0])  # the input y among the values
    ecc = len(STATE) + 1 + 2  # inputs (y z vy vz omega T_supply), then Fy, Fz, eccentricity
    assert values[ecc] == pytest.approx(math.hypot(*STATE[:2]) / CR, rel=1e-12)
    damaged = {
        "a flipped bit": good.replace(b"0.0001", b"0.0003", 1),  # the time changed, the checksum not
        "a flipped bit in the checksum": good[:-3] + (b"0" if good[-3:-2] != b"0" else b"1") + good[-2:],
        "not JSON": good[:-5],
        "NaN, checksum right": _blob([tag, t, values[:y] + [math.nan] + values[y + 1:], own]),
        "negative eccentricity, checksum right": _blob([tag, t, values[:ecc] + [-0.5] + values[ecc + 1:], own]),
        "a time of inf": _blob([tag, math.inf, values, own]),
        "another tag": _blob(["something else", t, values, own]),
        "a value short": _blob([tag, t, values[:-1], own]),
    }
    why = {"a flipped bit": "its checksum does not match its contents", "a flipped bit in the checksum":
           "its checksum does not match its contents", "not JSON": "not a serialised bearing_fmu.fmu.slave/4 state",
           "NaN, checksum right": "y = nan is not a finite number",
           "negative eccentricity, checksum right": "eccentricity = -0.5 is out of its range (>= 0)",
           "a time of inf": "its time inf s is not a finite number",
           "another tag": "not a bearing_fmu.fmu.slave/4 state of this FMU",
           "a value short": "not a bearing_fmu.fmu.slave/4 state of this FMU"}
    assert r.step(1e-4, 1e-4, (2 * STATE[0], *STATE[1:])) == OK  # the instance moves on from the saved state
    fy = r.get("Fy")
    for case, blob in damaged.items():
        n = len(r.messages)
        assert restore_state(r, blob) == ERROR, case
        assert any(why[case] in m for m in r.errors(n)), (case, r.messages[n:])
        assert r.get("Fy") == fy  # the instance keeps its state
    assert restore_state(r, good) == OK  # the good one still reads back and restores
    assert r.get("y") == (OK, STATE[0])


_RETRY = textwrap.dedent("""
    import json, math, sys
    import fmpy
    start = json.loads(sys.argv[2])
    try:
        res = fmpy.simulate_fmu(sys.argv[1], start_values=start, stop_time=1e-3, output_interval=1e-4,
                                output=["Fy"])
        print(json.dumps({"rows": len(res)}))
    except Exception as exc:
        print(json.dumps({"raised": type(exc).__name__, "message": str(exc)}))
""")


def test_simulate_fmu_ends_with_an_error_after_a_discard(fmu):
    """fmpy's simulate_fmu (FMI 2) retries a discarded step with the same inputs again (it sets
    them before every doStep): the FMU refuses the unchanged retry, so the run ends at once with
    an error instead of looping forever. The input omega starts at 0, the linear model's speed
    is omega_lin: every step is a refused state."""
    start = {**LINEAR, "linear_from": "coefficients"}
    run = subprocess.run([sys.executable, "-c", _RETRY, str(fmu), json.dumps(start)], capture_output=True, text=True,
                         timeout=120, env=dict(os.environ, PYTHONPATH=""))
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out == {"raised": "FMICallException", "message": "fmi2DoStep failed with status 3 (error)."}, out
    assert "[discard]" in run.stderr and "the inputs are unchanged" in run.stderr, run.stderr


def test_memoryless_declared_for_the_host_as_by_the_native_fmus(fmu):
    """The Python FMU declares the internals whose outputs follow the inputs alone (thermal off)
    in its model description, as the native FMUs do (the host then iterates it without FMU
    states, through its compiled loop); the set is the native catalogue's."""
    import zipfile

    from bearing_fmu.fmu.meta import memoryless_declaration
    from bearing_fmu.fmu.native.catalogue import NATIVE
    from bearing_fmu.fmu.variables import MEMORYLESS

    declared = memoryless_declaration(zipfile.ZipFile(fmu).read("modelDescription.xml"))
    assert declared == ({"map", "linear"}, {"thermal"})
    assert set(MEMORYLESS) == {name for name, n in NATIVE.items() if n.memoryless}


def test_linear_beyond_the_wall_is_flagged_not_discarded(raw):
    """The one internal that answers beyond the clearance circle (docs/fmu.md, "FMI status"): the
    paper's linear orbits cross the bearing wall and a run reports it (its crossed_clearance)
    rather than stopping, so the step is OK with out_of_domain true and the linear formula's
    force; every other internal discards there."""
    r = raw()
    assert set(r.initialise(**LINEAR).values()) == {OK}
    beyond = (0.0, -1.2 * CR, 0.0, 0.0, OMEGA)
    assert r.step(0.0, 1e-4, beyond) == OK
    assert r.get("out_of_domain") == (OK, 1)
    assert r.get("Fz") == (OK, linear_force(*beyond[:4])[1])
    assert r.get("h_min")[1] == pytest.approx(-0.2 * CR, rel=1e-12)


@pytest.mark.slow
def test_start_values_agree_with_each_other_and_with_demo(tmp_path, code_cache):
    """`bearing-fmu build --bearing FILE` with an oil supplied at 50 C: T_supply starts at the
    file's supply temperature (before: 40 C whatever the file said), T_eff (thermal off: T_supply)
    there too, mu_eff and mu at the oil's viscosity there; `bearing-fmu demo --json` of the same
    file gives the same supply temperature, and its viscosity there is the oil's."""
    import fmpy

    from bearing_fmu.cli import main
    from bearing_fmu.physics.params import BearingParams

    f = tmp_path / "hot.toml"
    f.write_text("[bearing]\nD_mm = 31.0\nL_mm = 20.0\nCR_um = 90.0\n\n[oil]\ngrade = \"ISO VG 46\"\nsupply_C = 50.0\n")
    out = tmp_path / "hot.fmu"
    assert main(["build", "--bearing", str(f), "-o", str(out)]) == 0
    starts = {v.name: float(v.start) for v in fmpy.read_model_description(str(out)).modelVariables
              if v.start is not None and v.name in ("T_supply", "mu", "T_eff", "mu_eff")}
    oil = BearingParams.from_toml(f).oil
    assert starts["T_supply"] == 50.0 + 273.15 == oil.T_supply
    assert starts["mu"] == oil.mu(oil.T_supply)
    # the outputs in Initialization Mode, nothing set: thermal off, so at the supply temperature
    res = fmpy.simulate_fmu(str(out), stop_time=1e-4, output_interval=1e-4, output=["T_eff", "mu_eff"],
                            start_values={"internal": "linear", "linear_from": "coefficients", "omega_lin": 0.0})
    assert res["T_eff"][0] == starts["T_supply"] and res["mu_eff"][0] == starts["mu"]
    for name in ("T_eff", "mu_eff"):  # where the model description gives them, they agree too
        assert starts.get(name, res[name][0]) == res[name][0]
    demo = subprocess.run([sys.executable, "-m", "bearing_fmu.cli", "demo", "--json", "--bearing", str(f)],
                          capture_output=True, text=True, timeout=300)
    assert demo.returncode == 0, demo.stderr[-2000:]
    d = json.loads(demo.stdout)
    # demo runs the film at its effective temperature (a few K above the supply): the law there
    assert d["T_supply_K"] == starts["T_supply"] and oil.mu(d["T_supply_K"]) == starts["mu"]
    assert d["T_eff_K"] > d["T_supply_K"] and d["mu_eff_Pa_s"] == pytest.approx(oil.mu(d["T_eff_K"]), rel=1e-9)


def _scene_run(scene, compiled: bool, memoryless: bool = True):
    """The scene's Newmark run through its Python FMU bearings (tests/test_native_loop.py's ``_run``
    for the Python FMU): (result or IntegrationError, whether the compiled loop ran)."""
    from pathlib import Path

    import numpy as np

    from rotor_host.integrate.newmark import IntegrationError, Newmark, NewmarkConfig
    from rotor_host.model.rotor import Rotor
    from rotor_host.scenes import bearings as scene_bearings, run as scene_run

    rotor = Rotor.from_toml(scene.rotor_path)
    fs = rotor.weight_vector(9.81) + rotor.point_load_vector(scene.static_loads)
    loads = scene_run.bearing_loads(rotor, fs)
    with scene_bearings.build_bearings(scene, rotor, loads, Path(scene.fmu).parent) as b:
        assert b.memoryless  # the Python FMU declares the map memoryless
        b.memoryless = memoryless
        q0 = scene_run.initial_state(scene, rotor, fs, loads, b)
        integ = Newmark(rotor.M, rotor.K, rotor.C, rotor.G, scene.omega, scene_run.external_force(scene, rotor, fs),
                        b, NewmarkConfig(alpha=scene.alpha, tangent=scene.newton_tangent, compiled=compiled))
        plan = integ._compiled_plan() is not None
        rec = [rotor.dof(n, d) for n in (2, 5, 8) for d in ("y", "z")]
        try:
            res = integ.run(q0, np.zeros(rotor.n_dof), 0.0, scene.t_end_s, scene.dt_s, record_every=1,
                            record_dofs=rec, progress=lambda t: None, progress_every=7)
        except IntegrationError as exc:
            res = exc
        return res, plan


@pytest.mark.parametrize("unbalance_g", [8.5, 50e3])
def test_python_fmu_in_the_compiled_loop_equals_the_saved_and_restored_iteration(fmu, map_file, tmp_path,
                                                                                    unbalance_g):
    """The Python FMU of a memoryless internal is driven by the host's compiled loop without FMU
    states: the same numbers, bit for bit, as the Python driver's save and restore around every
    iterate (8.5 g: the paper's run; 50 kg at the bearing node drives the journal into the wall,
    a discard in the compiled loop hands the step to Python, which asks the same state again:
    the FMU is restored first, so it discards again instead of refusing the unchanged retry, and
    the step is cut until the run gives up, naming the bearing, as the reference does)."""
    import numpy as np
    from conftest import paper_scene_text

    from rotor_host.integrate.newmark import IntegrationError
    from rotor_host.scenes.scene import load_scene

    path = tmp_path / "s.toml"
    path.write_text(paper_scene_text(internal="map", via="fmu", fmu_kind="python", fmu=str(fmu), t_end=0.004,
                                     map={"map": str(map_file)}, unbalance_g=unbalance_g,
                                     unbalance_node=2 if unbalance_g > 100 else 6))
    scene = load_scene(path)
    ref, plan_ref = _scene_run(scene, compiled=False, memoryless=False)
    new, plan = _scene_run(scene, compiled=True)
    assert plan and not plan_ref
    ra = new.result if isinstance(new, IntegrationError) else new
    rb = ref.result if isinstance(ref, IntegrationError) else ref
    for key in ("t", "q", "v", "f_nl", "iterations"):
        np.testing.assert_array_equal(getattr(ra, key), getattr(rb, key), err_msg=key)
    assert (ra.n_evaluations, ra.n_cuts, ra.status) == (rb.n_evaluations, rb.n_cuts, rb.status)
    assert type(new) is type(ref)
    if isinstance(ref, IntegrationError):
        assert str(new) == str(ref)
    if unbalance_g > 100:
        assert isinstance(ref, IntegrationError) and "eccentricity ratio" in str(ref) and ra.n_cuts > 0
