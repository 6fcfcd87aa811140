"""The internals registry and the contract every registered internal keeps.

The contract is checked against things independent of each internal's own code: its force
against central differences of itself (the analytic Jacobian), the state checks against
the inputs' definition (non-finite, the clearance circle), the FMU against the direct call
(to round-off: the same code behind FMI). A new internal must add its case to CASES (the
first test fails otherwise) and so gets every check. The last tests add an internal the way
the package docstring says, from outside the package, and run a scene with it.
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
GRID = {"n_theta": 32, "n_x": 4}  # coarse: the contract, not the accuracy, is checked here


def _case(name, files):
    """(options, a state (y, z, vy, vz) inside what the internal answers for, what it does
    beyond the wall: "refuses" or "evaluates")."""
    moving = (10e-6, -40e-6, 1e-3, -2e-4)  # eccentricity 0.46
    if name == "reynolds":
        return dict(GRID), moving, "refuses"
    if name == "linear":  # the paper's linear orbits cross the wall: it evaluates there
        return {**GRID, "load_z": -16.7, "omega_lin": OMEGA}, moving, "evaluates"
    if name == "taylor":  # the made-up surrogate of conftest: expansion point (0.1, -0.4) CR
        return {"surrogate": str(files["surrogate"]), **GRID}, (0.15 * P.CR, -0.35 * P.CR, 1e-3, -2e-3), "refuses"
    if name == "map":  # the coarse map of conftest
        return {"map": str(files["map"])}, moving, "refuses"
    raise KeyError(name)


BUILTIN = ("reynolds", "linear", "taylor", "map")


@pytest.fixture
def files(surrogate_file, map_file):
    return {"surrogate": surrogate_file, "map": map_file}


def test_every_registered_internal_has_a_contract_case(files):
    for name in registry.names():
        _case(name, files)  # KeyError: add the new internal's case above
    assert registry.names()[:4] == BUILTIN


@pytest.fixture(params=BUILTIN)
def case(request, files):
    name = request.param
    options, state, wall = _case(name, files)
    return name, registry.create(name, P, options), options, state, wall


def test_force_and_jacobian_against_central_differences(case, central_jacobian):
    name, internal, _, state, _ = case
    f = np.array(internal.force(*state, OMEGA))
    assert np.all(np.isfinite(f))
    F, dq, dv = internal.force_and_jacobian(*state, OMEGA)
    np.testing.assert_allclose(F, f, rtol=1e-12, atol=0)
    h = 1e-6 * P.CR
    cq, cv = central_jacobian(internal.force, state, OMEGA, (h, h, h * OMEGA, h * OMEGA))
    # relative to the largest entry: Reynolds' adjoint holds the cavitation set fixed, which a
    # step of 1e-6 CR does not change; the polynomials are exact to round-off
    np.testing.assert_allclose(dq, cq, atol=1e-5 * np.abs(cq).max(), err_msg=f"{name} dF/dq")
    np.testing.assert_allclose(dv, cv, atol=1e-5 * np.abs(cv).max(), err_msg=f"{name} dF/dv")


@pytest.mark.parametrize("var", range(5))
def test_non_finite_input_is_refused_by_name(case, var):
    name, internal, _, state, _ = case
    x = [*state, OMEGA]
    x[var] = math.nan
    for call in (internal.force, internal.force_and_jacobian):
        with pytest.raises(BearingStateError, match=f"bearing input {registry.STATE_NAMES[var]} = nan is not finite"):
            call(*x)


def test_beyond_the_wall_refused_or_finite_never_nan(case):
    name, internal, _, state, wall = case
    y, z = 0.6 * 1.03 * P.CR, -0.8 * 1.03 * P.CR  # eccentricity 1.03
    if wall == "refuses":
        with pytest.raises(BearingStateError, match="eccentricity ratio 1.03"):
            internal.force(y, z, 0.0, 0.0, OMEGA)
    else:
        assert np.all(np.isfinite(internal.force(y, z, 0.0, 0.0, OMEGA)))


def test_fmu_equals_the_direct_call(case, fmu_instance):
    name, internal, options, state, _ = case
    for key in ("surrogate", "map"):  # in the FMU: the bundled file by its name
        if key in options:
            options = {**options, key: Path(options[key]).name}
    inst = fmu_instance(internal=name, **options)
    try:
        out = inst.step(1e-4, *state, OMEGA)
        F, dq, dv = internal.force_and_jacobian(*state, OMEGA)
        got = [out[k] for k in ("Fy", "Fz", "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz")]
        want = [*F, *(-np.asarray(dq)).ravel(), *(-np.asarray(dv)).ravel()]  # the FMU outputs Lund's sign
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    finally:
        inst.close()


def test_fmu_declares_every_option_with_its_default(fmu):
    fmpy = pytest.importorskip("fmpy")
    v = {x.name: x for x in fmpy.read_model_description(str(fmu)).modelVariables}
    for o in registry.all_options():
        assert v[o.name].causality == "parameter", o.name
        if not o.file:  # a file option defaults to the one bundled file
            start = v[o.name].start
            assert (o.type(float(start)) if o.type in (int, float) else o.type(start)) == o.default, o.name
        assert o.check(o.default) == o.default, o.name  # every default is allowed by its own option


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
    from bearing_fmu.physics.reynolds import Reynolds
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
        return -self.k * y - self.c * vy, -self.k * z - self.c * vz

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
    from rotor_host.cli import _internal_choices

    assert "spring" in _internal_choices()
