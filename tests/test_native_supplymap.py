"""The native map FMU of a fed-groove (4-D) force map (c/internal_map.c supply_arc_force, map_spline.h spline4;
generators/map.py): force and tangent against the Python internal (``supplymap.SupplyForceMap``, the numba
kernel ``supplykernels.map4_force`` it ports) at states over the whole map, the still journal (r = 0, u = 1)
and both sides of the kernel's at-rest switch (1 - u = T_MIN) among them, in Co-Simulation and Model
Exchange (where dF/domega is checked against central differences of the Python force, an independent
derivative); what it refuses by name; its sources under -Werror; the FMU Compliance Checker."""

from __future__ import annotations

import dataclasses
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.map.mapfile import open_map
from bearing_fmu.internals.map.supplymap import save_supply_map, supply_force, tabulate_supplied
from bearing_fmu.internals.map.tables import EPS_MIN, scale
from bearing_fmu.physics.params import BearingParams
from conftest import compliance_checker

fmpy = pytest.importorskip("fmpy")

ROOT = Path(__file__).resolve().parents[1]
BEARING = ROOT / "rotor_host" / "bundled" / "bearing_paper_2groove.toml"
AMBIENT = BearingParams.from_toml(BEARING)
P_S = 100e3  # [Pa]
FED = dataclasses.replace(AMBIENT, geometry=dataclasses.replace(AMBIENT.geometry, supply_pressure=P_S))
W22 = 2 * math.pi * 22


@pytest.fixture(scope="module")
def fed_map(tmp_path_factory, native_build_cache):
    """(the native map FMU, extracted, of a coarse 5 x 4 x 6 x 4 fed-groove map with its flow tables (format 7)
    of the two-groove paper bearing at 100 kPa, built through the command line; the map file; the bearing file)."""
    from bearing_fmu.cli import main

    folder = tmp_path_factory.mktemp("fed_map")
    table = tabulate_supplied(FED, n_eps=5, n_phi=4, n_beta=6, n_sup=4, n_phase=1, n_theta=32, n_x=4)
    table.provenance = {"test": "coarse fed-groove map"}  # the same bytes every run: the build cache's key
    path = save_supply_map(table, folder / "fed.json")
    bearing = folder / "fed.toml"
    bearing.write_text(BEARING.read_text().replace("supply_pressure_kPa = 0.0", f"supply_pressure_kPa = {P_S / 1e3}"))
    argv = ["build", "--native", "--internal", "map", "--map", str(path), "--bearing", str(bearing),
            "--platforms", "linux64"]

    def cli(target):
        assert main([*argv, "-o", str(target)]) == 0
        return target

    fmu = native_build_cache(folder / "map_fed.fmu", cli, [path, bearing], ("cli", *argv[1:]), code=("bearing_fmu.cli",))
    return fmu, Path(fmpy.extract(str(fmu))), path, bearing


def states(n=24, seed=7):
    """Journal states over the map: random ones up to eps 0.95 (speeds 0-22 Hz, velocities 0.3 omega CR: u
    from ~0.05 to 1), the still journal (r = 0) off and at the centre, eps below EPS_MIN, and a journal so
    slow that 1 - u is just below and just above the kernel's T_MIN (the at-rest first harmonic, the general
    derivatives)."""
    rng = np.random.default_rng(seed)
    CR, out = FED.CR, []
    for _ in range(n):
        e, a, w = rng.uniform(0, 0.95), rng.uniform(-math.pi, math.pi), rng.uniform(0.0, 1.0) * W22
        v = rng.normal(0, 0.3, 2) * max(w, 1.0) * CR
        out.append((e * CR * math.cos(a), e * CR * math.sin(a), v[0], v[1], w))
    t_per_omega = scale(FED) * 0.5 / supply_force(FED)  # 1 - u per rad/s of omega at eps 0.5, no velocity
    out += [(0.3 * CR, -0.2 * CR, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0, W22),
            (0.3 * EPS_MIN * CR, 0.0, 0.0, 0.1 * CR, W22), (-0.7 * EPS_MIN * CR, 0.2 * EPS_MIN * CR, 0.0, 0.0, 0.0),
            *((0.5 * CR * math.cos(1.0), 0.5 * CR * math.sin(1.0), 0.0, 0.0, f * 1e-8 / t_per_omega)
              for f in (0.5, 2.0))]
    return out


def python_internal(fmu, path):
    """The Python map internal for the FMU's own bearing parameters (its starts)."""
    md = fmpy.read_model_description(str(fmu))
    p = {v.name: float(v.start) for v in md.modelVariables if v.name in ("D", "L", "CR", "mu")}
    return open_map(path, dataclasses.replace(FED, **p))


def test_the_native_fed_map_is_the_python_internal(fed_map):
    """Co-Simulation: every output (Fy, Fz, K, C) the Python internal's to 1e-12 of each block's largest entry
    (the kernel's arithmetic in its order: in practice the same bits); beyond eps_max the step is discarded
    naming the map's range. A still journal is not warned about as an unconnected omega (the generic check
    for a zero force at rest): the supply carries load there."""
    from test_native_fmu import DISCARD, OK, Raw, assert_close, python_outputs

    fmu, unzip, path, _ = fed_map
    py = python_internal(fmu, path)
    raw = Raw(fmu, unzip)
    try:
        assert raw.init() == OK, raw.messages
        for st in states():
            assert raw.set_inputs(st) == OK
            assert raw.step() == OK, raw.last()
            status, got = raw.outputs()
            want = python_outputs(py, st)
            assert status == OK and np.all(np.isfinite(got)) and np.max(np.abs(want[:2])) > 0.0
            assert_close(got, want, f"fed map at {st}")
        assert raw.set_inputs((0.0, -0.995 * FED.CR, 0.0, 0.0, W22)) == OK
        assert raw.step() == DISCARD and "beyond the force map's last point" in raw.last()
    finally:
        raw.close()


def test_the_fmi3_fmu_is_the_python_internal_too(fed_map, native_build_cache):
    """FMI 3.0 Co-Simulation (``--fmi 3``): every output the Python internal's, as the FMI 2.0 FMU's."""
    from test_native_fmi3 import Raw3
    from test_native_fmu import IN, OK, OUT, assert_close, python_outputs

    from bearing_fmu.fmu.native.build import build_native_fmu

    fmu2, _, path, bearing = fed_map
    params = BearingParams.from_toml(bearing)
    fmu = native_build_cache(fmu2.with_name("map_fed3.fmu"), lambda target: build_native_fmu(
        target, "map", map=path, bearing=params, fmi_version=3, compiler="cc"), [path, bearing], ("fed map", "fmi 3"))
    py = python_internal(fmu, path)
    raw = Raw3((fmu, fmpy.extract(str(fmu))))
    try:
        assert raw.init() == OK
        for st in states(8, seed=11)[-10:]:
            assert raw.set(IN, st) == OK
            assert raw.step()[0] == OK, raw.last()
            status, got = raw.get(OUT)
            assert status == OK
            assert_close(np.array(got), python_outputs(py, st), f"FMI 3 fed map at {st}")
    finally:
        raw.close()


def test_model_exchange_outputs_and_directional_derivatives(fed_map):
    """ME: the outputs the Python internal's; the directional derivatives the tangent's bits, and in omega
    (the speed enters through a = eps omega - 2 v_t / CR, so through W and u too) central differences of
    the Python force."""
    from test_native_fmu import IN, OK, OUT, Raw, assert_close, python_outputs

    fmu, unzip, path, _ = fed_map
    py = python_internal(fmu, path)
    raw = Raw(fmu, unzip, kind="ME")
    f = raw.fmu
    try:
        assert raw.init() == OK
        f.enterContinuousTimeMode()
        vr = {n: raw.vars[n].valueReference for n in (*IN, *OUT)}
        for st in [s for s in states(8, seed=3) if s[4] > 1.0]:
            f.setReal([vr[n] for n in IN], list(st))
            got, want = np.array(f.getReal([vr[n] for n in OUT])), python_outputs(py, st)
            assert_close(got, want, "ME fed map")
            for j, name in enumerate(IN[:4]):
                d = f.getDirectionalDerivative([vr["Fy"], vr["Fz"]], [vr[name]], [1.0])
                assert d == ([-got[2 + j], -got[4 + j]] if j < 2 else [-got[4 + j], -got[6 + j]])
            h = 1e-5 * st[4]
            fd = (np.array(py.force(*st[:4], st[4] + h)) - np.array(py.force(*st[:4], st[4] - h))) / (2 * h)
            d = f.getDirectionalDerivative([vr["Fy"], vr["Fz"]], [vr["omega"]], [1.0])
            np.testing.assert_allclose(d, fd, rtol=1e-5, atol=1e-7 * np.max(np.abs(want[:2])) / st[4])
    finally:
        raw.close()


def test_what_the_native_fed_map_refuses_by_name(fed_map, tmp_path):
    """thermal = true (the fed map's film report has no C port), another supply pressure than the bearing's
    it was built with (the data's bore: check_bore), and at build time a bearing with ambient grooves."""
    from test_native_fmu import ERROR, OK, Raw

    from bearing_fmu.fmu.native.generators.map import FED_NO_FLOWS_WHY, map_model

    fmu, unzip, path, _ = fed_map
    for name, value, words in (("thermal", True, FED_NO_FLOWS_WHY[:60]),
                               ("supply_pressure", 2 * P_S, "supply_pressure = 200000 (the data's: 100000)")):
        raw = Raw(fmu, unzip)
        try:
            assert raw.set(name, value) == OK
            raw.enter()
            assert raw.call("fmi2ExitInitializationMode") == ERROR and words in raw.last(), raw.last()
        finally:
            raw.close()
    with pytest.raises(ValueError, match="is for fed grooves .*the bearing's are at ambient pressure: .*; for the "
                       "native map FMU give the file of the bearing whose grooves are fed .* with --bearing"):
        map_model(AMBIENT, None, path, {})


@pytest.mark.slow  # three compilers over the sources: 3.4 s, the quick loop's largest
def test_the_sources_compile_without_a_warning(fed_map, tmp_path):
    """gcc and zig (Windows, macOS) with -Wall -Wextra -Wpedantic -Werror on the FMU's sources."""
    from test_native_platforms import sources_compile_without_a_warning

    sources_compile_without_a_warning(fed_map[1], tmp_path)


@pytest.mark.parametrize("interface", ["me", "cs"])
def test_compliance_checker_reports_nothing(fed_map, interface, tmp_path):
    """The FMU Compliance Checker in an empty environment, the journal circling 0.3 CR about (0, -0.3 CR) at
    22 Hz: 0 warnings and 0 errors from the FMU and the checker."""
    fmu = fed_map[0]
    rows = ["time,y,z,vy,vz,omega"]
    for k in range(11):
        t, r = 1e-3 * k, 0.3 * FED.CR
        rows.append(f"{t!r},{r * math.cos(W22 * t)!r},{-r * math.sin(W22 * t) - r!r},"
                    f"{-r * W22 * math.sin(W22 * t)!r},{-r * W22 * math.cos(W22 * t)!r},{W22!r}")
    (tmp_path / "in.csv").write_text("\n".join(rows) + "\n")
    log = tmp_path / "check.log"
    done = subprocess.run(["env", "-i", str(compliance_checker()), "-h", "1e-4", "-s", "0.01", "-k", interface, "-i",
                           str(tmp_path / "in.csv"), "-o", str(tmp_path / "out.csv"), "-e", str(log), str(fmu)],
                          capture_output=True, text=True, timeout=300, check=False)
    text = log.read_text()
    summary = text[text.index("FMU check summary:"):]
    assert done.returncode == 0 and "Simulation finished successfully" in text, summary
    assert "FMU reported:\n\t0 warning(s) and error(s)" in summary, summary
    assert "0 Warning(s)" in summary and "0 Error(s)" in summary, summary
    assert len((tmp_path / "out.csv").read_text().splitlines()) >= 100
