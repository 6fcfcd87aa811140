"""The native Reynolds FMU's thermal ports (docs/thermal.md, docs/fmu.md) against the Python FMU's.

Expected values: the Python FMU (bearing_fmu/fmu/slave.py, its thermal model in Python:
physics/thermal.py film_temperature through fmu/ports.py thermal_state) at the same parameters
(the native FMU's starts: the ISO VG 46 paper bearing of models/bearing_paper_vg46.toml, a
32 x 4 grid) over the same short Co-Simulation run: T_eff, mu_eff, P_loss, Q_side and the force
with its tangent within 1e-12 relative (round-off: the C film report and oil law equal Python's to
about 1e-16, tests/test_native_film.py, tests/test_native_thermal.py). The native FMU's own
contract: T_eff is part of the FMU state (a restored state steps the same), a supply temperature
outside the oil's range refuses the step (Discard), Model Exchange refuses thermal = true.
"""

import math
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import FMU2Model, FMU2Slave  # noqa: E402
from fmpy.fmi3 import FMU3Slave  # noqa: E402

from bearing_fmu.physics.params import BearingParams  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
VG46 = ROOT / "models" / "bearing_paper_vg46.toml"
GRID = {"n_theta": 32, "n_x": 4}
IN = ("y", "z", "vy", "vz", "omega")
OUT = ("Fy", "Fz", "T_eff", "mu_eff", "P_loss", "Q_side", "Kyy", "Kzy", "Cyy", "Czz")
T_SUPPLY = 318.15  # 45 C
RTOL = 1e-12


@pytest.fixture(scope="module")
def native3(tmp_path_factory, native_build_cache):
    """FMI version -> (the native Reynolds FMU of the VG 46 bearing, its model description)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    folder = tmp_path_factory.mktemp("native_thermal")
    params = BearingParams.from_toml(VG46)
    out = {}
    for version in (2, 3):
        def build(target, version=version):
            return build_native_fmu(target, "reynolds", bearing=params, options=GRID, fmi_version=version,
                                    compiler="cc")
        path = native_build_cache(folder / f"reynolds_vg46_fmi{version}.fmu", build, [VG46],
                                  ("thermal", "reynolds", version, tuple(GRID.items())))
        out[version] = (path, fmpy.read_model_description(str(path)))
    return out


def trajectory(n=12):
    """The journal on a widening, speeding spiral: the load and the friction change every step."""
    CR, out = 90e-6, []
    for k in range(n):
        a, e, w = 0.3 * k, 0.5 + 0.02 * k, 300.0 + 20.0 * k
        out.append((e * CR * math.sin(a), -e * CR * math.cos(a), 0.01 * w * CR * math.cos(a),
                    0.01 * w * CR * math.sin(a), w))
    return out


class Run:
    """One Co-Simulation instance through fmpy (FMI 2.0 or 3.0) with the thermal model on."""

    def __init__(self, path, md, reals: dict, strings: dict | None = None, kind="CS", thermal=True):
        self.md, self.v3 = md, md.fmiVersion.startswith("3")
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        unzip = fmpy.extract(str(path))
        if self.v3:
            self.f = FMU3Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                               instanceName="thermal")
        else:
            cls, ident = ((FMU2Slave, md.coSimulation.modelIdentifier) if kind == "CS" else
                          (FMU2Model, md.modelExchange.modelIdentifier))
            self.f = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident, instanceName="thermal")
        self.f.instantiate()
        if self.v3:
            self.f.enterInitializationMode(startTime=0.0)
        else:
            self.f.setupExperiment(startTime=0.0)
            self.f.enterInitializationMode()
        self.f.setBoolean([self.vr["thermal"]], [thermal])
        for k, v in (strings or {}).items():
            self.f.setString([self.vr[k]], [v])
        self.set(reals)
        self.t = 0.0

    def set(self, values: dict):
        ids, vals = [self.vr[k] for k in values], [float(v) for v in values.values()]
        (self.f.setFloat64 if self.v3 else self.f.setReal)(ids, vals)

    def get(self, names=OUT) -> np.ndarray:
        ids = [self.vr[k] for k in names]
        return np.array((self.f.getFloat64 if self.v3 else self.f.getReal)(ids))

    def step(self, state, h):
        self.set(dict(zip(IN, state)))
        self.f.doStep(self.t, h)
        self.t += h

    def close(self):
        self.f.terminate()
        self.f.freeInstance()


def parameters(md) -> dict:
    """The native FMU's bearing and oil parameters (its starts), for the Python FMU too."""
    return {v.name: float(v.start) for v in md.modelVariables
            if v.causality == "parameter" and v.type == "Real" and (v.name in ("D", "L", "CR", "mu")
                                                                   or v.name.startswith("oil_"))}


def run(fmu, md, h=1e-3, python=False, native_md=None):
    states = trajectory()
    reals = {**parameters(native_md or md), "T_supply": T_SUPPLY, **dict(zip(IN, states[0]))}
    strings = {"internal": "reynolds", "oil_law": "walther"} if python else None
    r = Run(fmu, md, reals, strings)
    try:
        if python:
            ints = [r.vr["n_theta"], r.vr["n_x"]]
            r.f.setInteger(ints, [GRID["n_theta"], GRID["n_x"]])
        r.f.exitInitializationMode()
        rows = [r.get()]
        for s in states[1:]:
            r.step(s, h)
            rows.append(r.get())
        return np.array(rows)
    finally:
        r.close()


@pytest.mark.slow
@pytest.mark.parametrize("version", [2, 3])
def test_equals_the_python_fmu(native3, fmu, version):
    path, md = native3[version]
    got = run(path, md)
    want = run(fmu, fmpy.read_model_description(str(fmu)), python=True, native_md=md)
    scale = np.max(np.abs(want), axis=0)  # each output against its largest value over the run
    assert np.max(np.abs(got - want) / scale) <= RTOL
    T = got[:, OUT.index("T_eff")]
    assert np.all(T > T_SUPPLY) and np.ptp(T) > 0.1  # the film runs hot, and its temperature moves


@pytest.mark.slow
def test_fmpy_validates_the_thermal_fmus(native3):
    from fmpy.validation import validate_fmu

    for version, (path, md) in native3.items():
        assert validate_fmu(str(path)) == [], version
        names = {v.name for v in md.modelVariables}
        assert {"thermal", "T_supply", "T_eff", "oil_nu_1", "oil_rise_factor"} <= names and "oil_law" not in names


@pytest.mark.slow
def test_t_eff_is_part_of_the_fmu_state(native3):
    path, md = native3[2]
    states = trajectory()
    r = Run(path, md, {"T_supply": T_SUPPLY, **dict(zip(IN, states[0]))})
    try:
        r.f.exitInitializationMode()
        for s in states[1:5]:
            r.step(s, 1e-3)
        blob = r.f.serializeFMUstate(r.f.getFMUstate())
        before = r.get()
        r.step(states[5], 1e-3)
        after = r.get()
        assert after[OUT.index("T_eff")] != before[OUT.index("T_eff")]
        r.f.setFMUstate(r.f.deSerializeFMUstate(blob))
        r.t -= 1e-3
        assert np.array_equal(r.get(), before)
        r.step(states[5], 1e-3)
        assert np.array_equal(r.get(), after)  # the same lag from the same T_eff
        # a supply temperature outside the oil's range (0 .. 150 C): the step is refused
        r.set({"T_supply": 450.0})
        with pytest.raises(FMICallException, match="discard"):
            r.f.doStep(r.t, 1e-3)
    finally:
        r.close()


@pytest.mark.slow
def test_model_exchange_refuses_thermal(native3):
    path, md = native3[2]
    r = Run(path, md, {"T_supply": T_SUPPLY}, kind="ME")
    try:
        with pytest.raises(FMICallException, match="error"):
            r.f.exitInitializationMode()
    finally:
        r.f.freeInstance()
