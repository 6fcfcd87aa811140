"""The internals registry and the contract every registered internal keeps.

The contract is checked against things independent of each internal's own code: its force
against central differences of itself (the analytic Jacobian), the state checks against
the inputs' definition (non-finite, huge, the clearance circle), its capabilities against
what it does, the FMU against the direct call (to round-off: the same code behind FMI).
``CONTRACT`` is the list of checks; ``test_contract`` runs each over every internal in the
registry, built from its own ``ContractCase`` (``InternalSpec.case``: options for the paper
bearing at 22 Hz, a state it answers for, what it does past the wall), so a new internal
cannot be left out. An internal registered from outside the package runs the same checks
(``test_an_internal_added_from_outside_keeps_the_whole_contract``).
"""

import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals import registry
from bearing_fmu.internals.registry import BearingStateError, Context, InternalSpec, Option
from bearing_fmu.physics.params import PAPER_BEARING

P = PAPER_BEARING
OMEGA = 2 * math.pi * 22.0


class Built:
    """One internal built from its contract case, with what the checks need."""

    def __init__(self, spec, data_dir: Path, central_jacobian, fmu_instance):
        self.spec = spec
        self.case = spec.contract_case(data_dir)
        self.params = self.case.params or P  # the paper bearing, or its bore the internal needs (tilting pads)
        self.internal = registry.create(spec.name, self.params, self.case.options)
        self.central_jacobian, self.fmu_instance = central_jacobian, fmu_instance


def check_force_is_finite_and_the_jacobian_call_agrees(b: Built):
    f = np.array(b.internal.force(*b.case.state, b.case.omega))
    assert f.shape == (2,) and np.all(np.isfinite(f))
    if hasattr(b.internal, "force_and_jacobian"):
        F, dq, dv = b.internal.force_and_jacobian(*b.case.state, b.case.omega)
        np.testing.assert_allclose(F, f, rtol=1e-12, atol=0)
        assert np.shape(dq) == (2, 2) and np.shape(dv) == (2, 2)


def check_jacobian_against_central_differences(b: Built):
    if not hasattr(b.internal, "force_and_jacobian"):  # the statics difference it: nothing to compare
        return
    state, omega = b.case.state, b.case.omega
    F, dq, dv = b.internal.force_and_jacobian(*state, omega)
    h = 1e-6 * P.CR
    cq, cv = b.central_jacobian(b.internal.force, state, omega, (h, h, h * omega, h * omega))
    # relative to the largest entry: Reynolds' adjoint holds the cavitation set fixed, which a
    # step of 1e-6 CR does not change; the polynomials are exact to round-off
    np.testing.assert_allclose(dq, cq, atol=1e-5 * np.abs(cq).max(), err_msg=f"{b.spec.name} dF/dq")
    np.testing.assert_allclose(dv, cv, atol=1e-5 * np.abs(cv).max(), err_msg=f"{b.spec.name} dF/dv")


def check_non_finite_inputs_are_refused_by_name(b: Built):
    calls = [b.internal.force] + ([b.internal.force_and_jacobian] if hasattr(b.internal, "force_and_jacobian")
                                  else [])
    for var in range(5):
        for bad in (math.nan, math.inf):
            x = [*b.case.state, b.case.omega]
            x[var] = bad
            for call in calls:
                with pytest.raises(BearingStateError,
                                   match=f"bearing input {registry.STATE_NAMES[var]} = {bad!r} is not finite"):
                    call(*x)


def check_beyond_the_wall_refused_or_finite_never_nan(b: Built):
    y, z = 0.6 * 1.03 * P.CR, -0.8 * 1.03 * P.CR  # eccentricity 1.03
    if b.case.beyond_wall == "refuses":
        with pytest.raises(BearingStateError, match="eccentricity ratio 1.03"):
            b.internal.force(y, z, 0.0, 0.0, b.case.omega)
    else:
        assert b.case.beyond_wall == "evaluates", b.case.beyond_wall
        assert np.all(np.isfinite(b.internal.force(y, z, 0.0, 0.0, b.case.omega)))


def check_huge_finite_inputs_are_refused_by_name_or_finite(b: Built):
    # 1e308 is a float: an internal either evaluates it to finite numbers (a finite force the
    # model gives) or refuses it with BearingStateError naming the input, never inf or NaN
    import re

    calls = [b.internal.force] + ([b.internal.force_and_jacobian] if hasattr(b.internal, "force_and_jacobian")
                                  else [])
    for var in range(5):
        for big in (1e308, -1e308):
            x = [*b.case.state, b.case.omega]
            x[var] = big
            for call in calls:
                try:
                    out = call(*x)
                except BearingStateError as exc:
                    assert re.search(rf"\b{registry.STATE_NAMES[var]} = {re.escape(repr(big))}\b", str(exc)), \
                        (b.spec.name, exc)
                    assert "\n" not in str(exc)
                else:
                    values = out if call is not b.internal.force else [out]
                    assert all(np.all(np.isfinite(a)) for a in values), (b.spec.name, registry.STATE_NAMES[var], big)


def check_options_are_checked_by_name(b: Built):
    for o in b.spec.all_options():
        assert o.check(o.default) == o.default, o.name  # every default is allowed by its own option
    with pytest.raises(ValueError, match=rf"unknown option\(s\) no_such_option of the {b.spec.name} internal"):
        registry.create(b.spec.name, b.params, {**b.case.options, "no_such_option": 1})


def check_capabilities_hold(b: Built):
    can, internal, (y, z, vy, vz), omega = b.spec.can, b.internal, b.case.state, b.case.omega
    if can.truth:
        assert can.any_state, "a truth answers for any state"
    if can.any_state:  # another speed and load: still an answer
        assert np.all(np.isfinite(internal.force(0.5 * y, 0.5 * z, 0.0, 0.0, 2.0 * omega)))
    if can.fixed_speed:  # it has its speed and refuses another
        assert internal.omega == pytest.approx(omega)
        with pytest.raises(BearingStateError):
            internal.force(y, z, vy, vz, 2.0 * omega)
    if can.step_states:  # states of its own over a step: the host's hooks, and what an FMU state carries
        assert not can.memoryless
        internal.begin_step(0.0)
        internal.force(y, z, vy, vz, omega)  # at rest: the state
        saved = internal.step_state()
        internal.begin_step(1e-4)
        f1 = internal.force(y + 1e-7, z, vy, vz, omega)
        internal.accept_step()
        internal.set_step_state(saved)  # back: the same step gives the same force
        internal.begin_step(1e-4)
        assert internal.force(y + 1e-7, z, vy, vz, omega) == f1
        with pytest.raises(ValueError):
            internal.set_step_state(saved[:-1])
    if can.fitted_domain:
        assert math.isfinite(internal.domain_distance(y, z, vy, vz))
        internal.force(y, z, vy, vz, omega)
        assert internal.last_out_of_domain in (False, True)
    if not registry.film_flow_of(b.spec, internal):  # the FMU's thermal ports read its film report
        rep = internal.film_report(y, z, vy, vz, omega)  # friction and flows at any state
        assert rep.inflow_m3_s > 0.0 and rep.side_flow_m3_s > 0.0 and math.isfinite(rep.friction_power_W)
    if can.native:
        from bearing_fmu.fmu.native import INTERNALS

        assert b.spec.name in INTERNALS, "declared native, but the native FMU has no C model of it"
    assert hasattr(internal, "compiled_force") == can.compiled, "compiled_force() and Capabilities.compiled"
    if can.compiled:  # its compiled kernel: the numbers force_and_jacobian gives, and its refusals
        from bearing_fmu.internals.compiled import evaluate

        status, F, dq, dv = evaluate(internal.compiled_force(), y, z, vy, vz, omega)
        want = internal.force_and_jacobian(y, z, vy, vz, omega)
        assert status == 0
        for got, exp in zip((F, dq, dv), want):
            np.testing.assert_array_equal(got, exp)
        assert evaluate(internal.compiled_force(), y, math.nan, vy, vz, omega)[0] != 0
        assert evaluate(internal.compiled_force(), y, z, vy, vz, 2.0 * omega)[0] == (0 if can.any_state else 1)


def check_fmu_equals_the_direct_call(b: Built):
    options = dict(b.case.options)
    for key, path in b.case.files.items():  # in the FMU: the bundled file by its name
        options[key] = Path(path).name
    if callable(b.spec.factory) or not b.spec.can.fmu:  # registered from outside: the FMU carries the package's
        # internals only; one the FMU does not carry yet (Capabilities.fmu, fmu_why) is refused
        with pytest.raises(Exception):
            b.fmu_instance(internal=b.spec.name)
        return
    if b.case.params is not None:  # the case's own bearing (a bore the paper bearing lacks: tilting pads)
        from bearing_fmu.fmu.ports import port_defaults

        p = b.case.params
        options = {"D": p.D, "L": p.L, "CR": p.CR, "mu": p.mu, **port_defaults(p, pads=True), **options}
    inst = b.fmu_instance(internal=b.spec.name, **options)
    try:
        out = inst.step(1e-4, *b.case.state, b.case.omega)
        if b.spec.can.step_states:  # the FMU's states start at rest at its inputs of Initialization Mode (all 0)
            b.internal.begin_step(0.0)
            b.internal.force_and_jacobian(0.0, 0.0, 0.0, 0.0, 0.0)
            b.internal.begin_step(1e-4)  # then one doStep of 1e-4 s
        if hasattr(b.internal, "force_and_jacobian"):
            F, dq, dv = b.internal.force_and_jacobian(*b.case.state, b.case.omega)
        else:
            from bearing_fmu.physics.statics import film_jacobian

            F, dq, dv = film_jacobian(b.internal, *b.case.state, b.case.omega)
        got = [out[k] for k in ("Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")]
        want = [*F, *(-np.asarray(dq)).ravel(), *(-np.asarray(dv)).ravel()]  # the FMU outputs Lund's sign
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    finally:
        inst.close()


CONTRACT = [check_force_is_finite_and_the_jacobian_call_agrees, check_jacobian_against_central_differences,
            check_non_finite_inputs_are_refused_by_name, check_beyond_the_wall_refused_or_finite_never_nan,
            check_huge_finite_inputs_are_refused_by_name_or_finite, check_options_are_checked_by_name,
            check_capabilities_hold, check_fmu_equals_the_direct_call]


@pytest.fixture
def built(contract_data, central_jacobian, fmu_instance):
    return lambda name: Built(registry.get(name), contract_data, central_jacobian, fmu_instance)


@pytest.mark.parametrize("check", CONTRACT, ids=lambda c: c.__name__.removeprefix("check_"))
@pytest.mark.parametrize("name", registry.names())
def test_contract(name, check, built):
    check(built(name))


def test_every_registered_internal_declares_what_it_can_do():
    for name in registry.names():
        spec = registry.get(name)
        assert isinstance(spec.can, registry.Capabilities), name
        assert spec.can.validity or spec.summary, name
    assert registry.having(truth=True) == ("reynolds",)
    assert set(registry.having(any_state=True)) == {"reynolds", "map", "tilting_pad"}
    with pytest.raises(TypeError, match="no capability 'fast'"):
        registry.having(fast=True)


def test_the_fmu_declares_every_option_with_its_default(fmu):
    import fmpy

    v = {x.name: x for x in fmpy.read_model_description(str(fmu)).modelVariables}
    for o in registry.all_options():
        assert v[o.name].causality == "parameter", o.name
        if not o.file:  # a file option defaults to the one bundled file
            start = v[o.name].start
            assert (o.type(float(start)) if o.type in (int, float) else o.type(start)) == o.default, o.name


# ----------------------------------------------------------------------------- options and lookup

def test_option_checks_name_the_option_and_the_range():
    n_x = next(o for o in registry.get("reynolds").options if o.name == "n_x")
    assert n_x.check(0) == 0 and n_x.check(8) == 8 and n_x.check(8.0) == 8
    for bad in (7, -2, 8.5, "8", True, math.inf):
        with pytest.raises(ValueError, match=r"where: n_x = .* must be an even integer >= 2 and <= 100000, or 0"):
            n_x.check(bad, "where")
    action = next(o for o in registry.get("taylor").options if o.name == "domain_action")
    assert action.check(" Fallback ") == "fallback"
    with pytest.raises(ValueError, match="unknown domain_action 'ignore'; choose one of warn, fallback, discard"):
        action.check("ignore")
    with pytest.raises(ValueError, match=r"domain_limit = 0 must be a finite number > 0"):
        registry.create("taylor", P, {"domain_limit": 0})


def test_unknown_internal_and_option_name_the_allowed_ones():
    with pytest.raises(ValueError, match="unknown internal 'magic'; choose one of reynolds, linear, taylor, map"):
        registry.get("magic")
    with pytest.raises(ValueError, match=r"unknown option\(s\) grid of the reynolds internal; allowed: n_theta, n_x"):
        registry.create("reynolds", P, {"grid": 3})


def test_options_of_used_internals_reach_the_builder():
    # linear builds Reynolds with the reynolds options: its coefficients differ between grids
    # exactly as Reynolds' own derivatives do (Lund's K = -dF/dq at the equilibrium)
    from bearing_fmu.physics.solver.reynolds import Reynolds
    from bearing_fmu.physics.statics import equilibrium

    lin = registry.create("linear", P, {"n_theta": 32, "n_x": 4}, Context(load=(0.0, -16.7), omega=OMEGA))
    rey = Reynolds(P, n_theta=32, n_x=4)
    y0, z0 = equilibrium(rey, (0.0, -16.7), OMEGA)
    assert (lin.y0, lin.z0, lin.omega0) == pytest.approx((y0, z0, OMEGA), rel=1e-12)
    _, dq, _ = rey.force_and_jacobian(y0, z0, 0.0, 0.0, OMEGA)
    np.testing.assert_allclose(lin.K, -dq, rtol=1e-6)


def test_context_fills_what_nobody_set_and_explicit_values_win():
    spec = registry.get("linear")
    ctx = Context(load=(1.0, -20.0), omega=100.0)
    filled = spec.check_options({}, context=ctx)
    assert (filled["load_y"], filled["load_z"], filled["omega_lin"]) == (1.0, -20.0, 100.0)
    assert spec.check_options({"load_z": -5.0}, context=ctx)["load_z"] == -5.0
    assert spec.check_options({})["load_z"] == registry.DEFAULT_LOAD_Z


def test_a_clashing_option_name_is_refused():
    clash = InternalSpec("clash", lambda p, o, c: None, "", options=(Option("n_theta", float, 1.0, "not a grid"),))
    with pytest.raises(ValueError, match="option 'n_theta' of internal 'clash' differs"):
        registry.register(clash)
    assert "clash" not in registry.names()
    with pytest.raises(ValueError, match="'reynolds' is already registered"):
        registry.register(registry.get("reynolds"))


# ----------------------------------------------------------------------------- adding an internal

class Spring:
    """A trivial internal: an isotropic spring and damper about the bearing centre,
    F = -k q - c v. Its equilibrium under a load W is q = W / k (closed form)."""

    def __init__(self, params, k, c):
        self.params, self.k, self.c = params, k, c

    def force(self, y, z, vy, vz, omega):
        registry.check_state(self.params, y, z, vy, vz, omega)
        f = (-self.k * y - self.c * vy, -self.k * z - self.c * vz)
        if not all(map(math.isfinite, f)):  # the checklist: finite inputs past the float range, refused
            raise registry.overflow_error(self.params, y, z, vy, vz, omega)
        return f

    def force_and_jacobian(self, y, z, vy, vz, omega):
        F = np.array(self.force(y, z, vy, vz, omega))
        return F, -self.k * np.eye(2), -self.c * np.eye(2)


SPRING = InternalSpec(
    "spring", lambda params, o, context: Spring(params, o["spring_k"], o["spring_c"]),
    "isotropic spring and damper (test only)",
    options=(Option("spring_k", float, 1e6, "stiffness", "N/m", minimum=0.0, exclusive_minimum=True),
             Option("spring_c", float, 100.0, "damping", "N.s/m", minimum=0.0)),
)


@pytest.fixture
def spring():
    registry.register(SPRING)
    yield SPRING
    registry.unregister("spring")


def test_an_internal_added_from_outside_keeps_the_whole_contract(spring, built):
    # registered after collection: the parametrized test_contract cannot see it, so every
    # check of CONTRACT runs here, by name, for it
    ran = []
    for check in CONTRACT:
        check(built("spring"))
        ran.append(check.__name__)
    assert ran == [c.__name__ for c in CONTRACT] and len(ran) == 8


def test_an_internal_added_from_outside_keeps_the_contract(spring, central_jacobian):
    internal = registry.create("spring", P, {"spring_k": 2e6})
    state = (10e-6, -40e-6, 1e-3, -2e-4)
    F, dq, dv = internal.force_and_jacobian(*state, OMEGA)
    h = 1e-6 * P.CR
    cq, cv = central_jacobian(internal.force, state, OMEGA, (h, h, h * OMEGA, h * OMEGA))
    np.testing.assert_allclose(dq, cq, rtol=1e-8)
    np.testing.assert_allclose(dv, cv, rtol=1e-8)
    with pytest.raises(BearingStateError, match="bearing input vz = nan"):
        internal.force(0.0, 0.0, 0.0, math.nan, OMEGA)
    with pytest.raises(ValueError, match="spring_k = -1.0 must be a finite number > 0"):
        registry.create("spring", P, {"spring_k": -1.0})


def test_a_scene_runs_with_an_internal_added_from_outside(spring, tmp_path, paper_scene):
    # the scene loader, the CLI choices and the run know it from the registry alone; at rest
    # (no unbalance) each journal sits at W / k, W its bearing's static load
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    k = 4e6
    scene = load_scene(paper_scene(internal="spring", t_end=2e-3, unbalance_g=None, spring={"spring_k": k}))
    run = run_scene(scene, tmp_path / "out")
    assert run.ok, run.meta["message"]
    a = run.arrays
    W = np.array(run.meta["bearing_loads_N"])
    cols = [list(a["nodes"]).index(n) for n in a["bearing_nodes"]]
    np.testing.assert_allclose(a["z"][-1, cols], W[:, 1] / k, rtol=1e-6)
    from rotor_host.cli import internal_choices

    assert "spring" in internal_choices()


def test_the_linear_model_past_the_wall_evaluates_and_is_flagged(fmu_instance):
    # the linear model has no wall: past the clearance circle it still gives F0 - K dq - C v
    # (finite, meaningless), and says so in out_of_domain, directly and through the FMU
    lin = registry.create("linear", P, {"n_theta": 32, "n_x": 4, "load_z": -16.7, "omega_lin": OMEGA})
    lin.force(10e-6, -40e-6, 0.0, 0.0, OMEGA)
    assert lin.last_out_of_domain is False
    y, z = 0.6 * 1.03 * P.CR, -0.8 * 1.03 * P.CR  # eccentricity 1.03
    assert np.all(np.isfinite(lin.force(y, z, 0.0, 0.0, OMEGA))) and lin.last_out_of_domain is True
    inst = fmu_instance(internal="linear", n_theta=32, n_x=4, load_z=-16.7, omega_lin=OMEGA)
    try:
        inst.step(1e-4, 10e-6, -40e-6, 0.0, 0.0, OMEGA)
        assert not inst.get("out_of_domain")
        inst.step(1e-4, y, z, 0.0, 0.0, OMEGA)
        assert inst.get("out_of_domain")
    finally:
        inst.close()


def test_the_registry_docstring_table_lists_every_registered_internal():
    # the table of internals in bearing_fmu/internals/registry.py's docstring, read as written:
    # one row (name, factory) per internal registered by a module path, in registration order
    # (continuation lines start with blanks), so a new internal without its row fails here
    doc = registry.__doc__
    rules = [i for i, line in enumerate(doc.splitlines()) if line.startswith("====")]
    assert len(rules) >= 3, "registry docstring: no table of internals (three rules of '=')"
    rows = doc.splitlines()[rules[1] + 1:rules[2]]
    table = [tuple(line.split()[:2]) for line in rows if line.strip() and not line[0].isspace()]
    assert table == [(s.name, s.factory) for s in registry.REGISTRY.values() if isinstance(s.factory, str)]
