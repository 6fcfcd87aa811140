"""Every [oil] heat balance in the native FMU (docs/thermal.md, docs/fmu.md): the outflow share s
(``oil_outflow_share``: 0.5 half rise, 0 full rise), the housing's loss h A (``oil_ambient_loss``) to
the ambient ``oil_T_ambient`` (0: the supply temperature), in c/oil_thermal.c (ot_balance_terms,
ot_film_temperature, ot_film_rate) and the native FMUs' thermal ports; and the native Reynolds FMU's
thermal model on a circumferential groove (all the lands' oil at the full rise).

Expected values: ``physics.thermal.film_temperature`` and ``heat_balance_rise`` (Python) at the same
film report (quasi-static and lagged: the C solve is a port with scipy's brentq iterates, so 1e-12;
the FMU's against Python to 1e-10), the Python FMU at the same parameters, an energy balance written
here from the FMU's outputs alone (P = rho c_p (Q - s Qs) dT + h A (T_eff - T_amb), the inflow Q from
the film, which does not depend on mu), central differences of the outputs for the directional
derivatives.
"""

import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from bearing_fmu.fmu import ports
from bearing_fmu.fmu.native.solver_lib import NativeOil
from bearing_fmu.physics.oil import KELVIN, Oil
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from bearing_fmu.physics.thermal import film_temperature
from tests.test_native_reynolds import PAPER, lib  # noqa: F401  (lib: the fixture)

VG46 = Oil.grade("ISO VG 46")
T_S = 45.0 + KELVIN
# the balances besides the default: the full rise; a housing losing 2 W/K to 20 C air (below the supply);
# the loss to an ambient at the supply temperature (T_ambient None: oil_T_ambient 0); both together
BALANCES = {"full": dict(outflow_rise="full"),
            "ambient": dict(ambient_W_K=2.0, T_ambient=20.0 + KELVIN),
            "ambient at supply": dict(ambient_W_K=2.0, rise_factor=0.7),
            "full with ambient": dict(outflow_rise="full", ambient_W_K=0.5, T_ambient=30.0 + KELVIN)}


def oil_values(oil) -> dict:
    """The FMU's oil parameters of the paper bearing with ``oil`` (ports.port_defaults; the rows' defaults
    where the law sets none)."""
    rows = ports.OIL_ROWS + ports.BALANCE_ROWS
    return {**{r[0]: r[4] for r in rows}, **ports.port_defaults(BearingParams(**PAPER, oil=oil))}


@pytest.mark.parametrize("name", list(BALANCES))
def test_c_film_temperature_equals_python(lib, name):  # noqa: F811
    """ot_film_temperature with the balance's parameters against physics.thermal.film_temperature at one
    film report: quasi-static and lagged from below and above over short and long steps, to 1e-12."""
    values = oil_values(replace(VG46, **BALANCES[name]))
    oil = ports.oil_of(SimpleNamespace(**values), values["oil_law"])  # the parameters carry the balance
    for key, value in BALANCES[name].items():
        assert getattr(oil, key) == value, key
    c = NativeOil(lib, values)
    params = BearingParams(**PAPER, oil=oil)
    report = Reynolds(params, 32, 4).film_report(2e-5, -6e-5, 1e-4, -2e-4, 600.0)
    for T_old, dt in [(None, 0.0)] + [(T_S + d, dt) for d in (-8.0, 30.0) for dt in (1e-4, 1e-2, 1.0)]:
        want = film_temperature(params, report, oil, T_S, T_old, dt)
        got = c.film_temperature(params, report, T_S, T_old, dt)
        assert got == pytest.approx(want, rel=1e-12, abs=0.0), (T_old, dt)
    half = film_temperature(params, report, VG46, T_S)[0]
    assert abs(want[0] - half) > 0.05 * (half - T_S)  # another balance than the default, solved


def test_c_film_cooled_below_its_range_is_refused(lib):  # noqa: F811
    """A housing loss so large that the film would run below the oil's range: both refuse (C by name)."""
    oil = replace(VG46, ambient_W_K=1e4, T_ambient=-60.0 + KELVIN)
    params = BearingParams(**PAPER, oil=oil)
    report = Reynolds(params, 32, 4).film_report(2e-5, -6e-5, 0.0, 0.0, 600.0)
    with pytest.raises(ValueError, match="below the oil's range"):
        film_temperature(params, report, oil, T_S)
    with pytest.raises(ValueError, match="below the oil.s range.*oil_ambient_loss"):
        NativeOil(lib, oil_values(oil)).film_temperature(params, report, T_S)


def test_c_outflow_share_other_than_half_or_none_refused(lib):  # noqa: F811
    values = oil_values(VG46)
    with pytest.raises(ValueError, match="oil_outflow_share = 0.25 must be 0.5 .* or 0"):
        NativeOil(lib, {**values, "oil_outflow_share": 0.25})
    with pytest.raises(ValueError, match="oil_ambient_loss = -1"):
        NativeOil(lib, {**values, "oil_ambient_loss": -1.0})


# ----------------------------------------------------------------------------- the native FMUs

fmpy = pytest.importorskip("fmpy")
from test_native_fmu_thermal import GRID, IN, Run, by_version, central, parameters, trajectory  # noqa: E402

STATE = trajectory()[3]
BALANCE_NAMES = ("oil_outflow_share", "oil_ambient_loss", "oil_T_ambient")


def balance_values(name) -> dict:
    """The native FMU's balance parameters for ``BALANCES[name]`` (ports.port_defaults)."""
    values = oil_values(replace(VG46, **BALANCES[name]))
    return {**{n: values[n] for n in BALANCE_NAMES}, "oil_rise_factor": values["oil_rise_factor"]}


@pytest.fixture(scope="module")
def native2(tmp_path_factory, native_build_cache):
    """(the native Reynolds FMU (FMI 2.0) of the VG 46 bearing, its model description)."""
    return by_version(tmp_path_factory.mktemp("native_balance"), native_build_cache, "reynolds", [], options=GRID)[2]


def python_balance(md, reals, state=STATE, T_s=T_S, params_extra=None):
    """(the Python oil of the FMU's parameters ``reals``, the bearing, its film report at ``state`` on GRID)."""
    p = {**parameters(md), **reals}
    oil = ports.oil_of(SimpleNamespace(**p), "walther", grooved=bool((params_extra or {}).get("geometry")))
    params = BearingParams(D=p["D"], L=p["L"], CR=p["CR"], mu=p["mu"], **(params_extra or {}))
    return oil, params, Reynolds(params, GRID["n_theta"], GRID["n_x"]).film_report(*state)


def energy_residual(out, oil, inflow, T_s=T_S) -> float:
    """P_loss - rho c_p (Q - s Q_side) dT - h A (T_eff - T_amb) over P_loss at the FMU's outputs ``out``
    (T_eff, mu_eff, P_loss, Q_side): the balance written from the oil's keys, not the code's."""
    s = {"half": 0.5, "full": 0.0}[oil.outflow_rise]
    T_amb = T_s if oil.T_ambient is None else oil.T_ambient
    T, P, Qs = out[0], out[2], out[3]
    dT = (T - T_s) / oil.rise_factor
    return (P - oil.density * oil.heat_capacity * (inflow - s * Qs) * dT - oil.ambient_W_K * (T - T_amb)) / P


@pytest.mark.parametrize("name", list(BALANCES))
def test_native_fmu_film_temperature_is_pythons(native2, name):
    """Co-Simulation, thermal = true, the balance's parameters set: the quasi-static T_eff and mu_eff at
    Initialization Mode's inputs equal film_temperature's (1e-10), the energy balance closes at the
    outputs (1e-9), and a lagged step equals film_temperature's lag from there (1e-10)."""
    path, md = native2
    reals = balance_values(name)
    r = Run(path, md, {**reals, "T_supply": T_S, **dict(zip(IN, STATE))})
    try:
        r.f.exitInitializationMode()
        out = r.get(("T_eff", "mu_eff", "P_loss", "Q_side"))
        oil, params, report = python_balance(md, reals)
        T, mu_eff, _tau = film_temperature(params, report, oil, T_S)
        assert out[0] == pytest.approx(T, rel=1e-10) and out[1] == pytest.approx(mu_eff, rel=1e-10)
        assert abs(energy_residual(out, oil, report.inflow_m3_s)) <= 1e-9
        nxt = trajectory()[4]
        r.step(nxt, 2e-3)
        want = film_temperature(params, Reynolds(params, GRID["n_theta"], GRID["n_x"]).film_report(*nxt), oil, T_S,
                                float(out[0]), 2e-3)
        assert r.get(("T_eff", "mu_eff")) == pytest.approx(want[:2], rel=1e-10) and want[0] != out[0]
    finally:
        r.close()


@pytest.mark.parametrize("name", ["full with ambient", "ambient at supply"])
def test_native_fmu_equals_the_python_fmu(native2, fmu, name):
    """The same run (the journal on a spiral, the supply rising by 0.5 K a step) through both FMUs with
    the balance's parameters: T_eff, mu_eff, P_loss, Q_side and the force within 1e-12 of each output's
    largest value."""
    path, md = native2
    rows = both_runs(native2, fmu, {**parameters(md), **balance_values(name)}, trajectory(6))
    scale = np.max(np.abs(rows["python"]), axis=0)
    assert np.max(np.abs(rows["native"] - rows["python"]) / scale) <= 1e-12


def both_runs(native, fmu, reals: dict, states) -> dict:
    """{"native", "python"}: the outputs Fy, Fz, T_eff, mu_eff, P_loss, Q_side over ``states`` (Co-Simulation,
    steps of 1 ms, the supply rising 0.5 K a step from T_S) through the native FMU ``native`` (path, model
    description) and the Python FMU ``fmu`` (the Reynolds internal on GRID), both with the Real ``reals``."""
    outs = ("Fy", "Fz", "T_eff", "mu_eff", "P_loss", "Q_side")
    rows = {}
    for which, (f, m) in {"native": native, "python": (fmu, fmpy.read_model_description(str(fmu)))}.items():
        strings = {"internal": "reynolds", "oil_law": "walther"} if which == "python" else None
        r = Run(f, m, {**reals, "T_supply": T_S, **dict(zip(IN, states[0]))}, strings)
        try:
            if which == "python":
                r.f.setInteger([r.vr["n_theta"], r.vr["n_x"]], [GRID["n_theta"], GRID["n_x"]])
            r.f.exitInitializationMode()
            got = [r.get(outs)]
            for k, s in enumerate(states[1:], 1):
                r.set({"T_supply": T_S + 0.5 * k})
                r.step(s, 1e-3)
                got.append(r.get(outs))
            rows[which] = np.array(got)
        finally:
            r.close()
    return rows


def python_rate(md, reals, T) -> float:
    """der(T_eff) [K/s] at the film temperature T by Python: (T_supply + k dT(mu(T)) - T) / t_res, dT the
    heat balance at the film report scaled to mu(T) (physics.thermal.temperature_rise, film.at_viscosity)."""
    from bearing_fmu.physics.solver.film import at_viscosity
    from bearing_fmu.physics.thermal import residence_time_s, temperature_rise

    oil, params, report = python_balance(md, reals)
    rise = temperature_rise(at_viscosity(report, oil.mu(T) / params.mu), oil, T_S)
    return (T_S + oil.rise_factor * rise - T) / residence_time_s(params, report)


@pytest.mark.parametrize("name", ["full", "ambient"])
def test_native_model_exchange_rate_is_pythons(native2, name):
    """Model Exchange: T_eff the state; der(T_eff) at the states set is the heat balance's rate by Python
    (1e-10 of the rate's scale, 1 K over the residence time); at the quasi-static start it is ~0."""
    import ctypes

    path, md = native2
    reals = balance_values(name)
    r = Run(path, md, {**reals, "T_supply": T_S, **dict(zip(IN, STATE))}, kind="ME")
    try:
        r.f.exitInitializationMode()
        T0 = float(r.get(["T_eff"])[0])
        r.f.enterContinuousTimeMode()
        buf = np.zeros(1)
        _oil, params, report = python_balance(md, reals)
        from bearing_fmu.physics.thermal import residence_time_s

        scale = 1.0 / residence_time_s(params, report)
        for T in (T0, T0 + 5.0, T0 - 3.0):
            r.set_state(T)
            r.f.getDerivatives(buf.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), 1)
            assert abs(buf[0] - python_rate(md, reals, T)) <= 1e-10 * scale, T
        assert abs(python_rate(md, reals, T0)) <= 1e-8 * scale
    finally:
        r.close()


@pytest.mark.parametrize("name", ["ambient", "ambient at supply"])
def test_native_derivatives_along_the_supply_and_the_state(native2, name):
    """The directional derivatives (analytic: bearing_derivatives.c, the loss's shift in them) against
    central differences of the outputs (steps 1e-5 K, 1e-5 CR as tests/test_native_fmu_thermal.py's), within
    1e-6 (its DD_RTOL): in Initialization Mode
    (quasi-static) of T_eff, mu_eff, P_loss along T_supply and y; in Model Exchange's continuous-time mode,
    T_eff the state 4 K off the balance, of der(T_eff) along T_supply, y and T_eff. The ambient at the
    supply (oil_T_ambient 0) moves with T_supply, a fixed one does not."""
    import ctypes

    path, md = native2
    reals = balance_values(name)
    r = Run(path, md, {**reals, "T_supply": T_S, **dict(zip(IN, STATE))}, kind="ME")
    steps = (("T_supply", T_S, 1e-5), ("y", STATE[0], 1e-5 * 90e-6))
    try:
        outs = ("T_eff", "mu_eff", "P_loss")
        for known, x, h in steps:
            got = r.dd(outs, [known], [1.0])
            want = central(r, outs, known, x, h, lambda: r.get(outs))
            assert np.all(np.abs(got - want) <= 1e-6 * np.abs(want)), (known, got, want)
        r.f.exitInitializationMode()
        r.f.enterContinuousTimeMode()
        T = float(r.get(["T_eff"])[0]) + 4.0
        r.set_state(T)
        buf = np.zeros(1)
        ptr = buf.ctypes.data_as(ctypes.POINTER(ctypes.c_double))

        def rate():
            r.f.getDerivatives(ptr, 1)
            return np.array([buf[0]])

        for known, x, h in (*steps, ("T_eff", T, 1e-3)):
            got = r.dd(["der(T_eff)"], [known], [1.0])
            want = central(r, ["der(T_eff)"], known, x, h, rate)
            assert abs(got[0] - want[0]) <= 1e-6 * abs(want[0]), (known, got, want)
    finally:
        r.close()


def test_native_fmu_refuses_another_outflow_share(native2):
    from fmpy.fmi1 import FMICallException

    path, md = native2
    r = Run(path, md, {"T_supply": T_S})
    try:
        with pytest.raises(FMICallException):
            r.set({"oil_outflow_share": 0.25})
    finally:
        r.f.freeInstance()


# ----------------------------------------------------------------------------- a circumferential groove

GROOVE = dict(D=0.040, L=0.045, CR=42e-6, width=0.005, ps=200e3)  # tests/test_native_peak.py's grooved bearing


def grooved_bearing() -> BearingParams:
    """The grooved bearing with the VG 46 oil, its balance the full rise (as params.groove_problem demands)."""
    from bearing_fmu.physics.bore.geometry import Geometry

    oil = replace(VG46, outflow_rise="full")
    return BearingParams(D=GROOVE["D"], L=GROOVE["L"], CR=GROOVE["CR"], mu=oil.mu(oil.T_supply), oil=oil,
                         geometry=Geometry(circumferential_groove=GROOVE["width"], supply_pressure=GROOVE["ps"]))


def grooved_spiral(n=6):
    CR, out = GROOVE["CR"], []
    for k in range(n):
        a, e, w = 0.3 * k, 0.4 + 0.03 * k, 280.0 + 15.0 * k
        out.append((e * CR * math.sin(a), -e * CR * math.cos(a), 0.01 * w * CR * math.cos(a),
                    0.01 * w * CR * math.sin(a), w))
    return out


@pytest.fixture(scope="module")
def grooved2(tmp_path_factory, native_build_cache):
    """(the native Reynolds FMU (FMI 2.0) of the grooved bearing with its oil, its model description)."""
    from bearing_fmu.fmu.native.build import build_native_fmu

    target = tmp_path_factory.mktemp("native_groove_balance") / "reynolds_groove_vg46.fmu"
    path = native_build_cache(target, lambda t: build_native_fmu(t, "reynolds", bearing=grooved_bearing(),
                                                                 options=GRID, compiler="cc"),
                              [], ("groove balance", "reynolds", tuple(GRID.items()), tuple(GROOVE.items())))
    return path, fmpy.read_model_description(str(path))


def test_grooved_native_fmu_thermal_is_the_full_rise(grooved2):
    """thermal = true on the grooved native Reynolds FMU (refused before: its balance was the half rise's):
    oil_outflow_share starts at 0 (the file's 'full'); the quasi-static T_eff, mu_eff equal
    film_temperature's on the lands (1e-10), and the full-rise balance P = rho c_p Q dT with Q = Q_side (the
    groove delivers what leaves by the ends) closes at the outputs alone (1e-9)."""
    path, md = grooved2
    var = {v.name: v for v in md.modelVariables}
    assert float(var["oil_outflow_share"].start) == 0.0 and float(var["circumferential_groove"].start) == 0.005
    params = grooved_bearing()
    state = grooved_spiral()[2]
    r = Run(path, md, {"T_supply": T_S, **dict(zip(IN, state))})
    try:
        r.f.exitInitializationMode()
        out = r.get(("T_eff", "mu_eff", "P_loss", "Q_side"))
        report = Reynolds(params, GRID["n_theta"], GRID["n_x"]).film_report(*state)
        T, mu_eff, _tau = film_temperature(params, report, params.oil, T_S)
        assert out[0] == pytest.approx(T, rel=1e-10) and out[1] == pytest.approx(mu_eff, rel=1e-10)
        assert out[0] - T_S > 0.5  # the film runs hot
        oil = params.oil
        rise = (out[0] - T_S) / oil.rise_factor
        assert abs(out[2] - oil.density * oil.heat_capacity * out[3] * rise) <= 1e-9 * out[2]
    finally:
        r.close()


@pytest.mark.parametrize("share", [0.0, 0.5])
def test_grooved_native_fmu_equals_the_python_fmu(grooved2, fmu, share):
    """The same grooved run (a spiral, the supply rising 0.5 K a step) through the native and the Python FMU:
    T_eff, mu_eff, P_loss, Q_side and the force within 1e-10 of each output's largest value (the lands' C
    solver equals Python's to 1e-12, tests/test_native_peak.py). oil_outflow_share = 0.5 set on both: the
    groove's balance is the full rise still (both FMUs), the same rows as with 0."""
    path, md = grooved2
    params = grooved_bearing()
    reals = {**parameters(md), "circumferential_groove": GROOVE["width"], "supply_pressure": GROOVE["ps"],
             "oil_outflow_share": share}
    rows = both_runs(grooved2, fmu, reals, grooved_spiral())
    scale = np.max(np.abs(rows["python"]), axis=0)
    assert np.max(np.abs(rows["native"] - rows["python"]) / scale) <= 1e-10
    report = Reynolds(params, GRID["n_theta"], GRID["n_x"]).film_report(*grooved_spiral()[0])
    assert rows["native"][0, 2] == pytest.approx(film_temperature(params, report, params.oil, T_S)[0], rel=1e-10)
