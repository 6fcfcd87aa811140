"""The native FMU refuses what FMI refuses (issue 38 item 4), FMI 2.0 and 3.0 alike:

* a doStep from a currentCommunicationPoint other than where the last step ended (or the start
  time): fmi2Error naming both times; the memoryless internals (map, linear) with thermal = false
  declare any point allowed (docs/fmu.md, *Memoryless FMUs*) and are checked to take it;
* a non-finite input at fmi2SetReal / fmi3SetFloat64: error naming the input, the value kept;
* a discarded step retried with the same inputs (set again or not): error, so that
  fmpy.simulate_fmu, which sets the same inputs again before each retry, ends (in a subprocess
  with a timeout, so a regression fails instead of hanging the suite);
* a restored FMU state checked: every single-bit flip of a serialised state and a NaN written in
  (with its checksum made right) refused, the instance keeping its state;
* the linear internal beyond the wall: evaluated and flagged, not discarded (docs/fmu.md says why);
* the start values: T_supply at the bearing file's supply temperature, mu_eff at the oil's
  viscosity there, and the FMU at `bearing-fmu demo --json`'s equilibrium agreeing with demo.
A second fmi2FreeInstance is tests/test_fmi_call_order.py's, fmi3FreeInstance's test_native_fmi3.py's.
"""

import ctypes
import json
import math
import struct
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")

from conftest import restore_state, serialised_state  # noqa: E402
from test_native_fmi3 import Raw3  # noqa: E402
from test_native_fmu import Raw  # noqa: E402

from bearing_fmu.physics.params import PAPER_BEARING, BearingParams  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
VG46 = ROOT / "rotor_host" / "bundled" / "bearing_paper_vg46.toml"
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
OMEGA = 2 * math.pi * 22
WALL = (0.0, -1.01 * PAPER_BEARING.CR, 0.0, 0.0, OMEGA)
GOOD = (1e-5, -4e-5, 1e-3, -2e-3, OMEGA)
RETRY_WORDS = "was discarded and the inputs are unchanged"


@pytest.fixture(scope="module")
def built(tmp_path_factory, native_build_cache):
    """name -> (fmu, extracted folder): map (FMI 2 and 3), taylor and linear (FMI 2)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    folder = tmp_path_factory.mktemp("refusals")
    lin = {"linear_from": "map", "map": str(PAPER_MAP)}
    recipes = {"map": (lambda t: build_native_fmu(t, "map", map=PAPER_MAP, platforms=["linux64"]), [PAPER_MAP]),
               "map3": (lambda t: build_native_fmu(t, "map", map=PAPER_MAP, platforms=["linux64"], fmi_version=3),
                        [PAPER_MAP]),
               "taylor": (lambda t: build_native_fmu(t, "taylor", surrogate=SURROGATE, platforms=["linux64"]),
                          [SURROGATE]),
               "taylor3": (lambda t: build_native_fmu(t, "taylor", surrogate=SURROGATE, platforms=["linux64"],
                                                      fmi_version=3), [SURROGATE]),
               "linear": (lambda t: build_native_fmu(t, "linear", options=lin, platforms=["linux64"]), [PAPER_MAP])}
    out = {}
    for name, (build, inputs) in recipes.items():
        fmu = native_build_cache(folder / f"{name}.fmu", build, inputs, ("refusals", name))
        out[name] = (fmu, Path(fmpy.extract(str(fmu))))
    return out


# ----------------------------------------------------------------------------- the step's time

def test_a_step_from_elsewhere_than_the_last_steps_end_is_an_error(built):
    """Taylor (not memoryless: its excursions count from the previous step, a state): a step
    must start where the last one ended; FMI 2.0 and 3.0 word it alike."""
    raw = Raw(*built["taylor"])
    try:
        assert raw.init() == OK
        assert raw.step(0.0, 1e-4) == OK
        assert raw.step(0.0, 1e-4) == ERROR  # the step [0, 1e-4] again, without a restore
        msg = raw.last(ERROR)
        assert "currentCommunicationPoint = 0 s is not where the last step ended (t = 0.0001 s" in msg, msg
        assert raw.step(3e-4, 1e-4) == ERROR and "currentCommunicationPoint = 0.0003 s is not" in raw.last(ERROR)
        assert raw.step(1e-4 + 1e-13, 1e-4) == OK  # round-off is no gap
        assert raw.now() == pytest.approx(2e-4, abs=1e-12)
        state = ctypes.c_void_p()  # a restored state sets the time back: the step from there goes
        assert raw.call("fmi2GetFMUstate", ctypes.byref(state)) == OK
        assert raw.step() == OK
        assert raw.call("fmi2SetFMUstate", state) == OK and raw.step(raw.now()) == OK
        raw.call("fmi2FreeFMUstate", ctypes.byref(state))
    finally:
        raw.close()
    raw = Raw(*built["taylor"])  # before the first step: the start time (setupExperiment's 0)
    try:
        assert raw.init() == OK
        assert raw.step(0.5, 1e-4) == ERROR and "(t = 0 s;" in raw.last(ERROR)
    finally:
        raw.close()
    r3 = Raw3(built["taylor3"])
    try:
        assert r3.init() == OK
        assert r3.step(0.0)[0] == OK
        assert r3.step(0.0)[0] == ERROR
        assert "currentCommunicationPoint = 0 s is not where the last step ended (t = 0.0001 s" in r3.last()
    finally:
        r3.close()


def test_a_memoryless_fmu_steps_from_any_point_unless_thermal(built):
    """The map FMU declares itself memoryless (its outputs follow the inputs alone): a host
    iterates one step with setReal / doStep / getReal from the same point and no state restored
    (rotor_host/coupling/fmu_kernel.py), so any currentCommunicationPoint is taken."""
    raw = Raw(*built["map"])
    try:
        assert raw.init() == OK
        raw.set_inputs(GOOD)
        outs = []
        for t in (0.0, 0.0, 5.0, 1e-4):
            assert raw.step(t, 1e-4) == OK
            outs.append(raw.outputs()[1])
        assert all(np.array_equal(o, outs[0]) for o in outs)  # and the outputs do not depend on it
    finally:
        raw.close()
    from bearing_fmu.fmu.meta import memoryless_declaration

    with zipfile.ZipFile(built["map"][0]) as z:
        assert memoryless_declaration(z.read("modelDescription.xml")) == ({"map"}, {"thermal"})


# ----------------------------------------------------------------------------- inputs

def test_a_non_finite_input_is_refused_when_set_and_the_value_kept(built):
    for bad in (math.nan, math.inf, -math.inf):
        raw = Raw(*built["map"])
        try:
            assert raw.init() == OK and raw.set_inputs(GOOD) == OK
            assert raw.set("z", bad) == ERROR
            words = f"setReal: input z = {bad!r} is not finite; it keeps {'%.17g' % GOOD[1]}"
            assert words in raw.last(ERROR), raw.last(ERROR)
            assert raw.get("z") == (OK, GOOD[1])
            assert raw.step() == OK  # the step runs at the value kept
        finally:
            raw.close()
    r3 = Raw3(built["map3"])
    try:
        assert r3.init() == OK
        assert r3.set(["T_supply"], [math.nan]) == ERROR
        assert "fmi3SetFloat64: input T_supply = nan is not finite; it keeps" in r3.last()
        assert r3.get(["T_supply"])[1][0] == pytest.approx(313.15)
    finally:
        r3.close()


# ----------------------------------------------------------------------------- the retry

_SIMULATE = """
import sys, numpy as np, fmpy
z = float(sys.argv[2])
signal = np.array([(0.0, z), (1.0, z)], dtype=[("time", np.float64), ("z", np.float64)])
try:
    fmpy.simulate_fmu(sys.argv[1], stop_time=0.01, output_interval=1e-3, input=signal)
    print("returned")
except Exception as exc:
    print("raised", exc)
"""


@pytest.mark.parametrize("name", ["map", "map3"])
def test_fmpy_simulate_fmu_ends_after_a_discard_with_its_inputs_set_again(built, name):
    """fmpy's simulate_fmu with an input signal sets z again before each retry of the discarded
    step (FMI 2.0: it stops only at fmi2Terminated); the FMU ends that with an error, and the run
    with fmpy's exception, within seconds (the timeout: a regression fails, it does not hang)."""
    run = subprocess.run([sys.executable, "-c", _SIMULATE, str(built[name][0]), repr(WALL[1])],
                         capture_output=True, text=True, timeout=60)
    assert "raised" in run.stdout, run.stdout + run.stderr[-2000:]
    if name == "map":  # FMI 2.0: the discard, then the retry's error (logging off: the first of each on stderr)
        assert "at or beyond the" in run.stderr and RETRY_WORDS in run.stderr, run.stderr[-2000:]
    else:  # fmpy's FMI 3.0 driver raises at the discard itself
        assert "at or beyond the" in run.stderr, run.stderr[-2000:]


# ----------------------------------------------------------------------------- restored states

def _fnv1a(data: bytes) -> int:
    """FNV-1a, 32 bits (the state's checksum, bearing_state.c)."""
    h = 2166136261
    for b in data:
        h = ((h ^ b) * 16777619) & 0xFFFFFFFF
    return h


def test_a_damaged_state_is_refused_and_the_instance_keeps_its_own(built):
    raw = Raw(*built["taylor"])
    try:
        assert raw.init() == OK  # at the start inputs: the surrogate's equilibrium
        assert raw.step() == OK
        blob = serialised_state(raw)
        assert restore_state(raw, blob) == OK  # intact: taken
        assert raw.step() == OK
        before, t_before = raw.outputs()[1], raw.now()
        n_bits = 8 * len(blob)
        refused = 0
        for bit in range(n_bits):  # every single-bit flip (FNV-1a: a one-byte change always changes the sum)
            flipped = bytearray(blob)
            flipped[bit // 8] ^= 1 << (bit % 8)
            refused += restore_state(raw, bytes(flipped)) == ERROR
        assert refused == n_bits
        assert "checksum does not match" in raw.last(ERROR) or "not a serialised" in raw.last(ERROR)
        # NaN written over Fz (found by its bits), the checksum made right: refused by the range check
        fz = raw.outputs(("Fz",))[1][0]
        _, at_save = raw.outputs()
        blob2 = serialised_state(raw)
        where = blob2.find(struct.pack("<d", fz))
        assert where > 0
        bad = bytearray(blob2)
        bad[where:where + 8] = struct.pack("<d", math.nan)
        bad[-4:] = struct.pack("<I", _fnv1a(bytes(bad[:-4])))  # the checksum is the last field
        assert restore_state(raw, bytes(bad)) == ERROR
        assert "holding Fz = nan (not finite or out of range)" in raw.last(ERROR), raw.last(ERROR)
        assert np.array_equal(raw.outputs()[1], before) and raw.now() == t_before  # kept
        assert raw.step() == OK
    finally:
        raw.close()
    r3 = Raw3(built["taylor3"])  # FMI 3.0: the same check
    try:
        assert r3.init() == OK and r3.step()[0] == OK
        state = ctypes.c_void_p()
        assert r3.call("fmi3GetFMUState", ctypes.byref(state)) == OK
        size = ctypes.c_size_t()
        assert r3.call("fmi3SerializedFMUStateSize", state, ctypes.byref(size)) == OK
        buf = (ctypes.c_uint8 * size.value)()
        assert r3.call("fmi3SerializeFMUState", state, buf, size) == OK
        buf[100] ^= 0x10
        copy = ctypes.c_void_p()
        assert r3.call("fmi3DeserializeFMUState", buf, size, ctypes.byref(copy)) == ERROR
        assert "checksum does not match" in r3.last()
        r3.call("fmi3FreeFMUState", ctypes.byref(state))
    finally:
        r3.close()


# ----------------------------------------------------------------------------- linear beyond the wall

def test_the_linear_fmu_beyond_the_wall_is_flagged_not_discarded(built):
    """The linear model is an expansion about one point: the paper's linear orbits cross the
    wall, and a host reports that crossing (docs/fmu.md): beyond the clearance the FMU returns
    the expansion's force with out_of_domain = true, where the other internals discard."""
    raw = Raw(*built["linear"])
    try:
        assert raw.init() == OK
        omega = raw.get("omega_lin")[1]
        raw.set_inputs((0.0, -1.2 * PAPER_BEARING.CR, 0.0, 0.0, omega))
        assert raw.step() == OK
        assert raw.get("out_of_domain") == (OK, True)
        assert raw.outputs(("eccentricity",))[1][0] == pytest.approx(1.2)
        raw.set_inputs((0.0, -0.2 * PAPER_BEARING.CR, 0.0, 0.0, omega))
        assert raw.step() == OK and raw.get("out_of_domain") == (OK, False)
    finally:
        raw.close()


# ----------------------------------------------------------------------------- start values

@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
def test_start_values_agree_with_the_bearing_file_and_with_demo(tmp_path, native_build_cache):
    """A bearing file supplying its oil at 50 C: T_supply starts at 323.15 K, mu at the oil's
    viscosity there (the file's), and the outputs before a step agree (thermal off: T_eff =
    T_supply, mu_eff = mu). At demo's equilibrium (its journal position, the same speed) with
    thermal = true, the FMU gives demo's film temperature and viscosity and carries demo's load
    (expected values: `bearing-fmu demo --json`, the Python Reynolds solver and heat balance;
    the native solver is the same method in C, to its tolerance)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    toml = tmp_path / "b50.toml"
    toml.write_text(VG46.read_text().replace("supply_C = 40.0", "supply_C = 50.0"))
    params = BearingParams.from_toml(toml)
    assert params.oil.T_supply == pytest.approx(323.15)
    fmu = native_build_cache(tmp_path / "reynolds_b50.fmu", lambda t: build_native_fmu(
        t, "reynolds", bearing=params, platforms=["linux64"]), [toml], ("refusals", "reynolds b50"))
    md = fmpy.read_model_description(str(fmu))
    start = {v.name: v.start for v in md.modelVariables if v.start is not None}
    assert float(start["T_supply"]) == pytest.approx(323.15, abs=1e-12)
    assert float(start["mu"]) == pytest.approx(params.oil.mu(323.15), rel=1e-15)
    demo = subprocess.run([sys.executable, "-m", "bearing_fmu.cli", "demo", "--bearing", str(toml), "--json"],
                          capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert demo.returncode == 0, demo.stderr
    d = json.loads(demo.stdout)
    assert d["T_supply_K"] == pytest.approx(float(start["T_supply"]))
    raw = Raw(fmu, Path(fmpy.extract(str(fmu))))
    try:
        raw.enter()  # thermal off: the outputs before the first step
        assert raw.set_inputs((d["y0_m"], d["z0_m"], 0.0, 0.0, 2 * math.pi * d["speed_hz"])) == OK
        status, (t_eff, mu_eff) = raw.outputs(("T_eff", "mu_eff"))
        assert status == OK and t_eff == float(start["T_supply"]) and mu_eff == float(start["mu"])
        assert raw.set("thermal", True) == OK
        assert raw.call("fmi2ExitInitializationMode") == OK  # thermal on: T_eff quasi-static there
        status, (fy, fz, t_eff, mu_eff) = raw.outputs(("Fy", "Fz", "T_eff", "mu_eff"))
        assert status == OK
        assert t_eff == pytest.approx(d["T_eff_K"], abs=0.02)  # K
        assert mu_eff == pytest.approx(d["mu_eff_Pa_s"], rel=2e-3)
        load = np.array(d["load_N"])
        assert np.allclose([fy, fz], -load, atol=2e-3 * np.abs(load).max()), (fy, fz, load)
    finally:
        raw.close()
