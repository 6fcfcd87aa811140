"""Native bearing FMUs inside the integrator's compiled loop (rotor_host.coupling.fmu_kernel).

The reference is the Python driver's conformant iteration (``cosim.FMUBearings`` with the FMU
state saved once per step and restored before every iterate, as for any FMU): the compiled loop
makes the same FMI calls (setReal, doStep, getReal) on the same instances, and the memoryless
FMU has no state for the restore to change, so the orbits, forces and Newton statistics must be
identical to the bit, also when a discard inside the compiled loop hands the step back to
Python, which cuts it. An FMU that is not memoryless (native Taylor, Reynolds) is iterated by
the compiled loop with the same save and restore the Python driver makes (the kernel's
fmi2GetFMUstate at a step's first evaluation, fmi2SetFMUstate before every later one): again
the same numbers to the bit and the same log lines.
"""

import dataclasses
import shutil
from pathlib import Path

import numpy as np
import pytest
from conftest import paper_scene_text

from bearing_fmu.fmu.meta import memoryless_annotation, memoryless_declaration
from rotor_host.integrate import newmark_loop
from rotor_host.integrate.newmark import IntegrationError, Newmark, NewmarkConfig
from rotor_host.model.rotor import Rotor
from rotor_host.scenes import bearings as scene_bearings, run as scene_run
from rotor_host.scenes.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
PAPER_MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
PAPER_SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
DATA = {"map": ("map", "map", PAPER_MAP), "taylor": ("taylor", "surrogate", PAPER_SURROGATE)}


@pytest.fixture(scope="module")
def native_scene(tmp_path_factory, native_build_cache):
    """scene(internal, **overrides): the paper's 22 Hz scene through the scene's own native FMU
    of ``internal`` (map, linear, taylor or reynolds), built once per internal (and kept between
    sessions: ``native_build_cache``)."""
    folder = tmp_path_factory.mktemp("native_loop")
    built = {}

    def scene(internal="map", **overrides):
        path = folder / f"{internal}_{len(list(folder.glob('*.toml')))}.toml"
        table, key, data = DATA.get(internal, (None, None, None))
        tables = {table: {key: str(data)}} if table else {}
        path.write_text(paper_scene_text(internal=internal, via="fmu", fmu_kind="native", **tables, **overrides))
        s = load_scene(path)
        if internal not in built:
            rotor = Rotor.from_toml(s.rotor_path)

            def build(target):
                shutil.copyfile(scene_bearings.scene_fmu(s, folder / "work", rotor.bearings[0]), target)
                return target

            built[internal] = native_build_cache(folder / f"{internal}.fmu", build,
                                                 [data] if data else [], ("native_loop", internal))
        return dataclasses.replace(s, fmu=built[internal])

    return scene


def _run(s, compiled, memoryless=True, t_end=None):
    """The scene's Newmark run through its FMU bearings: (result or IntegrationError, whether the
    compiled loop ran, the bearings' largest eccentricities). memoryless=False: the Python
    driver saves and restores the FMU state around every iterate (the conformant iteration of
    any FMU)."""
    rotor = Rotor.from_toml(s.rotor_path)
    fs = rotor.weight_vector(9.81) + rotor.point_load_vector(s.static_loads)
    loads = scene_run.bearing_loads(rotor, fs)
    with scene_bearings.build_bearings(s, rotor, loads, Path(s.fmu).parent) as b:
        assert b.memoryless or not memoryless
        b.memoryless = memoryless
        q0 = scene_run.initial_state(s, rotor, fs, loads, b)
        integ = Newmark(rotor.M, rotor.K, rotor.C, rotor.G, s.omega, scene_run.external_force(s, rotor, fs), b,
                        NewmarkConfig(alpha=s.alpha, tangent=s.newton_tangent, compiled=compiled))
        plan = integ._compiled_plan() is not None
        rec = [rotor.dof(n, d) for n in (2, 5, 8) for d in ("y", "z")]
        try:
            res = integ.run(q0, np.zeros(rotor.n_dof), 0.0, t_end or s.t_end_s, s.dt_s, record_every=1,
                            record_dofs=rec, progress=lambda t: None, progress_every=7)
        except IntegrationError as exc:
            res = exc
        _run.messages = [list(m) for m in b.messages]  # the FMUs' log lines
        return res, plan, b.max_eccentricity.copy()


def _assert_same(a, b):
    ra = a.result if isinstance(a, IntegrationError) else a
    rb = b.result if isinstance(b, IntegrationError) else b
    for key in ("t", "q", "v", "f_nl", "iterations"):
        np.testing.assert_array_equal(getattr(ra, key), getattr(rb, key), err_msg=key)
    assert (ra.n_evaluations, ra.n_cuts, ra.status) == (rb.n_evaluations, rb.n_cuts, rb.status)
    assert type(a) is type(b) and str(a) == str(b) if isinstance(a, IntegrationError) else True


def test_memoryless_annotation_reads_back_and_a_description_without_it_declares_nothing():
    import xml.etree.ElementTree as ET

    root = ET.Element("fmiModelDescription")
    assert memoryless_declaration(ET.tostring(root)) is None  # a foreign FMU: save and restore
    root.append(memoryless_annotation(["map", "linear"]))
    assert memoryless_declaration(ET.tostring(root)) == ({"map", "linear"}, {"thermal"})


def test_compiled_native_map_equals_the_conformant_python_driver(native_scene):
    s = native_scene("map", t_end=0.002)
    ref, plan_ref, ecc_ref = _run(s, compiled=False, memoryless=False)
    new, plan, ecc = _run(s, compiled=True)
    assert plan and not plan_ref
    _assert_same(new, ref)
    np.testing.assert_array_equal(ecc, ecc_ref)
    assert ref.n_evaluations > 0 and ecc.min() > 0.1


def test_a_discard_in_the_compiled_loop_goes_back_to_python_and_is_cut_the_same(native_scene, monkeypatch):
    # 50 kg at 50 mm at the bearing node drives the journal into the wall within ~20 steps: the
    # FMU discards (eccentricity >= 1), the compiled loop hands the step to Python, which halves
    # it until it gives up, naming the bearing (tests/test_cosim.py, the same through Reynolds)
    s = native_scene("map", t_end=0.01, unbalance_node=2, unbalance_g=50e3)
    ref, _, ecc_ref = _run(s, compiled=False, memoryless=False)
    why = []  # why each compiled chunk stopped early: a refused (discarded) state among them
    run = newmark_loop.ChunkDriver.run
    monkeypatch.setattr(newmark_loop.ChunkDriver, "run",
                        lambda self, k0, k1: (run(self, k0, k1), why.append(int(self.b.cnt[newmark_loop.CNT_WHY])))[0])
    new, plan, ecc = _run(s, compiled=True)
    assert plan and isinstance(ref, IntegrationError) and "eccentricity ratio" in str(ref)
    assert newmark_loop.WHY_REFUSED in why
    _assert_same(new, ref)
    np.testing.assert_array_equal(ecc, ecc_ref)


@pytest.mark.slow
@pytest.mark.parametrize("internal", ["map", "linear"])
def test_compiled_native_scene_equals_the_python_driver(native_scene, internal):
    # longer: 0.1 s of the 22 Hz scene (2.2 turns), chunks of 7 steps; the Python driver both
    # with the save and restore and without (memoryless: the same numbers, fewer FMI calls)
    s = native_scene(internal, t_end=0.1)
    ref, _, ecc_ref = _run(s, compiled=False, memoryless=False)
    lean, _, ecc_lean = _run(s, compiled=False, memoryless=True)
    new, plan, ecc = _run(s, compiled=True)
    assert plan
    _assert_same(lean, ref)
    _assert_same(new, ref)
    np.testing.assert_array_equal(ecc, ecc_ref)
    np.testing.assert_array_equal(ecc_lean, ecc_ref)


@pytest.mark.parametrize("internal", ["taylor", "reynolds"])
def test_compiled_loop_saves_and_restores_an_fmu_that_is_not_memoryless(native_scene, internal):
    # the native Taylor FMU (excursion warnings count from the committed state) and Reynolds FMU
    # (its solver's warm start kept in the FMU, on the C side) are not memoryless; the compiled
    # loop makes the conformant iteration's FMI calls itself: the same numbers and log lines as
    # the Python driver's (Reynolds on a 32 x 4 grid, which the FMU takes as parameters)
    s = native_scene(internal, t_end=0.004, grid=(32, 4) if internal == "reynolds" else None)
    ref, plan_ref, ecc_ref = _run(s, compiled=False, memoryless=False)
    log_ref = _run.messages
    new, plan, ecc = _run(s, compiled=True, memoryless=False)
    assert plan and not plan_ref
    _assert_same(new, ref)
    np.testing.assert_array_equal(ecc, ecc_ref)
    assert _run.messages == log_ref
    assert ref.n_evaluations > 40 and ecc.min() > 0.1


def test_a_discard_in_a_stateful_compiled_loop_goes_back_to_python_at_the_step_start(native_scene, monkeypatch):
    # the map FMU iterated as if it had a state (saved and restored by the compiled kernels): a
    # discard hands the step to Python with each instance back in the state saved at the step's
    # start (its FMU time too), and the run is cut and fails as the Python driver's does
    s = native_scene("map", t_end=0.01, unbalance_node=2, unbalance_g=50e3)
    ref, _, ecc_ref = _run(s, compiled=False, memoryless=False)
    why = []
    run = newmark_loop.ChunkDriver.run
    monkeypatch.setattr(newmark_loop.ChunkDriver, "run",
                        lambda self, k0, k1: (run(self, k0, k1), why.append(int(self.b.cnt[newmark_loop.CNT_WHY])))[0])
    new, plan, ecc = _run(s, compiled=True, memoryless=False)
    assert plan and isinstance(ref, IntegrationError) and newmark_loop.WHY_REFUSED in why
    _assert_same(new, ref)
    np.testing.assert_array_equal(ecc, ecc_ref)


class _FailingDll:
    """The FMU's library with fmi2DoStep answering ``status`` from its ``after``-th call on (the
    calls before go to the FMU): a C function, so the compiled loop calls it too."""

    def __init__(self, dll, status, after):
        import ctypes

        real, self._dll, self.calls = dll.fmi2DoStep, dll, 0

        def do_step(c, t, h, flag):
            self.calls += 1
            return status if self.calls >= after else real(c, t, h, flag)

        self.fmi2DoStep = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double, ctypes.c_double,
                                           ctypes.c_int)(do_step)

    def __getattr__(self, name):
        return getattr(self._dll, name)


@pytest.mark.parametrize("status", [3, 4])
def test_an_error_in_the_compiled_loop_stops_the_run_as_in_python(native_scene, status):
    # fmi2Error / fmi2Fatal from the 40th doStep of bearing 1 on (inside a compiled chunk): the
    # step goes back to Python, whose driver asks again and raises FMUError, as the Python driver
    # does at the same step (not a cut step: tests/test_cosim.py::test_only_a_discard_cuts_the_step)
    from rotor_host.coupling.cosim import FMUError

    s = native_scene("map", t_end=0.003)
    rotor = Rotor.from_toml(s.rotor_path)
    fs = rotor.weight_vector(9.81) + rotor.point_load_vector(s.static_loads)
    loads = scene_run.bearing_loads(rotor, fs)
    messages = []
    for compiled in (False, True):
        with scene_bearings.build_bearings(s, rotor, loads, Path(s.fmu).parent) as b:
            q0 = scene_run.initial_state(s, rotor, fs, loads, b)
            real = b.instances[0].dll
            b.instances[0].dll = _FailingDll(real, status, after=40)
            try:
                integ = Newmark(rotor.M, rotor.K, rotor.C, rotor.G, s.omega, scene_run.external_force(s, rotor, fs),
                                b, NewmarkConfig(compiled=compiled))
                assert (integ._compiled_plan() is not None) == compiled
                with pytest.raises(FMUError, match="bearing 1.*fmi2DoStep returned") as err:
                    integ.run(q0, np.zeros(rotor.n_dof), 0.0, s.t_end_s, s.dt_s, progress=lambda t: None,
                              progress_every=7)
                messages.append(str(err.value))
            finally:
                b.instances[0].dll = real
    assert messages[0] == messages[1]
