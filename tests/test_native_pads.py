"""The native tilting-pad FMU (c/internal_tilting_pad.c over the C Reynolds solver) against the Python
``tilting_pad`` internal, which it ports (each pad the partial-arc solver in its frame, the same
Newton iterations): the force, tangent and tilts of the massless pads in equilibrium
(Initialization Mode), Co-Simulation steps against ``PadStepper`` (BDF2, variable steps), Model
Exchange's state derivatives against ``PadAssembly.derivatives``, massless, with pad inertia and
every pad from the pads' map (``padmap.PadMapSolver``), FMI 2.0 and 3.0; FMU states; refusals; the Compliance Checker. The Python internal is the
reference (its own checks: tests/test_tilting_pad*.py); the C solver equals the Python one to
round-off (tests/test_native_reynolds.py), so agreement to ~1e-12 relative is expected."""

from __future__ import annotations

import ctypes
import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

from bearing_fmu.internals import registry
from bearing_fmu.internals.tilting_pad.tilting_pad import TiltingPad
from bearing_fmu.physics.params import BearingParams
from tests.conftest import compliance_checker

ROOT = Path(__file__).resolve().parents[1]
BEARING = ROOT / "rotor_host" / "bundled" / "bearing_paper_5pad_lbp.toml"
INERTIA = 1e-3  # [kg m^2]: a pad whose own motion an explicit integrator at 1e-4 s still follows
OMEGA = 2.0 * math.pi * 50.0
REL = 1e-11  # relative agreement expected (the same arithmetic, summed in another order)
INPUTS = ("y", "z", "vy", "vz", "omega")
DISCARD, ERROR = 2, 3  # FMI statuses


def params(inertia: float = 0.0) -> BearingParams:
    p = BearingParams.from_toml(BEARING)
    if inertia:
        g = p.geometry
        p = replace(p, geometry=replace(g, pads=replace(g.pads, inertia=inertia)))
    return p


class Builds:
    """(massless | inertia | map, FMI version) -> (fmu, extracted folder), each built when first asked
    (the quick tests build the massless ones only); ``pad_map``: the small pads' map the map FMUs
    hold (6.7 s on a busy machine; the map's own accuracy: tests/test_pad_map.py)."""

    def __init__(self, folder: Path, cached):
        self.folder, self.cached, self.done, self._map = folder, cached, {}, None

    @property
    def pad_map(self) -> Path:
        if self._map is None:
            from bearing_fmu.internals.map.groovemap import save_grooved_map
            from bearing_fmu.internals.tilting_pad.padmap import build_pad_map

            self._map = save_grooved_map(build_pad_map(params(), n_theta=24, n_x=4, n_eps=12, n_phi=10, n_beta=10),
                                         self.folder / "pads_map.json")
        return self._map

    def __getitem__(self, key):
        if key == "pad_map":
            return self.pad_map
        if key not in self.done:
            from bearing_fmu.fmu.native.build import build_native_fmu

            kind, version = key
            options = {"pad_map": str(self.pad_map)} if kind == "map" else {}
            inertia = INERTIA if kind == "inertia" else 0.0

            def build(t):
                return build_native_fmu(t, "tilting_pad", bearing=params(inertia), platforms=["linux64"],
                                        fmi_version=version, speed_hz=50.0, options=options)
            inputs = [BEARING] + ([self.pad_map] if options else [])
            fmu = self.cached(self.folder / f"{kind}{version}.fmu", build, inputs, ("pads", kind, version))
            self.done[key] = (fmu, Path(fmpy.extract(str(fmu))))
        return self.done[key]


@pytest.fixture(scope="module")
def built(tmp_path_factory, native_build_cache):
    return Builds(tmp_path_factory.mktemp("pads"), native_build_cache)


def python_internal(built, kind: str) -> TiltingPad:
    """The Python internal the FMU of ``kind`` ports (massless, with inertia, every pad from the map)."""
    p = params(INERTIA if kind == "inertia" else 0.0)
    return TiltingPad(p, pad_map=str(built["pad_map"]) if kind == "map" else None)


class Driver:
    """One instance of a built FMU (FMI 2 or 3, ME or CS) through fmpy's low-level classes."""

    def __init__(self, fmu, unzip, version: int, kind: str):
        md = fmpy.read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.nx = md.numberOfContinuousStates
        self.version, self.kind = version, kind
        ident = (md.coSimulation if kind == "CS" else md.modelExchange).modelIdentifier
        cls = {(2, "CS"): FMU2Slave, (2, "ME"): FMU2Model, (3, "CS"): FMU3Slave, (3, "ME"): FMU3Model}[version, kind]
        token = md.guid if version == 2 else md.instantiationToken
        self.f = cls(guid=token, unzipDirectory=str(unzip), modelIdentifier=ident, instanceName="pads")
        self.f.instantiate()
        if version == 2:
            self.f.setupExperiment(startTime=0.0)
        self.f.enterInitializationMode()

    def set(self, x) -> None:
        vrs = [self.vr[n] for n in INPUTS]
        (self.f.setReal if self.version == 2 else self.f.setFloat64)(vrs, list(map(float, x)))

    def get(self, names) -> np.ndarray:
        vrs = [self.vr[n] for n in names]
        return np.array((self.f.getReal if self.version == 2 else self.f.getFloat64)(vrs))

    def exit(self) -> None:
        self.f.exitInitializationMode()
        if self.kind == "ME":
            self.f.enterContinuousTimeMode()

    def step(self, t, h) -> int:
        """doStep's status (0 OK, 2 Discard, 3 Error)."""
        try:
            self.f.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        except FMICallException as exc:
            return exc.status
        return 0

    def states(self) -> np.ndarray:
        x = (ctypes.c_double * self.nx)()
        self.f.getContinuousStates(x, self.nx)
        return np.array(x)

    def set_states(self, x) -> None:
        self.f.setContinuousStates((ctypes.c_double * self.nx)(*x), self.nx)

    def derivatives(self) -> np.ndarray:
        dx = (ctypes.c_double * self.nx)()
        (self.f.getDerivatives if self.version == 2 else self.f.getContinuousStateDerivatives)(dx, self.nx)
        return np.array(dx)

    def close(self) -> None:
        self.f.terminate()
        self.f.freeInstance()


def tilts(n=5):
    return [f"pad_tilt_{k}" for k in range(1, n + 1)]


OUT = ["Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz"]


def reference(F, dq, dv):
    """The FMU's outputs Fy .. Czz of a (F, dF/dq, dF/dv) (Lund's signs: K = -dF/dq)."""
    return np.concatenate([F, -dq.ravel(), -dv.ravel()])


def close(got, want, scale):
    """Relative agreement of arrays whose natural scale is ``scale``."""
    return float(np.max(np.abs(np.asarray(got) - np.asarray(want)))) / scale


# the quick loop builds and checks the massless pads; pad inertia and the pads' map are slow tests
KINDS = ["massless", pytest.param("inertia", marks=pytest.mark.slow), pytest.param("map", marks=pytest.mark.slow)]
STATE = (0.1, -0.5, 0.01, -0.02)  # y, z [CR], vy, vz [CR omega]


def journal(p, y, z, vy, vz):
    return (y * p.CR, z * p.CR, vy * p.CR * OMEGA, vz * p.CR * OMEGA, OMEGA)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("version", [2, 3])
def test_cosimulation_equals_the_python_internal_and_its_steps(built, kind, version):
    """Initialization Mode: the massless pads in equilibrium (PadAssembly.equilibrate) and the
    quasi-static tangent; then doSteps of 1e-4 s and a changed step of 2e-4 s along a moving journal,
    each against TiltingPad's begin_step / force_and_jacobian / accept_step (stepping.PadStepper:
    backward Euler, then BDF2 with variable steps), force, K, C and the tilts; every pad from the
    Reynolds solver, or from the pads' map (PadMapSolver)."""
    p = params(INERTIA if kind == "inertia" else 0.0)
    d = Driver(*built[kind, version], version, "CS")
    tp = python_internal(built, kind)
    try:
        x = journal(p, *STATE)
        d.set(x)
        d.exit()
        F, dq, dv = tp.force_and_jacobian(*x)
        scale = float(np.max(np.abs(reference(F, dq, dv)[2:])))
        assert close(d.get(OUT)[:2], F, abs(F).max()) < REL
        assert close(d.get(OUT)[2:], reference(F, dq, dv)[2:], scale) < REL
        assert close(d.get(tilts()), tp.last.delta, p.CR / tp.pads.arm) < REL
        t = 0.0
        for k, h in enumerate((1e-4, 1e-4, 1e-4, 2e-4, 2e-4, 1e-4)):
            x = journal(p, STATE[0] + 0.03 * (k + 1), STATE[1] - 0.02 * (k + 1), 0.05, -0.03)
            d.set(x)
            assert d.step(t, h) == 0
            t += h
            tp.begin_step(h)
            F, dq, dv = tp.force_and_jacobian(*x)
            tp.accept_step()
            got = d.get(OUT)
            assert close(got[:2], F, abs(F).max()) < REL, (k, got[:2], F)
            want = reference(F, dq, dv)[2:]
            assert close(got[2:], want, max(scale, float(np.max(np.abs(want))))) < REL, k
            assert close(d.get(tilts()), tp.last.delta, p.CR / tp.pads.arm) < REL, k
    finally:
        d.close()


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("version", [2, 3])
def test_model_exchange_states_and_derivatives_equal_the_python_equations(built, kind, version):
    """Model Exchange: the states start at the pads' equilibrium; at other tilts (and rates) the
    derivatives are PadAssembly.derivatives' (massless: the rate whose squeeze balances the moment;
    with inertia: the rates and M / I), the force at them too."""
    inertia = INERTIA if kind == "inertia" else 0.0
    p = params(inertia)
    d = Driver(*built[kind, version], version, "ME")
    tp = python_internal(built, kind)
    try:
        x = journal(p, *STATE)
        d.set(x)
        d.exit()
        assert d.nx == (10 if inertia else 5)
        eq = tp.pads.equilibrate(*x)
        x0 = d.states()
        assert close(x0[:5], eq.delta, p.CR / tp.pads.arm) < REL
        if inertia:
            assert np.all(x0[5:] == 0.0)
        state = x0.copy()
        state[:5] += 1e-4 * np.array([1.0, -2.0, 0.5, 1.0, -1.0])
        if inertia:
            state[5:] = 0.3 * np.array([1.0, -1.0, 2.0, 0.5, -0.2])
        d.set_states(state)
        F, want, _sol = tp.pads.derivatives(state, *x)
        got = d.derivatives()
        assert close(got, want, float(np.max(np.abs(want)))) < REL
        assert close(d.get(["Fy", "Fz"]), F, abs(F).max()) < REL
        assert close(d.get(tilts()), state[:5], 1e-3) < 1e-15  # the tilt outputs are the states
    finally:
        d.close()


def test_model_exchange_tangent_is_the_total_derivative_with_the_rates_following(built):
    """Massless pads in Model Exchange: the rate solves M(delta, rate) = 0 at each journal state,
    so K and C are the force's total derivatives with the rates following: against central
    differences of the force over the journal position and velocity (steps 1e-6 CR, 1e-6 CR omega)."""
    p = params()
    d = Driver(*built["massless", 2], 2, "ME")
    try:
        x = np.array(journal(p, *STATE))
        d.set(x)
        d.exit()
        K = d.get(OUT)[2:]  # at the states' start, the equilibrium: Model Exchange's tangent already
        num = []
        for i, h in ((0, 1e-6 * p.CR), (1, 1e-6 * p.CR), (2, 1e-6 * p.CR * OMEGA), (3, 1e-6 * p.CR * OMEGA)):
            up, down = x.copy(), x.copy()
            up[i] += h
            down[i] -= h
            d.set(up)
            Fu = d.get(["Fy", "Fz"])
            d.set(down)
            Fd = d.get(["Fy", "Fz"])
            num.append(-(Fu - Fd) / (2 * h))
        num = np.array(num).T  # rows Fy, Fz; columns y, z, vy, vz
        want = np.concatenate([num[:, :2].ravel(), num[:, 2:].ravel()])
        assert close(K[:4], want[:4], float(np.max(np.abs(want[:4])))) < 1e-6
        assert close(K[4:], want[4:], float(np.max(np.abs(want[4:])))) < 1e-6
    finally:
        d.close()


def test_cosimulation_directional_derivatives_are_the_steps(built):
    """After a doStep, fmi2GetDirectionalDerivative of Fy, Fz along y, z, vy, vz is the step's own
    tangent (the step taken again from its start), the K and C outputs to the bit; also after the
    FMU state is restored."""
    p = params()
    d = Driver(*built["massless", 2], 2, "CS")
    try:
        d.set(journal(p, *STATE))
        d.exit()
        for k in range(3):
            d.set(journal(p, STATE[0] + 0.03 * (k + 1), STATE[1], 0.05, -0.02))
            assert d.step(1e-4 * k, 1e-4) == 0
        K = d.get(OUT)[2:]
        for j, name in enumerate(INPUTS[:4]):
            dd = d.f.getDirectionalDerivative([d.vr["Fy"], d.vr["Fz"]], [d.vr[name]], [1.0])
            want = -K[[j, 2 + j]] if j < 2 else -K[[4 + j - 2, 6 + j - 2]]
            assert np.array_equal(np.array(dd), want), name
    finally:
        d.close()


@pytest.mark.parametrize("version", [2, 3])
def test_an_fmu_state_restores_the_pads_history(built, version):
    """The pads' committed state and BDF2's history are part of the FMU state: a step redone from a
    restored (and a serialised and deserialised) state gives the same bits."""
    p = params()
    d = Driver(*built["massless", version], version, "CS")
    f = d.f
    try:
        d.set(journal(p, *STATE))
        d.exit()
        for k in range(2):
            d.set(journal(p, STATE[0] + 0.03 * (k + 1), STATE[1], 0.05, 0.0))
            assert d.step(1e-4 * k, 1e-4) == 0
        get, put = (f.getFMUstate, f.setFMUstate) if version == 2 else (f.getFMUState, f.setFMUState)
        ser, deser = ((f.serializeFMUstate, f.deSerializeFMUstate) if version == 2 else
                      (f.serializeFMUState, f.deserializeFMUState))
        saved = get()
        blob = ser(saved)
        x = journal(p, STATE[0] + 0.1, STATE[1] - 0.05, 0.05, -0.02)
        d.set(x)
        assert d.step(2e-4, 1e-4) == 0
        first = d.get(OUT + tilts())
        put(saved)
        d.set(x)
        assert d.step(2e-4, 1e-4) == 0
        assert np.array_equal(d.get(OUT + tilts()), first)
        put(deser(blob))
        d.set(x)
        assert d.step(2e-4, 1e-4) == 0
        assert np.array_equal(d.get(OUT + tilts()), first)
    finally:
        d.close()


@pytest.mark.parametrize("version", [2, 3])
def test_a_journal_beyond_a_pads_wall_is_discarded_then_an_error_if_retried(built, version):
    """A journal that closes a pad's film: doStep Discard (the instance as before: a step with
    other inputs goes on), the same inputs again Error; Model Exchange: the derivatives Discard."""
    p = params()
    d = Driver(*built["massless", version], version, "CS")
    try:
        d.set(journal(p, *STATE))
        d.exit()
        before = d.get(tilts())
        d.set(journal(p, 0.0, -3.0, 0.0, 0.0))
        assert d.step(0.0, 1e-4) == DISCARD
        assert np.array_equal(d.get(tilts()), before)
        assert d.step(0.0, 1e-4) == ERROR
        d.set(journal(p, *STATE))
        assert d.step(0.0, 1e-4) == 0
    finally:
        d.close()
    d = Driver(*built["massless", version], version, "ME")
    try:
        d.set(journal(p, *STATE))
        d.exit()
        d.set(journal(p, 0.0, -3.0, 0.0, 0.0))
        with pytest.raises(FMICallException) as exc:
            d.derivatives()
        assert exc.value.status == DISCARD
    finally:
        d.close()


def _orbit(path: Path, cr: float, size: float) -> Path:
    """The checker's input: the journal circling ``size`` CR about (0, -``size`` CR) at 50 Hz."""
    rows = ["time,y,z,vy,vz,omega"]
    for k in range(11):
        t, r = 1e-3 * k, size * cr
        rows.append(f"{t!r},{r * math.cos(OMEGA * t)!r},{-r * math.sin(OMEGA * t) - size * cr!r},"
                    f"{-r * OMEGA * math.sin(OMEGA * t)!r},{-r * OMEGA * math.cos(OMEGA * t)!r},{OMEGA!r}")
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("interface", ["me", "cs"])
def test_compliance_checker_reports_nothing(built, kind, interface, tmp_path):
    """The FMU Compliance Checker (FMI 2.0), empty environment, the journal circling (0.3 CR; the small
    map of ``built`` 0.1 CR: its table ends at eps_max of C_pad, which bounds the tilts, and the pad at
    288 deg finds no balance inside it at 0.4 CR): 0 warnings and 0 errors from the FMU and from the
    checker, the tilts among its outputs."""
    fmu, _unzip = built[kind, 2]
    log = tmp_path / "check.log"
    orbit = _orbit(tmp_path / "in.csv", params().CR, 0.1 if kind == "map" else 0.3)
    done = subprocess.run(["env", "-i", str(compliance_checker()), "-h", "1e-4", "-s", "0.01", "-k", interface, "-i",
                           str(orbit), "-o", str(tmp_path / "out.csv"), "-e", str(log), str(fmu)],
                          capture_output=True, text=True, timeout=300)
    text = log.read_text()
    summary = text[text.index("FMU check summary:"):]
    assert done.returncode == 0, summary
    assert "FMU reported:\n\t0 warning(s) and error(s)" in summary, summary
    assert "0 Warning(s)" in summary and "0 Error(s)" in summary, summary
    head = (tmp_path / "out.csv").read_text().splitlines()[0]
    assert '"pad_tilt_1"' in head and '"pad_tilt_5"' in head


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_fmpy_validates_the_model_description(built, version):
    """fmpy's validation (the model structure: the tilts as states, their derivatives)."""
    from fmpy.validation import validate_fmu

    for kind in ("massless", "inertia", "map"):
        assert validate_fmu(str(built[kind, version][0])) == [], (kind, version)


@pytest.mark.parametrize("kind", KINDS[:2])
def test_fmi3_dependencies_of_the_binary_are_the_model_descriptions(built, kind):
    """fmi3GetVariableDependencies (fmi3_modes.c) gives each output's and state derivative's
    dependencies as the model structure lists them (fmi3.output_dependencies, derivative_dependencies):
    the force, K, C and the pads' variables on the journal state and every pad state."""
    fmu, unzip = built[kind, 3]
    md = fmpy.read_model_description(str(fmu))
    by_vr = {v.valueReference: v.name for v in md.modelVariables}
    listed = {u.variable.name: sorted(d.name for d in u.dependencies) for u in md.outputs + md.derivatives}
    states = sorted(v.name for v in md.modelVariables if v.name.startswith(("pad_tilt_", "pad_rate_")))
    assert len(states) == md.numberOfContinuousStates == (10 if kind == "inertia" else 5)
    last = md.derivatives[-1].variable.name  # der(pad_tilt_N), or with inertia der(pad_rate_N)
    assert listed["Fy"] == listed["pad_tilt_3"] == listed[last] == sorted(list(INPUTS) + states)
    d = Driver(fmu, unzip, 3, "ME")
    try:
        for name, deps in listed.items():
            vr = next(v.valueReference for v in md.modelVariables if v.name == name)
            n = ctypes.c_size_t()
            assert d.f.dll.fmi3GetNumberOfVariableDependencies(d.f.component, vr, ctypes.byref(n)) == 0
            ind = (ctypes.c_uint * n.value)()
            assert d.f.dll.fmi3GetVariableDependencies(d.f.component, vr, (ctypes.c_size_t * n.value)(), ind,
                                                        (ctypes.c_size_t * n.value)(), (ctypes.c_int * n.value)(),
                                                        n.value) == 0
            assert sorted(by_vr[r] for r in ind) == deps, name
    finally:
        d.f.freeInstance()


@pytest.mark.slow  # the rotor host's command line in processes of their own
def test_the_rotor_host_runs_a_native_pad_fmu_as_the_direct_pads(tmp_path):
    """rotor-host run --native on the five-pad scene: the FMU declares the pads' step states
    (stepStates in its Memoryless annotation), so the host finds the static equilibrium in
    Initialization Mode, where the native pads answer in moment equilibrium, and then steps them with
    the Python internal's BDF2 rule: the orbit is the direct run's to round-off (measured 3e-13)."""
    scene = str(ROOT / "rotor_host" / "bundled" / "scenes" / "paper_5pad_lbp_44hz.toml")
    runs = {}
    for name, extra in (("native", ["--native", "--via", "fmu"]), ("direct", ["--via", "direct"])):
        done = subprocess.run([sys.executable, "-m", "rotor_host.cli", "run", scene, *extra, "--t-end", "5e-3",
                               "--out", str(tmp_path / name), "--no-plots", "--quiet"],
                              capture_output=True, text=True, cwd=ROOT, timeout=600)
        assert done.returncode == 0, done.stderr
        runs[name] = np.load(next((tmp_path / name).glob("*.npz")))
    for key in ("y", "z", "eccentricity"):
        scale = np.abs(runs["direct"][key]).max()
        assert np.abs(runs["native"][key] - runs["direct"][key]).max() <= 1e-9 * scale, key


@pytest.mark.skipif(not registry.get("tilting_pad").can.film_flow,
                    reason="the Python tilting_pad internal has no film report here (Capabilities.film_flow)")
def test_thermal_model_reports_the_pads_film_as_the_python_internal(tmp_path, native_build_cache):
    """thermal = true on the five pads with an ISO VG 46 oil law (Initialization Mode: T_eff the
    quasi-static root): P_loss, Q_side and the force are the Python internal's film report and force
    at the FMU's mu_eff (TiltingPad.film_report: each pad's report summed), to round-off."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    text = "\n".join(line for line in BEARING.read_text().splitlines() if not line.startswith("mu_Pa_s"))
    oily = tmp_path / "bearing_paper_5pad_oil.toml"
    oily.write_text(text + '\n[oil]\ngrade = "ISO VG 46"\nsupply_C = 40.0\n')
    p = BearingParams.from_toml(oily)
    fmu = native_build_cache(tmp_path / "thermal.fmu", lambda t: build_native_fmu(
        t, "tilting_pad", bearing=p, platforms=["linux64"], speed_hz=50.0), [oily], ("pads", "thermal"))
    d = Driver(fmu, Path(fmpy.extract(str(fmu))), 2, "CS")
    try:
        x = (0.1 * p.CR, -0.5 * p.CR, 0.0, 0.0, OMEGA)
        d.set(x)
        d.f.setBoolean([d.vr["thermal"]], [True])
        d.exit()
        P, Q, T, mu = d.get(["P_loss", "Q_side", "T_eff", "mu_eff"])
        assert T > p.oil.T_supply and 0.0 < mu < p.mu
        hot = TiltingPad(replace(p, mu=mu))
        rep, F = hot.film_report(*x), hot.force(*x)
        assert P == pytest.approx(rep.friction_power_W, rel=1e-12)
        assert Q == pytest.approx(rep.side_flow_m3_s, rel=1e-12)
        assert close(d.get(["Fy", "Fz"]), F, float(np.max(np.abs(F)))) < 1e-12
    finally:
        d.close()


@pytest.mark.slow
def test_the_command_line_builds_the_pads_map_fmu(built, tmp_path):
    """`bearing-fmu build --native --internal tilting_pad --bearing PADS --map MAP`: the command's
    --map goes to the internal's own file option (pad_map, by its file format), so every pad comes
    from the map: the force after Initialization Mode is the Python internal's on the same map
    (to the other map tests' REL), not the Reynolds pads'."""
    from bearing_fmu.cli import main

    out = tmp_path / "cli_pads_map.fmu"
    assert main(["build", "--native", "--internal", "tilting_pad", "--bearing", str(BEARING), "--map",
                 str(built["pad_map"]), "--platforms", "linux64", "--speed-hz", "50", "-o", str(out)]) == 0
    d = Driver(out, Path(fmpy.extract(str(out))), 2, "CS")
    p = params()
    x = journal(p, *STATE)
    try:
        d.set(x)
        d.exit()
        got = d.get(OUT)
    finally:
        d.close()
    want = reference(*python_internal(built, "map").force_and_jacobian(*x))
    reynolds = reference(*python_internal(built, "massless").force_and_jacobian(*x))
    scale = float(np.max(np.abs(want[:2])))
    assert close(got[:2], want[:2], scale) < REL, (got, want)
    assert close(reynolds[:2], want[:2], scale) > 1e-4  # the coarse map is not the Reynolds pads: the check can tell
