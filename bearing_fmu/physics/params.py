"""Bearing geometry and lubricant, validated once, in SI units."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..io.schema import Key, Number, Table, Text, check_keys, check_table, read_toml, show
from .bore.geometry import FULL_BORE, GEOMETRY_KEYS, Geometry
from .oil import OIL_KEYS, Oil, oil_from_table

# ----------------------------------------------------------------------------- physical ranges
# What a real plain journal bearing can be; values outside are typos or unit slips (a clearance
# in mm where m was meant), and some (CR = 1e-300) would only end in a division by zero deep in
# the Reynolds kernel. The ranges are wide on purpose: they refuse nonsense, not unusual designs.
#
# D   1 mm .. 5 m     instrument spindles and micro-turbines have journals of a few mm; hydro-
#                     generator guide bearings, mill and ship stern-tube bearings reach 1-3 m.
# L/D 0.05 .. 5       squeeze-film dampers and very short bearings go to L/D ~ 0.1, stern tubes
#                     to ~ 4; shorter is a seal land rather than a bearing, longer a bush no
#                     shaft stays aligned in.
# CR/R 1e-5 .. 0.05   the clearance ratio: about 1e-3 for most oil bearings, 1e-4 for precision
#                     spindles, 5.8e-3 for the paper's bearing. Below 1e-5 the film (0.15 um
#                     at the paper's 15.5 mm radius) is thinner than a ground journal's
#                     roughness; above 0.05 the thin-film assumption behind Reynolds'
#                     equation (film thickness << radius, curvature dropped) no longer holds.
# mu  1e-5 .. 10 Pa s cryogenic liquids (liquid hydrogen 1.3e-5, liquid nitrogen 1.6e-4), water
#                     (1e-3), oils (1e-3 .. 1) up to a heavy gear oil cold (a few Pa s). Gases
#                     (air 1.8e-5) are inside but compressible: this incompressible model only
#                     approximates them.
D_RANGE_M = (1e-3, 5.0)
L_OVER_D_RANGE = (0.05, 5.0)
CR_OVER_R_RANGE = (1e-5, 0.05)
MU_RANGE_PA_S = (1e-5, 10.0)

_UNITS = {"D": "m", "L": "m", "CR": "m", "mu": "Pa s"}


def _length(x: float) -> str:
    """A length [m] with a readable prefix: 0.031 -> '31 mm', 9e-05 -> '90 um'."""
    a = abs(x)
    for scale, unit in ((1.0, "m"), (1e-3, "mm"), (1e-6, "um"), (1e-9, "nm")):
        if a >= scale:
            return f"{x / scale:.4g} {unit}"
    return f"{x:.4g} m"


def _quantity(name: str, x: float) -> str:
    return _length(x) if _UNITS[name] == "m" else f"{x:.4g} {_UNITS[name]}"


def allowed_range(name: str, D: float | None = None) -> tuple[float, float, str]:
    """(low, high, words) of BearingParams field ``name`` in SI; L and CR scale with the
    diameter D [m] (the words then give both the ratio and the bounds at that D)."""
    if name == "D":
        lo, hi = D_RANGE_M
        return lo, hi, f"{_length(lo)} .. {_length(hi)}"
    if name == "mu":
        lo, hi = MU_RANGE_PA_S
        return lo, hi, f"{lo:g} .. {hi:g} Pa s"
    if name == "L":
        ratio, ref, label = L_OVER_D_RANGE, D, "L/D"
    else:
        ratio, ref, label = CR_OVER_R_RANGE, None if D is None else D / 2, "CR/R"
    words = f"{label} {ratio[0]:g} .. {ratio[1]:g}"
    if ref is None:
        return math.nan, math.nan, words
    lo, hi = ratio[0] * ref, ratio[1] * ref
    return lo, hi, f"{_length(lo)} .. {_length(hi)} ({words} at D = {_length(D)})"


def range_error(name: str, value, D: float | None = None) -> str | None:
    """What is wrong with ``value`` for field ``name`` (in SI, e.g. 'D = 0.5 mm is outside
    1 mm .. 5 m'), or None if it is a finite number in the field's physical range."""
    lo, hi, words = allowed_range(name, D)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return f"{name} must be a number [{_UNITS[name]}], got {value!r}; allowed {words}"
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        # "finite and > 0" first: the plainest words for a sign or NaN slip
        return f"{name} must be finite and > 0, got {value!r} {_UNITS[name]}; allowed {words}"
    if not lo <= value <= hi:
        return f"{name} = {_quantity(name, value)} is outside the physical range {words}"
    return None


# the keys of a bearing file ([bearing] table, or the top level): each carries its unit; the
# schema checks their types (a finite number, text), the allowed values are the physical ranges
# above, in the file's units (checked by range_error, naming the key)
BEARING_KEYS = (
    Key("D_mm", "bearing (journal) diameter [mm]",
        allowed=f"{D_RANGE_M[0] * 1e3:g} .. {D_RANGE_M[1] * 1e3:g}", kind=Number()),
    Key("L_mm", "bearing length [mm]", allowed=f"L/D {L_OVER_D_RANGE[0]:g} .. {L_OVER_D_RANGE[1]:g}",
        kind=Number()),
    Key("CR_um", "radial clearance [um]",
        allowed=f"CR/R {CR_OVER_R_RANGE[0]:g} .. {CR_OVER_R_RANGE[1]:g} (R = D/2: the clearance ratio)",
        kind=Number()),
    Key("mu_Pa_s", "dynamic viscosity of the oil [Pa s]: an isoviscous bearing (or an [oil] table: its viscosity law "
        "at its supply temperature)", None, allowed=f"{MU_RANGE_PA_S[0]:g} .. {MU_RANGE_PA_S[1]:g}; required without "
        "[oil], refused with it", kind=Number()),
    Key("name", "label", None, "text", kind=Text()),
    Key("description", "free text", None, "text", kind=Text()),
)

# resources/bearing.json of an FMU built with --bearing (bearing_fmu.fmu.build): SI values
BEARING_JSON_KEYS = (
    Key("D", "bearing (journal) diameter [m]", kind=Number()),
    Key("L", "bearing length [m]", kind=Number()),
    Key("CR", "radial clearance [m]", kind=Number()),
    Key("mu", "dynamic viscosity of the oil [Pa s]", kind=Number()),
    Key("source", "the bearing file it was built from", None, kind=Text()),
)

# the top level of a bearing file that has a [bearing] table: that table, its bore and its oil; any
# other table is refused: ignored, it would leave the bearing computed without it
BEARING_FILE_KEYS = (
    Key("bearing", "the bearing ([bearing])", kind=Table(BEARING_KEYS)),
    Key("geometry", "the bore ([geometry]): grooves, a partial arc, lobes; absent: the full 360 deg bore",
        None, kind=Table(GEOMETRY_KEYS)),
    Key("oil", "the oil ([oil]): its viscosity law, density, heat capacity, supply temperature; absent: "
        "isoviscous at mu_Pa_s", None, kind=Table(OIL_KEYS)),
)


class BearingFileError(KeyError, ValueError):
    """A bearing file or mapping that cannot be used; one line naming the file and key. A
    KeyError for callers that catch the missing or unknown key, a ValueError like every
    input error (the command lines map those to exit status 2)."""

    def __str__(self) -> str:  # a KeyError would show its message in quotes
        return str(self.args[0]) if self.args else ""


@dataclass(frozen=True)
class BearingParams:
    """Journal bearing: a plain cylindrical bore unless ``geometry`` says otherwise.

    D  : bearing (journal) diameter [m]
    L  : bearing length [m]
    CR : radial clearance [m] (of a lobed bore: the assembled clearance C_bearing)
    mu : dynamic viscosity of the oil [Pa s] (with an ``oil``: its viscosity at the supply
         temperature, or the effective one a thermal model set with ``with_viscosity``)
    geometry : the bore (``physics.bore.geometry.Geometry``: grooves, arc, lobes); default the full bore
    oil : the oil's viscosity law and properties (``physics.oil.Oil``); None: isoviscous at mu
    """

    D: float
    L: float
    CR: float
    mu: float
    geometry: Geometry = field(default=FULL_BORE)
    oil: Oil | None = None

    def __post_init__(self) -> None:
        # D first: the ranges of L and CR scale with it
        for name in ("D", "L", "CR", "mu"):
            value = getattr(self, name)
            if not isinstance(value, (bool, str, bytes)):
                try:
                    value = float(value)  # numpy scalars too
                except (TypeError, ValueError):
                    pass
            error = range_error(name, value, self.D if name in ("L", "CR") else None)
            if error is not None:
                raise ValueError(f"BearingParams.{error}")
            object.__setattr__(self, name, value)
        if not isinstance(self.geometry, Geometry):
            raise TypeError(f"BearingParams.geometry must be a Geometry, got {type(self.geometry).__name__}")
        problem = groove_problem(self.L, self.geometry, self.oil)
        if problem is not None:
            raise ValueError(f"BearingParams: {problem}")
        if self.oil is not None and not isinstance(self.oil, Oil):
            raise TypeError(f"BearingParams.oil must be an Oil or None, got {type(self.oil).__name__}")

    def __repr__(self) -> str:  # the full bore as before: a plain bearing reads as it always did
        tail = "" if self.geometry.is_full_bore else f", geometry={self.geometry!r}"
        tail += "" if self.oil is None else f", oil={self.oil!r}"
        return f"BearingParams(D={self.D!r}, L={self.L!r}, CR={self.CR!r}, mu={self.mu!r}{tail})"

    def with_geometry(self, geometry: Geometry) -> "BearingParams":
        """The same bearing with another bore (a placed feed line: ``physics.bore.feed``)."""
        return replace(self, geometry=geometry)

    def with_viscosity(self, mu: float) -> "BearingParams":
        """The same bearing at viscosity mu [Pa s] (an effective one): the film force scales with it."""
        return replace(self, mu=float(mu))

    def require_full_bore(self, what: str, why: str = "") -> None:
        """ValueError unless the bore is the full 360 deg circle: ``what`` (the force map, the FMU)
        models only that one; ``why`` says why, in a few words."""
        if not self.geometry.is_full_bore:
            raise ValueError(f"{what} models only the full 360 deg circular bore{' (' + why + ')' if why else ''}, "
                             f"not this bearing's {self.geometry.describe()}: the Reynolds internal takes it (in a scene: "
                             "internal = 'reynolds', via = 'direct')")

    @property
    def R(self) -> float:
        """Journal radius [m]."""
        return 0.5 * self.D

    def as_dict(self) -> dict[str, float]:
        """D, L, CR, mu [SI]: what files and FMU parameters record (the geometry is not one of them;
        the FMU and the force map refuse a bearing that is not the full bore)."""
        return {"D": self.D, "L": self.L, "CR": self.CR, "mu": self.mu}

    @classmethod
    def from_toml(cls, path: str | Path) -> "BearingParams":
        """Read a bearing file with keys ``D_mm``, ``L_mm``, ``CR_um``, ``mu_Pa_s`` in ``[bearing]``
        (or at the top level) and an optional ``[geometry]`` table; errors are BearingFileError
        naming the file and key."""
        path = Path(path)
        data = read_toml(path, "bearing file", BearingFileError)
        if "bearing" in data:
            if not isinstance(data["bearing"], dict):
                raise BearingFileError(f"{path}: bearing = {data['bearing']!r}: expected a table ([bearing])")
            # nothing else beside [bearing] and [geometry]: a table this code does not read ([oil])
            # would otherwise be ignored silently and the bearing computed as isothermal
            check_keys(data, BEARING_FILE_KEYS, str(path), BearingFileError)
            return cls.from_mapping(data["bearing"], where=str(path), label="[bearing]", geometry=data.get("geometry"),
                                    oil=data.get("oil"))
        data = dict(data)
        geometry = data.pop("geometry") if isinstance(data.get("geometry"), dict) else None
        oil = data.pop("oil") if isinstance(data.get("oil"), dict) else None
        return cls.from_mapping(data, where=str(path), geometry=geometry, oil=oil)

    @classmethod
    def from_json(cls, path: str | Path) -> "BearingParams":
        """Read an FMU's resources/bearing.json (D, L, CR [m], mu [Pa s], source), every key
        checked (finite, in range, no other key); errors are BearingFileError naming the file
        and key, so a damaged resource never becomes another bearing."""
        import json

        path = Path(path)
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            raise BearingFileError(f"bearing file {path} cannot be read as JSON: {exc}") from None
        d = check_table(data, BEARING_JSON_KEYS, str(path), BearingFileError)
        try:
            return cls(**{k: d[k] for k in ("D", "L", "CR", "mu")})
        except ValueError as exc:  # the physical ranges, one line naming the field
            raise BearingFileError(f"{path}: {str(exc).removeprefix('BearingParams.')}") from None

    @classmethod
    def from_mapping(cls, data: dict, where: str = "bearing", label: str = "",
                     geometry: dict | None = None, oil: dict | None = None) -> "BearingParams":
        """Build from a mapping whose keys carry their unit (``D_mm``, ``L_mm``, ``CR_um``, ``mu_Pa_s``)
        and the ``[geometry]`` and ``[oil]`` tables' mappings (None: the full bore, isoviscous);
        errors name ``where`` (the file) and ``label`` (its table, '[bearing]')."""
        # divisors, not factors: 31 / 1000 is exactly the float 0.031, 31 * 1e-3 is not
        units = {"D_mm": 1e3, "L_mm": 1e3, "CR_um": 1e6, "mu_Pa_s": 1.0}
        d = check_table(data, BEARING_KEYS, where, BearingFileError, label)
        prefix = f"{where}: {label + ' ' if label else ''}"
        the_oil = read_oil(oil, where)
        if the_oil is not None and d["mu_Pa_s"] is not None:
            raise BearingFileError(f"{prefix}mu_Pa_s = {show(data['mu_Pa_s'])} and an [oil] table both give the "
                                   "viscosity: keep mu_Pa_s for an isoviscous bearing or [oil] for its viscosity law")
        if the_oil is None and d["mu_Pa_s"] is None:
            raise BearingFileError(f"{where}: {label + ': ' if label else ''}missing key(s) mu_Pa_s (the oil's viscosity "
                                   "[Pa s]), or give an [oil] table with its viscosity law")
        vals = {}
        for key, divisor in units.items():
            name = key.split("_")[0]
            if d[key] is None:  # mu with an [oil]: the law's at the supply temperature
                vals[name] = the_oil.mu(the_oil.T_supply)
                error = range_error(name, vals[name])
                if error is not None:
                    raise BearingFileError(f"{where}: [oil] at supply_C = {the_oil.T_supply - 273.15:g}: {error}")
                continue
            vals[name] = d[key] / divisor
            error = range_error(name, vals[name], vals.get("D"))
            if error is not None:  # the constructor's words, with the file's key in front
                raise BearingFileError(f"{prefix}{key} = {show(data[key])}: {error}")
        geo = read_geometry(geometry, where)
        problem = groove_problem(vals["L"], geo, the_oil)
        if problem is not None:
            raise BearingFileError(f"{where}: [geometry] {problem}")
        return cls(**vals, geometry=geo, oil=the_oil)


def groove_problem(L: float, geometry: Geometry, oil: Oil | None = None) -> str | None:
    """Why a circumferential groove does not fit a bearing of length L [m] and its oil (naming the keys),
    or None: it leaves two lands of (L - width) / 2, whose oil all leaves by the ends at the full rise."""
    c = geometry.circumferential_groove
    if c and not c < L:
        return (f"circumferential_groove_mm = {c * 1e3:.6g} must be < L_mm = {L * 1e3:.6g} (the groove leaves two lands "
                "of (L - width) / 2)")
    if c and oil is not None and oil.outflow_rise != "full":
        return (f"circumferential_groove_mm = {c * 1e3:.6g} with [oil] outflow_rise = {oil.outflow_rise!r}: the groove's "
                "oil flows through the lands and all of it leaves by their ends at the full rise (Shigley's pressure-fed "
                "bearing, P = rho c_p Qs dT): write [oil] outflow_rise = 'full'")
    return None


def read_geometry(table, where: str) -> Geometry:
    """The ``[geometry]`` table of bearing file ``where`` (None: the full bore), its keys checked by
    type and range, then together (``Geometry.check``); errors name the file and the keys."""
    if table is None:
        return FULL_BORE
    d = check_table(table, GEOMETRY_KEYS, where, BearingFileError, "[geometry]")
    return Geometry.from_mapping(d, set(table), lambda text: BearingFileError(f"{where}: [geometry] {text}"))


def read_oil(table, where: str) -> Oil | None:
    """The ``[oil]`` table of bearing file ``where`` (None: isoviscous), its keys checked by type and
    range, then together (``oil.oil_from_table``); errors name the file and the keys."""
    if table is None:
        return None
    d = check_table(table, OIL_KEYS, where, BearingFileError, "[oil]")
    return oil_from_table(d, set(table), f"oil of {Path(where).name}",
                          lambda text: BearingFileError(f"{where}: [oil] {text}"))


# Table 2 of the paper: D = 31 mm, L = 20 mm, CR = 90 um, mu = 50 mPa s.
PAPER_BEARING = BearingParams(D=0.031, L=0.020, CR=90e-6, mu=0.05)
