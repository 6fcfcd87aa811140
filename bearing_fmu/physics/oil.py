"""The oil: viscosity as a function of temperature, density and heat capacity (the bearing
file's ``[oil]`` table; docs/thermal.md).

Laws (T in kelvin everywhere inside):

* ``walther`` -- ASTM D341 (Standard practice for viscosity-temperature equations and charts of
  liquid petroleum or hydrocarbon products; Walther's equation):
      log10(log10(nu + 0.7)) = A - B log10(T),   nu kinematic viscosity [mm^2/s = cSt]
  through two points (nu1 at T1, nu2 at T2). The simple form with 0.7 holds for nu >= 2 cSt
  (D341 adds small terms below); a law whose range reaches below 2 cSt is refused.
* ``vogel`` -- mu = a exp(b / (T - c)) (Vogel 1921; the Vogel-Fulcher-Tammann form), a [Pa s],
  b, c [K]; T must stay above c.
* a ``grade`` preset (``PRESETS``: named records, each law's data with its units and where
  they come from): ISO VG 32 and ISO VG 46 by Walther through two typical points of a turbine
  oil of viscosity index about 100, SAE 30 by Shigley's Vogel fit. For any other oil, give its
  data sheet's two points.

mu [Pa s] = rho nu with a constant density. Defaults rho = 861 kg/m^3 and c_p = 1760 J/(kg K):
the oil of Shigley's Mechanical Engineering Design (chapter 12, the SI temperature-rise equation
Delta T = 8.30 P (r/c) f / [(1 - Qs / 2Q) Q / (r c N l)] with P in MPa: 8.30 = 4 pi / (rho c_p)
in K/MPa), the same constant 8.3 as in Jindal's Machine Design. A real oil's density falls by
about 0.07 % per K and its c_p rises by about 0.2 % per K: neither is modelled (docs/thermal.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..io.schema import Choice, Invalid, Key, Kind, List, Number

__all__ = ["Oil", "OilPreset", "OIL_KEYS", "PRESETS", "GRADES", "KELVIN", "oil_from_table"]

KELVIN = 273.15
WALTHER_MIN_CST = 2.0  # below, D341's simple form (nu + 0.7) is no longer the standard's equation
DEFAULT_DENSITY = 861.0  # kg/m^3, Shigley ch. 12 (see the module docstring)
DEFAULT_HEAT_CAPACITY = 1760.0  # J/(kg K), the same
DEFAULT_RANGE_C = (0.0, 150.0)  # a mineral oil's working range: below 0 C it thickens fast, above
                                # 150 C it oxidises; widen it in the file for another oil

# the viscosity any law may give over its range [Pa s]: water's tenth to a bitumen's (a lubricant
# is 1e-3 .. 10; beyond this a law's coefficients are a typo, and exp() overflows near 1e308)
MU_RANGE_PA_S = (1e-5, 1e6)

@dataclass(frozen=True)
class OilPreset:
    """A named oil of the ``grade`` key: its viscosity law's data in the units of the [oil]
    table's keys, and where the numbers come from. Exactly one law: Walther (``nu_cSt`` at
    ``temperatures_C``) or Vogel (``vogel_a_Pa_s``, ``vogel_b_K``, ``vogel_c_K``).

    name           : the grade, as the bearing file writes it
    nu_cSt         : Walther: kinematic viscosities [cSt = mm^2/s] at ``temperatures_C`` [C]
    vogel_a_Pa_s   : Vogel law mu = a exp(b / (T - c)): a [Pa s]; ``vogel_b_K`` b [K]; ``vogel_c_K`` c [K]
    source         : the sources of the numbers
    """

    name: str
    source: str
    nu_cSt: tuple[float, float] | None = None
    temperatures_C: tuple[float, float] | None = None
    vogel_a_Pa_s: float | None = None
    vogel_b_K: float | None = None
    vogel_c_K: float | None = None

    @property
    def law(self) -> str:
        return "walther" if self.nu_cSt is not None else "vogel"

    def oil(self, **kw) -> "Oil":
        """The preset as an ``Oil`` (``kw``: the other fields of ``Oil``: range, density, ...)."""
        kw.setdefault("name", self.name)
        if self.law == "vogel":
            return Oil.vogel(self.vogel_a_Pa_s, self.vogel_b_K, self.vogel_c_K, **kw)
        (nu1, nu2), (t1, t2) = self.nu_cSt, self.temperatures_C
        return Oil.walther(nu1, t1 + KELVIN, nu2, t2 + KELVIN, **kw)


_ISO_VG_SOURCE = ("40 C: the grade's mid-point (ISO 3448, Industrial liquid lubricants -- ISO viscosity "
                  "classification); 100 C: a turbine oil of viscosity index about 100 as the ROSS project quotes "
                  "it for this grade (github.com/petrobras/ross issue 37)")
# the grade presets, in the order the documentation lists them (docs/thermal.md: generated from these)
PRESETS = (
    OilPreset("ISO VG 32", _ISO_VG_SOURCE, nu_cSt=(32.0, 5.4), temperatures_C=(40.0, 100.0)),
    OilPreset("ISO VG 46", _ISO_VG_SOURCE, nu_cSt=(46.0, 6.8), temperatures_C=(40.0, 100.0)),
    # Shigley's mu = 0.0141 exp(1360 / (T_F + 95)) micro-reyn, T_F in F, in SI: a micro-reyn is
    # 6894.757e-6 Pa s, T_F + 95 = 1.8 (T - c) with c = 273.15 - (95 + 32) / 1.8 K
    OilPreset("SAE 30", "Shigley's Mechanical Engineering Design, Table 12-1 (Seireg & Dandage's fit): mu = "
              "0.0141 exp(1360 / (T_F + 95)) micro-reyn, T_F in F; its solutions manual (problem 12-20) gives "
              "15.2 mPa s at 79 C from it",
              vogel_a_Pa_s=0.0141e-6 * 6894.757, vogel_b_K=1360.0 / 1.8, vogel_c_K=KELVIN - 127.0 / 1.8),
)
GRADES = {p.name: p for p in PRESETS}

OUTFLOW_RISES = ("half", "full")  # the side flow's share of the rise: 1/2 or 1 (``Oil.outflow_share``)
CAVITATED_SHEARS = ("full", "striated")  # or a fraction in [0, 1] (``physics.solver.film.cavitated_relief``)


@dataclass(frozen=True)
class ShearKind(Kind):
    """The [oil] key cavitated_shear: 'full', 'striated' or a number 0 .. 1."""

    def expected(self) -> str:
        return "'full', 'striated' or a number 0 .. 1"

    def check(self, value, where, label, error):
        if isinstance(value, str) and value in CAVITATED_SHEARS:
            return value
        if isinstance(value, (int, float)) and not isinstance(value, bool) and 0.0 <= value <= 1.0:
            return float(value)
        raise Invalid(f" must be {self.expected()}")

# the keys of the [oil] table; exactly one law: grade, or nu_cSt with temperatures_C, or the
# three vogel_ keys
OIL_KEYS = (
    Key("grade", "a preset: ISO VG grades by Walther (ASTM D341) through typical viscosities at 40 and 100 C, "
        "SAE 30 by Shigley's Vogel fit (physics/oil.py gives the sources)", None,
        kind=Choice(tuple(p.name for p in PRESETS))),
    Key("nu_cSt", "kinematic viscosities at temperatures_C [cSt = mm^2/s] (Walther, ASTM D341)", None,
        "2 numbers > 0, falling with temperature", kind=List(Number(0.0, exclusive_minimum=True), length=2)),
    Key("temperatures_C", "the temperatures of nu_cSt [C]", None, "2 different numbers",
        kind=List(Number(-100.0, 400.0), length=2)),
    Key("vogel_a_Pa_s", "Vogel law mu = a exp(b / (T - c)): a [Pa s]", None, "> 0",
        kind=Number(0.0, exclusive_minimum=True)),
    Key("vogel_b_K", "Vogel law: b [K]", None, "> 0", kind=Number(0.0, exclusive_minimum=True)),
    Key("vogel_c_K", "Vogel law: c [K] (T must stay above it)", None, ">= 0", kind=Number(0.0)),
    Key("range_C", "temperatures the law may be used at [C]; outside, it is refused", list(DEFAULT_RANGE_C),
        "[low, high], low < high", kind=List(Number(-100.0, 400.0), length=2)),
    Key("density_kg_m3", "oil density (constant) [kg/m^3]", DEFAULT_DENSITY, "500 .. 2000",
        kind=Number(500.0, 2000.0)),
    Key("heat_capacity_J_kgK", "specific heat capacity (constant) [J/(kg K)]", DEFAULT_HEAT_CAPACITY,
        "500 .. 5000", kind=Number(500.0, 5000.0)),
    Key("supply_C", "oil supply temperature when a scene gives none [C]; the bearing's isothermal viscosity "
        "is the oil's at it", 40.0, "inside range_C", kind=Number(-100.0, 400.0)),
    Key("rise_factor", "k in T_eff = T_supply + k dT (Raimondi & Boyd, Shigley: 1/2, the mean of inlet and "
        "outlet)", 0.5, "0 .. 1", kind=Number(0.0, 1.0)),
    Key("outflow_rise", "the side flow leaves at 'half' the rise (Raimondi & Boyd, Shigley: P = rho c_p (Q - Qs / 2) "
        "dT) or at the 'full' rise (all the inflow heated by dT: P = rho c_p Q dT)", "half", "half or full",
        kind=Choice(OUTFLOW_RISES)),
    Key("ambient_W_K", "heat the bearing loses to the ambient per kelvin of T_eff above ambient_C [W/K] (a "
        "housing's h A; 0: adiabatic, all the friction power into the oil)", 0.0, ">= 0", kind=Number(0.0)),
    Key("ambient_C", "the ambient's temperature for ambient_W_K [C]; absent: the supply temperature", None,
        "a temperature", kind=Number(-100.0, 400.0)),
    Key("cavitated_shear", "how the cavitated film shears the journal in the friction: 'full' (a full film, as "
        "Raimondi & Boyd), 'striated' (oil striations carrying the film's Couette flow at rupture: the fraction "
        "h_rupture / h of the gap) or a fixed fraction 0 .. 1 of the full film's shear (the Reynolds internal's "
        "pressure field tells the cavitated cells)", "full", "full, striated or 0 .. 1", kind=ShearKind()),
)


@dataclass(frozen=True)
class Oil:
    """An oil's viscosity law and properties, SI (temperatures in K). Build with ``Oil.walther``,
    ``Oil.vogel`` or ``Oil.grade``; ``mu(T)`` refuses a temperature outside [T_min, T_max].

    law         : "walther" or "vogel"
    coefficients: walther (A, B) of log10(log10(nu_cSt + 0.7)) = A - B log10(T); vogel (a [Pa s], b [K], c [K])
    T_min, T_max: the range the law may be used in [K]
    density     : [kg/m^3]; heat_capacity : [J/(kg K)]
    T_supply    : the supply temperature a bearing file gives (its isothermal viscosity's) [K]
    rise_factor : k in T_eff = T_supply + k dT
    outflow_rise: "half" (the side flow leaves at half the rise) or "full" (all the inflow at the full rise)
    cavitated_shear: "full", "striated" or a fraction in [0, 1]: the cavitated film's shear in the friction
    ambient_W_K : heat lost to the ambient per kelvin of T_eff above T_ambient [W/K] (0: adiabatic)
    T_ambient   : the ambient's temperature [K]; None: the supply temperature
    name        : how messages call it ("ISO VG 32", "oil of bearing.toml")
    """

    law: str
    coefficients: tuple[float, ...]
    T_min: float = DEFAULT_RANGE_C[0] + KELVIN
    T_max: float = DEFAULT_RANGE_C[1] + KELVIN
    density: float = DEFAULT_DENSITY
    heat_capacity: float = DEFAULT_HEAT_CAPACITY
    T_supply: float = 40.0 + KELVIN
    rise_factor: float = 0.5
    outflow_rise: str = "half"
    ambient_W_K: float = 0.0
    T_ambient: float | None = None
    name: str = "oil"
    cavitated_shear: str | float = "full"

    def __post_init__(self) -> None:
        if self.law not in ("walther", "vogel"):
            raise ValueError(f"Oil: law must be 'walther' or 'vogel', got {self.law!r}")
        object.__setattr__(self, "coefficients", tuple(float(c) for c in self.coefficients))
        for name in ("T_min", "T_max", "density", "heat_capacity", "T_supply", "rise_factor"):
            v = float(getattr(self, name))
            if not math.isfinite(v):
                raise ValueError(f"Oil {self.name}: {name} = {v!r} must be finite")
            object.__setattr__(self, name, v)
        if not 0.0 < self.T_min < self.T_max:
            raise ValueError(f"Oil {self.name}: the range {_c(self.T_min)} .. {_c(self.T_max)} must have "
                             "0 K < low < high (range_C)")
        if self.density <= 0.0 or self.heat_capacity <= 0.0:
            raise ValueError(f"Oil {self.name}: density and heat capacity must be > 0")
        if not 0.0 <= self.rise_factor <= 1.0:
            raise ValueError(f"Oil {self.name}: rise_factor = {self.rise_factor:g} must be in 0 .. 1")
        if self.outflow_rise not in OUTFLOW_RISES:
            raise ValueError(f"Oil {self.name}: outflow_rise = {self.outflow_rise!r} must be one of "
                             f"{', '.join(OUTFLOW_RISES)}")
        if not (math.isfinite(self.ambient_W_K) and self.ambient_W_K >= 0.0):
            raise ValueError(f"Oil {self.name}: ambient_W_K = {self.ambient_W_K!r} must be finite and >= 0")
        c = self.cavitated_shear
        if isinstance(c, (int, float)) and not isinstance(c, bool):
            c = float(c)
            object.__setattr__(self, "cavitated_shear", c)
        if not (c in CAVITATED_SHEARS if isinstance(c, str) else (isinstance(c, float) and 0.0 <= c <= 1.0)):
            raise ValueError(f"Oil {self.name}: cavitated_shear = {c!r} must be 'full', 'striated' or a number 0 .. 1")
        if self.T_ambient is not None and not (math.isfinite(self.T_ambient) and self.T_ambient > 0.0):
            raise ValueError(f"Oil {self.name}: ambient_C = {self.T_ambient - KELVIN!r} must be finite and above "
                             "absolute zero")
        if self.law == "vogel":
            a, b, c = self.coefficients
            if not (a > 0.0 and b > 0.0 and c >= 0.0):
                raise ValueError(f"Oil {self.name}: the Vogel law needs a > 0, b > 0, c >= 0 (vogel_a_Pa_s, "
                                 f"vogel_b_K, vogel_c_K), got {a:g}, {b:g}, {c:g}")
            if not self.T_min > c:
                raise ValueError(f"Oil {self.name}: the Vogel law diverges at T = c = {c:g} K ({_c(c)}); its "
                                 f"range must start above it, not at {_c(self.T_min)} (range_C)")
        else:
            nu_top = self.nu(self.T_max) * 1e6
            if nu_top < WALTHER_MIN_CST:
                raise ValueError(f"Oil {self.name}: at {_c(self.T_max)}, the top of its range (range_C), the "
                                 f"Walther law gives {nu_top:.3g} cSt, below the {WALTHER_MIN_CST:g} cSt where "
                                 "ASTM D341's simple form holds: lower the range's top")
        self._check_viscosity_range()
        if not self.T_min <= self.T_supply <= self.T_max:
            raise ValueError(f"Oil {self.name}: supply_C = {_c(self.T_supply)} is outside its range "
                             f"{_c(self.T_min)} .. {_c(self.T_max)} (range_C)")

    def _check_viscosity_range(self) -> None:
        """ValueError naming the law's keys unless mu stays within MU_RANGE_PA_S over the range (the
        law is monotonic: its ends bound it; evaluated in logs, so a steep law cannot overflow)."""
        lo, hi = MU_RANGE_PA_S
        if self.law == "vogel":
            a, b, c = self.coefficients
            log_mu = math.log(a) + b / (self.T_min - c)  # the largest, at the range's bottom
            law = f"Oil {self.name}: the Vogel law (vogel_a_Pa_s = {a:g}, vogel_b_K = {b:g}, vogel_c_K = {c:g}) gives"
            if log_mu > math.log(hi):
                b_max = math.log(hi / a) * (self.T_min - c)
                raise ValueError(f"{law} mu = exp({log_mu:.4g}) Pa s at {_c(self.T_min)}, the bottom of its range "
                                 f"(range_C), above {hi:g} Pa s: "
                                 + (f"vogel_b_K at most {b_max:.6g} K with these a, c and range" if b_max > 0.0
                                    else "lower vogel_a_Pa_s"))
            mu_top = a * math.exp(b / (self.T_max - c))  # the smallest: b > 0, so no overflow below log_mu
            if mu_top < lo:
                raise ValueError(f"{law} mu = {mu_top:.4g} Pa s at {_c(self.T_max)}, the top of its range (range_C), "
                                 f"below {lo:g} Pa s: raise vogel_a_Pa_s or vogel_b_K, or lower the range's top")
            return
        try:
            mu_lo, mu_hi = self._mu(self.T_max), self._mu(self.T_min)
        except OverflowError:
            mu_lo, mu_hi = 0.0, math.inf
        if not (lo <= mu_lo and mu_hi <= hi):
            raise ValueError(f"Oil {self.name}: the Walther law (nu_cSt, temperatures_C) gives mu = {mu_hi:.4g} Pa s "
                             f"at {_c(self.T_min)}, the bottom of its range (range_C), and {mu_lo:.4g} Pa s at its top: "
                             f"outside {lo:g} .. {hi:g} Pa s; narrow range_C")

    # ------------------------------------------------------------------ building
    @classmethod
    def walther(cls, nu1_cSt: float, T1_K: float, nu2_cSt: float, T2_K: float, **kw) -> "Oil":
        """Walther (ASTM D341) through two points: kinematic viscosities [cSt] at temperatures [K]."""
        name = kw.get("name", "oil")
        (n1, t1), (n2, t2) = sorted([(float(nu1_cSt), float(T1_K)), (float(nu2_cSt), float(T2_K))],
                                    key=lambda p: p[1])
        if not (n1 > 0.0 and n2 > 0.0 and t1 > 0.0):
            raise ValueError(f"Oil {name}: viscosities must be > 0 cSt and temperatures > 0 K (nu_cSt, "
                             f"temperatures_C), got {n1:g}, {n2:g} cSt at {_c(t1)}, {_c(t2)}")
        if t1 == t2:
            raise ValueError(f"Oil {name}: the two temperatures must differ (temperatures_C), got {_c(t1)} twice")
        if not n1 > n2:
            raise ValueError(f"Oil {name}: the viscosity must fall as the temperature rises (nu_cSt, "
                             f"temperatures_C): {n1:g} cSt at {_c(t1)}, {n2:g} cSt at {_c(t2)}")
        if min(n1, n2) < WALTHER_MIN_CST:
            raise ValueError(f"Oil {name}: {min(n1, n2):g} cSt is below the {WALTHER_MIN_CST:g} cSt where ASTM "
                             "D341's simple form holds (nu_cSt)")
        w1, w2 = math.log10(math.log10(n1 + 0.7)), math.log10(math.log10(n2 + 0.7))
        B = (w1 - w2) / (math.log10(t2) - math.log10(t1))
        A = w1 + B * math.log10(t1)
        return cls("walther", (A, B), **kw)

    @classmethod
    def vogel(cls, a_Pa_s: float, b_K: float, c_K: float, **kw) -> "Oil":
        """Vogel law mu = a exp(b / (T - c)) [Pa s], T in K."""
        return cls("vogel", (a_Pa_s, b_K, c_K), **kw)

    @classmethod
    def grade(cls, grade: str, **kw) -> "Oil":
        """A preset of ``PRESETS`` by name (``GRADES[grade].oil(**kw)``)."""
        if grade not in GRADES:
            raise ValueError(f"Oil: unknown grade {grade!r}; choose one of {', '.join(GRADES)}")
        return GRADES[grade].oil(**kw)

    # ------------------------------------------------------------------ properties
    def check_temperature(self, T_K: float, what: str = "T") -> float:
        """T_K as a float, or ValueError naming the oil, the value and its range."""
        T = float(T_K)
        if not (math.isfinite(T) and self.T_min <= T <= self.T_max):
            shown = f"{T:.6g} K ({_c(T)})" if math.isfinite(T) else repr(T)
            raise ValueError(f"Oil {self.name}: {what} = {shown} is outside the viscosity law's range "
                             f"{_c(self.T_min)} .. {_c(self.T_max)} (the bearing file's [oil] range_C)")
        return T

    def nu(self, T_K: float) -> float:
        """Kinematic viscosity [m^2/s] at T_K [K] (no range check: ``mu`` checks)."""
        return self._mu(float(T_K)) / self.density

    def _mu(self, T: float) -> float:
        if self.law == "walther":
            A, B = self.coefficients
            return (10.0 ** (10.0 ** (A - B * math.log10(T))) - 0.7) * 1e-6 * self.density
        a, b, c = self.coefficients
        return a * math.exp(b / (T - c))

    def mu(self, T_K: float) -> float:
        """Dynamic viscosity [Pa s] at T_K [K]; ValueError outside [T_min, T_max]."""
        return self._mu(self.check_temperature(T_K))

    @property
    def outflow_share(self) -> float:
        """s in the heat the oil carries away, rho c_p (Q - s Qs) dT: 1/2 when the side flow leaves at half
        the rise, 0 when all the inflow leaves at the full rise."""
        return 0.5 if self.outflow_rise == "half" else 0.0

    def describe(self) -> str:
        """The law in a few words (for the demo and messages)."""
        law = ("Walther (ASTM D341)" if self.law == "walther" else "Vogel")
        return (f"{self.name}: {law}, {self.mu(40.0 + KELVIN) * 1e3:.4g} mPa s at 40 C"
                if self.T_min <= 40.0 + KELVIN <= self.T_max else f"{self.name}: {law}")


def _c(T_K: float) -> str:
    return f"{T_K - KELVIN:.6g} C"


def oil_from_table(d: dict, given: set, name: str, error) -> Oil:
    """The [oil] table's schema-checked values ``d`` (``OIL_KEYS``; ``given`` the keys the file
    wrote) as an Oil; ``error(text)`` makes the exception (naming the file)."""
    walther = {"nu_cSt", "temperatures_C"} & given
    vogel = {"vogel_a_Pa_s", "vogel_b_K", "vogel_c_K"} & given
    laws = [w for w, on in (("grade", "grade" in given), ("nu_cSt with temperatures_C", bool(walther)),
                            ("vogel_a_Pa_s, vogel_b_K, vogel_c_K", bool(vogel))) if on]
    if len(laws) != 1:
        raise error("give exactly one viscosity law: grade, or nu_cSt with temperatures_C, or vogel_a_Pa_s, "
                    "vogel_b_K, vogel_c_K" + (f" (given: {'; '.join(laws)})" if laws else " (none given)"))
    if walther and walther != {"nu_cSt", "temperatures_C"}:
        raise error(f"{'nu_cSt' if 'nu_cSt' in walther else 'temperatures_C'} needs "
                    f"{'temperatures_C' if 'nu_cSt' in walther else 'nu_cSt'} (two viscosities at two temperatures)")
    if vogel and len(vogel) != 3:
        raise error(f"the Vogel law needs vogel_a_Pa_s, vogel_b_K and vogel_c_K (missing: "
                    f"{', '.join(sorted({'vogel_a_Pa_s', 'vogel_b_K', 'vogel_c_K'} - vogel))})")
    lo, hi = d["range_C"]
    kw = dict(T_min=lo + KELVIN, T_max=hi + KELVIN, density=d["density_kg_m3"],
              heat_capacity=d["heat_capacity_J_kgK"], T_supply=d["supply_C"] + KELVIN,
              rise_factor=d["rise_factor"], outflow_rise=d["outflow_rise"], ambient_W_K=d["ambient_W_K"],
              T_ambient=None if d["ambient_C"] is None else d["ambient_C"] + KELVIN, name=name,
              cavitated_shear=d["cavitated_shear"])
    if not lo < hi:
        raise error(f"range_C = [{lo:g}, {hi:g}] must have low < high")
    try:
        if "grade" in given:
            kw["name"] = f"{d['grade']} ({name})"
            return Oil.grade(d["grade"], **kw)
        if walther:
            (n1, n2), (t1, t2) = d["nu_cSt"], d["temperatures_C"]
            return Oil.walther(n1, t1 + KELVIN, n2, t2 + KELVIN, **kw)
        return Oil.vogel(d["vogel_a_Pa_s"], d["vogel_b_K"], d["vogel_c_K"], **kw)
    except ValueError as exc:
        raise error(str(exc).removeprefix(f"Oil {kw['name']}: ")) from None
