"""The bearing FMU: build, validation, fmpy, equality with the internals, conformant
iteration, errors that leave the process usable, leave-out of unused internals, shadowing.

The FMU is built once per session (tests/conftest.py). Its code cache (BEARING_FMU_CACHE_DIR,
where numba's cache lives too) is kept between sessions in .pytest_cache and shared with the
subprocess tests.
"""

import importlib.util
import json
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.physics.params import PAPER_BEARING, BearingParams

import fmpy  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
P = PAPER_BEARING
OMEGA = 2 * math.pi * 22.0
STATE = (10e-6, -40e-6, 1e-3, -2e-4, OMEGA)  # eccentricity 0.46, moving
IN = ("y", "z", "vy", "vz", "omega")
TANGENT = ("Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")


def _example():
    spec = importlib.util.spec_from_file_location("drive_fmu_with_fmpy", ROOT / "examples" / "drive_fmu_with_fmpy.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


EX = _example()


def instance(fmu, unzip, **params):
    return EX.BearingInstance(fmu, params, unzip_dir=unzip)


@pytest.fixture(scope="session")
def reynolds():
    from bearing_fmu.physics.solver.reynolds import Reynolds

    return Reynolds(P)


# ----------------------------------------------------------------------------- build


def test_validate_and_model_description(fmu):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmu)) == []
    md = fmpy.read_model_description(str(fmu))
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    v = {x.name: x for x in md.modelVariables}
    assert [n for n in IN if v[n].causality == "input"] == list(IN)
    assert v["Fy"].unit == "N" and v["Kyy"].unit == "N/m" and v["omega"].unit == "rad/s"
    assert float(v["CR"].start) == 90e-6 and v["internal"].start == "reynolds"
    assert v["surrogate"].start == "paper_22hz.json"  # the one bundled surrogate
    inputs = {v[n] for n in (*IN, "T_supply")}  # the thermal port's input too (docs/fmu.md)
    assert {u.variable.name for u in md.initialUnknowns} == {x.name for x in md.modelVariables
                                                            if x.causality == "output"}
    for u in md.outputs:
        assert set(u.dependencies) == inputs


# ----------------------------------------------------------------------------- what a system-simulation engineer reads


def test_model_description_units_ranges_and_names(fmu, surrogate_file, map_file):
    import hashlib
    import tomllib

    md = fmpy.read_model_description(str(fmu))
    v = {x.name: x for x in md.modelVariables}
    # display units where natural (the list: um for y, z, CR; mm for D, L; rpm for omega)
    assert {n: v[n].displayUnit for n in ("y", "z", "CR", "h_min", "D", "L", "omega", "omega_lin", "vy")} == {
        "y": "um", "z": "um", "CR": "um", "h_min": "um", "D": "mm", "L": "mm", "omega": "rpm", "omega_lin": "rpm",
        "vy": "mm/s"}
    factors = {(u.name, d.name): d.factor for u in md.unitDefinitions for d in u.displayUnits}
    assert factors[("m", "um")] == 1e6 and factors[("m", "mm")] == 1e3
    assert factors[("rad/s", "rpm")] == pytest.approx(60 / (2 * math.pi), rel=1e-15)
    # bounds: the physical ranges of bearing_fmu/physics/params.py (D 1 mm .. 5 m, L/D 0.05 .. 5, CR/R 1e-5 .. 0.05,
    # mu 1e-5 .. 10 Pa s), for any D (the ratios are checked at initialisation)
    bounds = {n: (float(v[n].min), float(v[n].max)) for n in ("D", "L", "CR", "mu")}
    assert bounds["D"] == (1e-3, 5.0) and bounds["mu"] == (1e-5, 10.0)
    assert bounds["L"] == pytest.approx((0.05 * 1e-3, 5 * 5.0), rel=1e-15)
    assert bounds["CR"] == pytest.approx((1e-5 * 0.5e-3, 0.05 * 2.5), rel=1e-15)
    assert float(v["D"].nominal) == P.D and float(v["y"].nominal) == P.CR  # the bearing's scales
    # the registry's ranges: n_theta >= 8 or 0 (the solver's default), at most 100000
    assert (v["n_theta"].min, v["n_theta"].max) == ("0", "100000")
    assert float(v["domain_limit"].min) == 0.0 and float(v["eccentricity"].min) == 0.0
    # author and license: the project's (pyproject.toml), or the fallback when it names no author
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    authors = ", ".join(a.get("name") or a.get("email", "") for a in project.get("authors", []))
    assert md.author == (authors or "bearing_fmu maintainers")
    lic = project.get("license")
    assert md.license == ((lic.get("text") or lic.get("file")) if isinstance(lic, dict) else lic)
    # a model name per build: what computes, the bundled files, the bearing (fmu_meta.model_name)
    assert md.modelName == "BearingFMU python paper_22hz paper_map (paper bearing)"
    # the bearing's geometry and the bundled files with their hashes in the description
    assert "bearing D 31 mm, L 20 mm, CR 90 um, mu 0.05 Pa.s (paper bearing (Table 2))" in md.description
    for f in (surrogate_file, map_file):
        assert f"{f.name} sha256 {hashlib.sha256(f.read_bytes()).hexdigest()[:12]}" in md.description


def test_choice_parameters_are_also_enumerations(fmu):
    """FMI 2.0 enumerations (Integer-valued TypeDefinitions) beside the String parameters: the
    items are the registry's choices in its order, numbered from 1; the start is the String's."""
    from bearing_fmu.internals import registry

    md = fmpy.read_model_description(str(fmu))
    v = {x.name: x for x in md.modelVariables}
    expected = {"internal": registry.names(), **{o.name: o.choices for o in registry.all_options() if o.choices}}
    assert set(expected) == {"internal", "cavitation", "linear_from", "domain_action"}
    for string, items in expected.items():
        e = v[f"{string}_enum"]
        assert (e.type, e.causality, e.variability) == ("Enumeration", "parameter", "fixed")
        assert [(i.name, int(i.value)) for i in e.declaredType.items] == [(c, k + 1) for k, c in enumerate(items)]
        assert int(e.start) == items.index(v[string].start) + 1
        assert v[string].type == "String"  # kept: masters and rotor_host/coupling/cosim.py set it by name


class _Instance(EX.BearingInstance):
    """examples/drive_fmu_with_fmpy.py's BearingInstance, also setting and reading enumerations."""

    def set(self, name, value):
        v = self.vars[name]
        if v.type != "Enumeration":
            return super().set(name, value)
        self.fmu.setInteger([v.valueReference], [value])

    def get(self, name):
        v = self.vars[name]
        return self.fmu.getInteger([v.valueReference])[0] if v.type == "Enumeration" else super().get(name)


def _simulate_all_starts(fmu, start_values: dict):
    """One step of fmpy.simulate_fmu as a master that writes every start value and then the
    user's (apply_default_start_values): (result, or the FMICallException; messages >= warning)."""
    msgs = []

    def logger(_component, _name, status, _category, message):
        if status >= 1:
            msgs.append(message.decode())

    try:
        res = fmpy.simulate_fmu(str(fmu), stop_time=1e-4, output_interval=1e-4, start_values=start_values,
                                apply_default_start_values=True, debug_logging=True, logger=logger,
                                output=["Fy", "Fz"])
    except FMICallException as exc:
        res = exc
    return res, msgs


def test_enumeration_parameters_choose_like_their_string(fmu, unzip, surrogate_file, map_file):
    from bearing_fmu.internals import registry
    from bearing_fmu.internals.taylor import Taylor

    inside = (0.12 * P.CR, -0.42 * P.CR, 0.0, 0.0, OMEGA)  # the fixture surrogate's fitted domain
    inst = _Instance(fmu, {"internal_enum": 3}, unzip_dir=unzip)  # 3 = taylor
    try:
        out = inst.step(1e-4, *inside)
        assert (out["Fy"], out["Fz"]) == Taylor.from_file(surrogate_file, P).force(*inside)
        assert (inst.get("internal"), inst.get("internal_enum")) == (b"taylor", 3)  # both show the choice (fmpy: bytes)
    finally:
        inst.close()
    inst = _Instance(fmu, {"internal": "taylor", "domain_action_enum": 3}, unzip_dir=unzip)  # 3 = discard
    try:
        with pytest.raises(FMICallException):
            inst.step(1e-4, 0.45 * P.CR, -0.4 * P.CR, 0.0, 0.0, OMEGA)
        assert "domain_action = 'discard'" in inst.messages[-1] and inst.get("domain_action") == b"discard"
    finally:
        inst.close()
    # a master that writes every start value (the String's "reynolds" too): the enumeration set away
    # from its start wins
    res, msgs = _simulate_all_starts(fmu, {"internal_enum": 4, "y": STATE[0], "z": STATE[1], "omega": OMEGA})
    want = registry.create("map", P, {"map": str(map_file)}).force(STATE[0], STATE[1], 0.0, 0.0, OMEGA)
    assert (res["Fy"][-1], res["Fz"][-1]) == pytest.approx(want, rel=1e-14) and not msgs
    # both set away from their starts: they must agree
    res, msgs = _simulate_all_starts(fmu, {"internal": "map", "internal_enum": 3})
    assert isinstance(res, FMICallException)
    assert any("internal = 'map' and internal_enum = 3 (taylor) disagree: set one of them" in m for m in msgs), msgs
    # (at a state inside the surrogate's domain: a refused one is discarded, and fmpy retries it)
    res, msgs = _simulate_all_starts(fmu, {"internal": "taylor", "internal_enum": 3, "y": inside[0], "z": inside[1],
                                           "omega": OMEGA})
    assert not isinstance(res, FMICallException), msgs
    res, msgs = _simulate_all_starts(fmu, {"internal_enum": 9})
    assert any("internal_enum = 9 must be one of 1 (reynolds), 2 (linear), 3 (taylor), 4 (map)" in m for m in msgs)


def test_rotor_host_sets_an_enumeration_by_name_or_number(fmu, map_file):
    """rotor_host/coupling/cosim.py (FMUBearings): an enumeration parameter given as its item's name or its
    number; an unknown name is refused naming the items."""
    from bearing_fmu.internals import registry
    from rotor_host.coupling.cosim import FMUBearings, FMUError

    q, v = np.array(STATE[:2]), np.array(STATE[2:4])
    want = registry.create("map", P, {"map": str(map_file)}).force(*q, *v, OMEGA)
    for value in ("map", 4):
        with FMUBearings(fmu, [(0, 1)], OMEGA, [{"internal_enum": value}]) as b:
            b.begin_step(0.0, 1e-4)
            f, _dq, _dv = b.evaluate(q, v)
            assert tuple(f) == pytest.approx(want, rel=1e-14), value
            b.accept_step()
    with pytest.raises(FMUError, match=r"internal_enum = 'magic' is not an item of .*BearingFMU.Internal; "
                                       r"items: reynolds = 1, linear = 2, taylor = 3, map = 4"):
        FMUBearings(fmu, [(0, 1)], OMEGA, [{"internal_enum": "magic"}])


def test_nothing_set_initialises_without_a_warning(fmu):
    """fmpy.simulate_fmu with nothing set (and with every start value written): the default
    internal (Reynolds) at the start values (journal centred, omega 0) evaluates without a
    warning or an error; the centred journal carries no force."""
    msgs = []
    res = fmpy.simulate_fmu(str(fmu), stop_time=2e-4, debug_logging=True,
                            logger=lambda _c, _n, status, _k, m: status >= 1 and msgs.append(m.decode()))
    assert not msgs and len(res) == 3 and set(res["Fy"]) | set(res["Fz"]) == {0.0}
    res, msgs = _simulate_all_starts(fmu, {})
    assert not msgs and not isinstance(res, FMICallException)


def test_documentation_and_build_record(fmu, surrogate_file, map_file):
    """documentation/index.html (one generator for both FMUs, bearing_fmu/fmu/docs.py) lists every
    variable of the model description and where the data came from; resources/build_info.json
    records the bearing and the files with their SHA-256."""
    import hashlib
    import zipfile

    from bearing_fmu.internals import registry

    with zipfile.ZipFile(fmu) as z:
        page = z.read("documentation/index.html").decode()
        info = json.loads(z.read("resources/build_info.json"))
    md = fmpy.read_model_description(str(fmu))
    for v in md.modelVariables:
        assert f"<tr><td>{v.name}</td><td>{v.causality}</td>" in page, v.name
    assert md.modelName in page and "BearingFMU.Internal" in page and "<b>taylor</b>" in page
    for f in (surrogate_file, map_file):
        sha = hashlib.sha256(f.read_bytes()).hexdigest()
        assert sha in page
        assert next(d for d in info["data_files"] if d["name"] == f.name)["sha256"] == sha
    assert {k: info["bearing"][k] for k in ("D", "L", "CR", "mu")} == P.as_dict()
    assert info["bearing"]["source"] == "paper bearing (Table 2)"
    assert info["internals"] == list(registry.names()) and info["model_name"] == md.modelName


def test_linux_binary_has_the_exit_fix(fmu):
    """pythonfmu 0.7.0 releases its interpreter state twice at exit (heap corruption, abort in
    about half the runs once all instances are freed); the build patches it, and the FMI status
    patches with it (bearing_fmu/fmu/binary.py; their effect: tests/test_fmi_status.py)."""
    import zipfile

    from bearing_fmu.fmu.binary import patch_pythonfmu_binary
    from bearing_fmu.fmu.build import patch_linux_binary

    with zipfile.ZipFile(fmu) as z:
        data = z.read("binaries/linux64/BearingFMU.so")
        recorded = json.loads(z.read("resources/pythonfmu_patches.json"))
    assert patch_linux_binary(data)[1] == "already patched"
    notes = patch_pythonfmu_binary(data)[1]
    assert set(notes.values()) == {"already patched"} and set(notes) == set(recorded["linux64"])
    assert set(recorded["linux64"].values()) == {"patched"}  # what the build did to pythonfmu's original


def test_cli_build(tmp_path):
    from bearing_fmu.cli import main

    out = tmp_path / "cli.fmu"
    assert main(["build", "-o", str(out)]) == 0
    assert out.is_file()
    with pytest.raises(SystemExit) as exc:  # refused by argparse, naming --surrogate (tests/test_bad_inputs.py)
        main(["build", "-o", str(tmp_path / "x.fmu"), "--surrogate", str(tmp_path / "nope.json")])
    assert exc.value.code == 2


# ----------------------------------------------------------------------------- equality with the internals


def test_simulate_fmu_with_input_table(fmu, reynolds):
    """fmpy.simulate_fmu applies the table at the start of each step: row k is the force at
    the table's state of row k - 1."""
    sig, res = EX.simulate(fmu, t_end=0.005, dt=1e-3)
    assert len(res) == len(sig) == 6
    for k in range(1, len(res)):
        s = [sig[n][k - 1] for n in IN]
        assert (res["Fy"][k], res["Fz"][k]) == reynolds.force(*s)
        assert res["eccentricity"][k] == pytest.approx(math.hypot(s[0], s[1]) / P.CR, rel=1e-15)


def test_reynolds_default_and_grid_parameters_reach_the_solver(fmu, unzip, reynolds):
    from bearing_fmu.physics.solver.reynolds import Reynolds

    inst = instance(fmu, unzip)  # no parameter set: the paper bearing, default grid
    try:
        out = inst.step(1e-4, *STATE)
        F, dq, dv = reynolds.force_and_jacobian(*STATE)
        assert (out["Fy"], out["Fz"]) == reynolds.force(*STATE)
        assert [out[n] for n in TANGENT] == pytest.approx(list(-dq.ravel()) + list(-dv.ravel()), rel=1e-14)
        assert out["h_min"] == pytest.approx(P.CR - math.hypot(*STATE[:2]), rel=1e-14)
        # the peak of the force call's own field (Capabilities.film_field), as the solver gives it
        assert (inst.get("peak_pressure"), inst.get("peak_pressure_angle")) == reynolds.peak_pressure(*STATE)
        assert inst.get("peak_pressure") > 0.0
        assert inst.get("out_of_domain") is False
    finally:
        inst.close()
    other = BearingParams(D=0.05, L=0.03, CR=100e-6, mu=0.02)
    inst = instance(fmu, unzip, D=other.D, L=other.L, CR=other.CR, mu=other.mu, n_theta=40, n_x=6,
                    cavitation="gumbel", compute_tangent=False)
    try:
        out = inst.step(1e-4, *STATE)
        assert (out["Fy"], out["Fz"]) == Reynolds(other, 40, 6, "gumbel").force(*STATE)
        assert all(out[n] == 0.0 for n in TANGENT)  # not asked for
    finally:
        inst.close()


def test_linear_internal_equals_linear(fmu, unzip, reynolds):
    from bearing_fmu.internals.linear import Linear

    direct = Linear.at_load(reynolds, (0.0, -16.7), OMEGA)
    inst = instance(fmu, unzip, internal="linear")  # default: at the paper rotor's load and speed
    try:
        s = (direct.y0 + 5e-6, direct.z0 - 3e-6, 1e-3, 2e-4, OMEGA)
        out = inst.step(1e-4, *s)
        assert (out["Fy"], out["Fz"]) == pytest.approx(direct.force(*s), rel=1e-12)
        assert [out[n] for n in TANGENT] == pytest.approx(list(direct.K.ravel()) + list(direct.C.ravel()),
                                                          rel=1e-12)
        assert (inst.get("peak_pressure"), inst.get("peak_pressure_angle")) == (0.0, 0.0)  # no pressure field
        far = (2 * P.CR, 0.0, 0.0, 0.0, OMEGA)  # linear evaluates beyond the wall, as the paper's orbits do
        assert inst.step(1e-4, *far)["eccentricity"] == 2.0
    finally:
        inst.close()
    coef = dict(internal="linear", linear_from="coefficients", omega_lin=OMEGA, lin_y0=direct.y0,
                lin_z0=direct.z0, lin_Fy0=direct.F0[0], lin_Fz0=direct.F0[1])
    coef.update({f"lin_{n}": float(v) for n, v in zip(TANGENT, [*direct.K.ravel(), *direct.C.ravel()])})
    inst = instance(fmu, unzip, **coef)
    try:
        out = inst.step(1e-4, *s)
        assert (out["Fy"], out["Fz"]) == direct.force(*s)
    finally:
        inst.close()


def test_taylor_internal_equals_taylor(fmu, unzip, surrogate_file):
    from bearing_fmu.internals.taylor import Taylor

    direct = Taylor.from_file(surrogate_file, P)
    inst = instance(fmu, unzip, internal="taylor")  # surrogate defaults to the one bundled file
    try:
        inside = (0.12 * P.CR, -0.42 * P.CR, 0.01 * OMEGA * P.CR, 0.0, OMEGA)
        out = inst.step(1e-4, *inside)
        assert (out["Fy"], out["Fz"]) == direct.force(*inside) and inst.get("out_of_domain") is False
        F, dq, dv = direct.force_and_jacobian(*inside)
        assert [out[n] for n in TANGENT] == pytest.approx(list(-dq.ravel()) + list(-dv.ravel()), rel=1e-14)
        # the fixture's domain: position disc of radius 0.3 CR about (0.1, -0.4) CR
        outside = (0.45 * P.CR, -0.4 * P.CR, 0.0, 0.0, OMEGA)  # 1/6 beyond: warn, surrogate value
        for _ in range(2):
            out = inst.step(1e-4, *outside)
            assert (out["Fy"], out["Fz"]) == direct.force(*outside) and inst.get("out_of_domain") is True
        assert sum("outside the surrogate's fitted domain" in m for m in inst.messages) == 1  # warned once
        far = (0.7 * P.CR, -0.4 * P.CR, 0.0, 0.0, OMEGA)  # 100 % beyond > domain_limit 0.5: refused
        with pytest.raises(FMICallException):
            inst.step(1e-4, *far)
        assert "100 % beyond the surrogate's fitted domain" in inst.messages[-1]
        out = inst.step(1e-4, *inside)  # still usable
        assert (out["Fy"], out["Fz"]) == direct.force(*inside)
    finally:
        inst.close()


@pytest.mark.parametrize("action", ["fallback", "discard"])
def test_taylor_domain_actions(fmu, unzip, reynolds, action):
    """Outside the fitted domain, 'fallback' gives the Reynolds force (default grid) for that
    call and 'discard' refuses the step; inside, both give the surrogate's force."""
    from bearing_fmu.internals.taylor import Taylor

    direct = Taylor.from_file(unzip / "resources" / "surrogates" / "paper_22hz.json", P)
    inst = instance(fmu, unzip, internal="taylor", domain_action=action)
    try:
        inside = (0.12 * P.CR, -0.42 * P.CR, 0.0, 0.0, OMEGA)
        out = inst.step(1e-4, *inside)
        assert (out["Fy"], out["Fz"]) == direct.force(*inside)
        outside = (0.45 * P.CR, -0.4 * P.CR, 0.01 * OMEGA * P.CR, 0.0, OMEGA)
        if action == "fallback":
            out = inst.step(1e-4, *outside)
            assert (out["Fy"], out["Fz"]) == pytest.approx(reynolds.force(*outside), rel=1e-12)
            assert inst.get("out_of_domain") is True
        else:
            with pytest.raises(FMICallException):
                inst.step(1e-4, *outside)
            assert "domain_action = 'discard'" in inst.messages[-1]
    finally:
        inst.close()


def test_tangent_matches_linearize(fmu, unzip, reynolds):
    from bearing_fmu.physics.statics import equilibrium, linearize

    y0, z0 = equilibrium(reynolds, (0.0, -16.7), OMEGA)
    K, C = linearize(reynolds, y0, z0, OMEGA)
    inst = instance(fmu, unzip)
    try:
        out = inst.step(1e-4, y0, z0, 0.0, 0.0, OMEGA)
    finally:
        inst.close()
    assert [out[n] for n in TANGENT] == pytest.approx([*K.ravel(), *C.ravel()], rel=1e-13)
    assert (out["Fy"], out["Fz"]) == pytest.approx((0.0, 16.7), abs=1e-6)


# ----------------------------------------------------------------------------- conformant iteration


def test_conformant_iteration_equals_fresh_steps(fmu, unzip):
    trials = [STATE, (12e-6, -38e-6, 0.0, 5e-4, OMEGA), (-20e-6, -60e-6, -1e-3, 0.0, OMEGA)]
    inst = instance(fmu, unzip)
    try:
        inst.step(1e-4, 0.0, -30e-6, 0.0, 0.0, OMEGA)  # the instance now at t = 1e-4
        iterated = inst.iterate(1e-4, trials)
        assert inst.get("y") == trials[-1][0]  # left at the accepted (last) iterate
        # serialized state round trip: restore t = 1e-4 from bytes and step again
        saved = inst.fmu.getFMUstate()
        blob = inst.fmu.serializeFMUstate(saved)
        inst.fmu.freeFMUstate(saved)
        restored = inst.fmu.deSerializeFMUstate(blob)
        inst.fmu.setFMUstate(restored)
        inst.fmu.freeFMUstate(restored)
        assert inst.get("y") == trials[-1][0]
    finally:
        inst.close()
    for s, got in zip(trials, iterated):
        fresh = instance(fmu, unzip)
        try:
            assert fresh.step(1e-4, *s) == got
        finally:
            fresh.close()


# ----------------------------------------------------------------------------- errors leave the process usable


def _discarded(inst, h, state):
    n = len(inst.messages)
    with pytest.raises(FMICallException) as exc:
        inst.step(h, *state)
    assert exc.value.status == 2  # fmi2Discard
    return inst.messages[n:]


def test_invalid_states_discard_with_message_and_recover(fmu, unzip):
    inst = instance(fmu, unzip)
    try:
        good = inst.step(1e-4, *STATE)
        saved = inst.fmu.getFMUstate()
        msgs = _discarded(inst, 1e-4, (1.05 * P.CR, 0.0, 0.0, 0.0, OMEGA))
        assert any("eccentricity ratio 1.05 >= 1" in m and "at t = 0.0002 s" in m for m in msgs), msgs
        assert inst.get("Fy") == good["Fy"]  # outputs keep their last valid values
        inst.fmu.setFMUstate(saved)
        msgs = _discarded(inst, 1e-4, (0.0, -1.03 * P.CR, 0.0, 0.0, OMEGA))
        assert any("eccentricity ratio 1.03 >= 1" in m and "at t = 0.0002 s" in m for m in msgs), msgs
        assert any(m.startswith("[2]") for m in msgs)
        inst.fmu.setFMUstate(saved)
        assert inst.step(1e-4, *STATE) == good  # usable again
        inst.fmu.freeFMUstate(saved)
    finally:
        inst.close()


# A refused parameter or initialisation (fmi2Error, the instance still usable), unknown value
# references, bad step sizes, refused setters, outputs in Initialization Mode, fmi2Terminated
# after a discard and the stderr echo without logging: tests/test_fmi_status.py.


# ----------------------------------------------------------------------------- leave-out, shadowing, code cache

_PROBE = textwrap.dedent("""
    import json, sys, time
    sys.path.insert(0, {decoy!r})   # a different 'bearing_fmu' the FMU must not use
    import bearing_fmu
    assert bearing_fmu.__version__ == "decoy"
    sys.path.insert(0, {examples!r})
    from drive_fmu_with_fmpy import BearingInstance
    inst = BearingInstance({fmu!r}, json.loads({params!r}))
    t0 = time.perf_counter()
    out = inst.step(1e-4, *json.loads({state!r}))
    first = time.perf_counter() - t0
    inst.close()
    assert not any(m.startswith(("[2]", "[3]", "[4]")) for m in inst.messages), inst.messages
    files = {{k: getattr(m, "__file__", None) for k, m in sys.modules.items() if k.startswith("bearing_fmu")}}
    print(json.dumps(dict(out=out, times=dict(inst.times, first_step=first), modules=sorted(sys.modules),
                          files=files)))
""")


def _probe(fmu, tmp_path, params, state):
    decoy = tmp_path / "decoy"
    (decoy / "bearing_fmu").mkdir(parents=True)
    (decoy / "bearing_fmu" / "__init__.py").write_text('__version__ = "decoy"\n')
    (decoy / "bearing_fmu" / "reynolds.py").write_text('raise ImportError("the decoy was imported")\n')
    code = _PROBE.format(decoy=str(decoy), examples=str(ROOT / "examples"), fmu=str(fmu),
                         params=json.dumps(params), state=json.dumps(state))
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, PYTHONPATH=""))
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


def test_linear_from_coefficients_imports_neither_reynolds_nor_numba(fmu, tmp_path):
    params = dict(internal="linear", linear_from="coefficients", omega_lin=OMEGA, lin_Kyy=1e5, lin_Kzz=2e5,
                  lin_Cyy=300.0, lin_Czz=300.0, lin_Fz0=16.7)
    res = _probe(fmu, tmp_path, params, STATE)
    mods = res["modules"]
    assert not [m for m in mods if m.endswith(".reynolds") or m == "numba" or m.startswith("numba.")]
    assert any(m.startswith("bearing_fmu_v") and m.endswith(".linear") for m in mods)
    assert res["out"]["Fy"] == pytest.approx(-1e5 * STATE[0] - 300.0 * STATE[2])
    print("linear (coefficients) times [s]:", res["times"])


@pytest.fixture(scope="module")
def taylor_probe(fmu, tmp_path_factory):
    """One fresh interpreter (the decoy package first on its path) driving the session FMU with the
    Taylor internal: its output, what it imported and from where (two tests read it)."""
    return _probe(fmu, tmp_path_factory.mktemp("probe"), {"internal": "taylor"}, STATE)


def test_taylor_does_not_import_reynolds_and_decoy_is_ignored(taylor_probe, surrogate_file):
    from bearing_fmu.internals.taylor import Taylor

    res = taylor_probe
    assert not [m for m in res["modules"] if m.endswith(".reynolds")]
    assert (res["out"]["Fy"], res["out"]["Fz"]) == Taylor.from_file(surrogate_file, P).force(*STATE)
    print("taylor times [s]:", res["times"])


def test_fmu_code_runs_from_the_code_cache_beside_its_numba_cache(taylor_probe, code_cache):
    # in a fresh interpreter (this process may hold the bundle imported from another cache): the
    # Taylor kernels the probe ran (compiled with numba) come from the code cache, their numba
    # cache beside them
    from bearing_fmu.fmu.build import package_name

    res = taylor_probe
    pkg = package_name()
    src = Path(res["files"][f"{pkg}.surrogates.taylor_kernels"])
    assert src.parent == code_cache / pkg / "surrogates"
    assert "bearing_fmu.surrogates.taylor_kernels" not in res["files"]  # the installed package is separate
    assert list((src.parent / "__pycache__").glob("taylor_kernels*.nbi"))  # numba's cache index of the kernels beside it


@pytest.mark.slow
def test_build_with_a_users_bearing_makes_it_the_default(tmp_path, code_cache):
    # `bearing-fmu build --bearing FILE`: a master that sets no parameters gets that bearing's
    # force (before: the paper bearing's, silently); the model description's start values say so
    import fmpy

    from bearing_fmu.cli import main
    from bearing_fmu.physics.params import BearingParams
    from bearing_fmu.physics.solver.reynolds import Reynolds

    f = tmp_path / "b.toml"
    f.write_text("[bearing]\nD_mm = 40.0\nL_mm = 20.0\nCR_um = 60.0\nmu_Pa_s = 0.02\n")
    out = tmp_path / "b.fmu"
    assert main(["build", "--bearing", str(f), "-o", str(out)]) == 0
    starts = {v.name: float(v.start) for v in fmpy.read_model_description(str(out)).modelVariables
              if v.name in ("D", "L", "CR", "mu")}
    params = BearingParams.from_toml(f)
    assert starts == {"D": params.D, "L": params.L, "CR": params.CR, "mu": params.mu}
    # the bearing file recorded: its name in the model name, its hash in the description and the build record
    import hashlib
    import zipfile

    md = fmpy.read_model_description(str(out))
    sha = hashlib.sha256(f.read_bytes()).hexdigest()
    assert md.modelName == "BearingFMU python (b)" and f"(b.toml sha256 {sha[:12]})" in md.description
    assert json.loads(zipfile.ZipFile(out).read("resources/build_info.json"))["bearing"]["sha256"] == sha
    res = fmpy.simulate_fmu(str(out), stop_time=1e-3, output_interval=1e-3, output=["Fy", "Fz"],
                            start_values={"y": 1e-5, "z": -2e-5, "omega": 314.0})
    want = Reynolds(params).force(1e-5, -2e-5, 0.0, 0.0, 314.0)
    np.testing.assert_allclose([res["Fy"][-1], res["Fz"][-1]], want, rtol=1e-12)


def test_guid_hashes_the_description_not_the_build_machine(fmu):
    """pythonfmu writes uuid1 (the build machine's MAC address and the time); the build replaces
    it with a hash of the model description (code package, data files, variables)."""
    import uuid

    guid = fmpy.read_model_description(str(fmu)).guid
    assert guid.startswith("{") and guid[1:-1].split("-")[-1] != f"{uuid.getnode():012x}"
