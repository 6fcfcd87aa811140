"""The native tilting-pad FMU (c/internal_tilting_pad.c) against the Python ``tilting_pad`` internal
it ports, on the bundled five-pad bearing (rotor_host/bundled/bearing_paper_5pad_lbp.toml) at 50 Hz:
agreement and time per call, side by side in one run.

1. Co-Simulation: --steps doSteps of 1e-4 s along a whirling journal (0.4 CR about (0, -0.4 CR),
   the orbit's own velocities), each against ``TiltingPad``'s begin_step / force_and_jacobian /
   accept_step (``stepping.PadStepper``: BDF2); the largest relative difference of the force, of
   K and C, and of the tilts (against CR / a); time per doStep (fmpy's FMU2Slave: setReal, doStep,
   getReal of the 10 outputs and 5 tilts) and per Python step.
2. Model Exchange: fmi2SetContinuousStates + fmi2GetDerivatives at the same journal states and
   tilts, against ``PadAssembly.derivatives``; time per call.

    .venv/bin/python benchmarks/bench_native_pads.py [--steps 200] [--inertia 0] [--pad-map FILE]

(--pad-map: every pad from the pads' map, ``padmap.build_pad_map``, in both.)
"""

from __future__ import annotations

import argparse
import ctypes
import math
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bearing_fmu.fmu.native.build import build_native_fmu  # noqa: E402
from bearing_fmu.internals.tilting_pad.tilting_pad import TiltingPad  # noqa: E402
from bearing_fmu.physics.params import BearingParams  # noqa: E402

OUT = ["Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz"]
TILTS = [f"pad_tilt_{k}" for k in range(1, 6)]
INPUTS = ["y", "z", "vy", "vz", "omega"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--inertia", type=float, default=0.0, help="pad inertia [kg m^2] (0: massless)")
    ap.add_argument("--pad-map", default="", help="the pads' map file (padmap.build_pad_map); default: Reynolds pads")
    a = ap.parse_args()
    import fmpy
    from fmpy.fmi2 import FMU2Model, FMU2Slave

    p = BearingParams.from_toml(ROOT / "rotor_host" / "bundled" / "bearing_paper_5pad_lbp.toml")
    if a.inertia:
        g = p.geometry
        p = replace(p, geometry=replace(g, pads=replace(g.pads, inertia=a.inertia)))
    w, h = 2.0 * math.pi * 50.0, 1e-4
    path = [(0.4 * p.CR * math.cos(w * h * k), -0.4 * p.CR + 0.4 * p.CR * math.sin(w * h * k),
             -0.4 * p.CR * w * math.sin(w * h * k), 0.4 * p.CR * w * math.cos(w * h * k), w) for k in range(a.steps + 1)]
    with tempfile.TemporaryDirectory() as tmp:
        options = {"pad_map": a.pad_map} if a.pad_map else {}
        fmu = build_native_fmu(Path(tmp) / "pads.fmu", "tilting_pad", bearing=p, platforms=["linux64"], speed_hz=50.0,
                               options=options)
        md = fmpy.read_model_description(str(fmu))
        vr = {v.name: v.valueReference for v in md.modelVariables}
        unzip = fmpy.extract(str(fmu))
        s = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName="cs")
        s.instantiate()
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
        ins, outs = [vr[n] for n in INPUTS], [vr[n] for n in OUT + TILTS]
        s.setReal(ins, list(path[0]))
        s.exitInitializationMode()
        tp = TiltingPad(p, pad_map=a.pad_map or None)
        tp.force_and_jacobian(*path[0])
        arm = tp.pads.arm
        native, python, t_native, t_python = [], [], 0.0, 0.0
        for k in range(1, a.steps + 1):
            t0 = time.perf_counter()
            s.setReal(ins, list(path[k]))
            s.doStep(currentCommunicationPoint=(k - 1) * h, communicationStepSize=h)
            native.append(s.getReal(outs))
            t1 = time.perf_counter()
            tp.begin_step(h)
            F, dq, dv = tp.force_and_jacobian(*path[k])
            tp.accept_step()
            python.append(np.concatenate([F, -dq.ravel(), -dv.ravel(), tp.last.delta]))
            t2 = time.perf_counter()
            t_native, t_python = t_native + t1 - t0, t_python + t2 - t1
        s.terminate()
        s.freeInstance()
        nat, py = np.array(native), np.array(python)
        dF = np.max(np.abs(nat[:, :2] - py[:, :2])) / np.max(np.abs(py[:, :2]))
        dK = np.max(np.abs(nat[:, 2:6] - py[:, 2:6])) / np.max(np.abs(py[:, 2:6]))
        dC = np.max(np.abs(nat[:, 6:10] - py[:, 6:10])) / np.max(np.abs(py[:, 6:10]))
        dT = np.max(np.abs(nat[:, 10:] - py[:, 10:])) / (p.CR / arm)
        print(f"Co-Simulation, {a.steps} steps of {h:g} s (pad inertia {a.inertia:g} kg m^2, pads from "
              f"{a.pad_map or 'the Reynolds solver'}): largest relative "
              f"difference force {dF:.2e}, K {dK:.2e}, C {dC:.2e}, tilts {dT:.2e} (of CR / a)")
        print(f"  time per step: native FMU (fmpy setReal, doStep, getReal) {1e6 * t_native / a.steps:.0f} us, "
              f"Python internal {1e6 * t_python / a.steps:.0f} us, ratio {t_python / t_native:.1f}")

        m = FMU2Model(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.modelExchange.modelIdentifier,
                      instanceName="me")
        m.instantiate()
        m.setupExperiment(startTime=0.0)
        m.enterInitializationMode()
        m.setReal(ins, list(path[0]))
        m.exitInitializationMode()
        m.enterContinuousTimeMode()
        nx = md.numberOfContinuousStates
        worst, t_native, t_python = 0.0, 0.0, 0.0
        for k in range(1, a.steps + 1):
            state = np.concatenate([nat[k - 1, 10:], np.zeros(nx - 5)])
            t0 = time.perf_counter()
            m.setReal(ins, list(path[k]))
            m.setContinuousStates((ctypes.c_double * nx)(*state), nx)
            dx = (ctypes.c_double * nx)()
            m.getDerivatives(dx, nx)
            t1 = time.perf_counter()
            _F, want, _sol = tp.pads.derivatives(state, *path[k])
            t2 = time.perf_counter()
            worst = max(worst, float(np.max(np.abs(np.array(dx) - want)) / np.max(np.abs(want))))
            t_native, t_python = t_native + t1 - t0, t_python + t2 - t1
        m.terminate()
        m.freeInstance()
        print(f"Model Exchange, {a.steps} states: largest relative difference of the derivatives {worst:.2e}")
        print(f"  time per call: native FMU (setReal, setContinuousStates, getDerivatives) "
              f"{1e6 * t_native / a.steps:.0f} us, Python PadAssembly.derivatives {1e6 * t_python / a.steps:.0f} us, "
              f"ratio {t_python / t_native:.1f}")


if __name__ == "__main__":
    main()
