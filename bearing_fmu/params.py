"""Bearing geometry and lubricant, validated once, in SI units."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

from .schema import Key, Number, Text, check_table, read_toml

# the keys of a bearing file ([bearing] table, or the top level): each carries its unit. The
# schema checks their types (a finite number, text); the ranges are BearingParams' own.
BEARING_KEYS = (
    Key("D_mm", "bearing (journal) diameter [mm]", allowed="> 0", kind=Number()),
    Key("L_mm", "bearing length [mm]", allowed="> 0", kind=Number()),
    Key("CR_um", "radial clearance [um]", allowed="> 0 and < D/2", kind=Number()),
    Key("mu_Pa_s", "dynamic viscosity of the oil [Pa s]", allowed="> 0", kind=Number()),
    Key("name", "label", None, "text", kind=Text()),
    Key("description", "free text", None, "text", kind=Text()),
)


class BearingFileError(KeyError, ValueError):
    """A bearing file or mapping that cannot be used; one line naming the file and key. A
    KeyError for callers that catch the missing or unknown key, a ValueError like every
    input error (the command lines map those to exit status 2)."""

    def __str__(self) -> str:  # a KeyError would show its message in quotes
        return str(self.args[0]) if self.args else ""


@dataclass(frozen=True)
class BearingParams:
    """Plain cylindrical journal bearing.

    D  : bearing (journal) diameter [m]
    L  : bearing length [m]
    CR : radial clearance [m]
    mu : dynamic viscosity of the oil [Pa s]
    """

    D: float
    L: float
    CR: float
    mu: float

    def __post_init__(self) -> None:
        for name in ("D", "L", "CR", "mu"):
            value = getattr(self, name)
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ValueError(f"BearingParams.{name} must be a number, got {value!r}") from None
            if not math.isfinite(value) or value <= 0.0:
                raise ValueError(f"BearingParams.{name} must be finite and > 0, got {value!r}")
            object.__setattr__(self, name, value)
        if self.CR >= 0.5 * self.D:
            raise ValueError(
                f"BearingParams.CR = {self.CR!r} m must be smaller than the radius D/2 = {0.5 * self.D!r} m"
            )

    @property
    def R(self) -> float:
        """Journal radius [m]."""
        return 0.5 * self.D

    def as_dict(self) -> dict[str, float]:
        return asdict(self)

    @classmethod
    def from_toml(cls, path: str | Path) -> "BearingParams":
        """Read a bearing file with keys ``D_mm``, ``L_mm``, ``CR_um``, ``mu_Pa_s`` in ``[bearing]``
        (or at the top level); errors are BearingFileError naming the file and key."""
        path = Path(path)
        data = read_toml(path, "bearing file", BearingFileError)
        if "bearing" in data:
            if not isinstance(data["bearing"], dict):
                raise BearingFileError(f"{path}: bearing = {data['bearing']!r}: expected a table ([bearing])")
            return cls.from_mapping(data["bearing"], where=str(path), label="[bearing]")
        return cls.from_mapping(data, where=str(path))

    @classmethod
    def from_mapping(cls, data: dict, where: str = "bearing", label: str = "") -> "BearingParams":
        """Build from a mapping whose keys carry their unit (``D_mm``, ``L_mm``, ``CR_um``, ``mu_Pa_s``);
        errors name ``where`` (the file) and ``label`` (its table, '[bearing]')."""
        # divisors, not factors: 31 / 1000 is exactly the float 0.031, 31 * 1e-3 is not
        units = {"D_mm": 1e3, "L_mm": 1e3, "CR_um": 1e6, "mu_Pa_s": 1.0}
        d = check_table(data, BEARING_KEYS, where, BearingFileError, label)
        try:
            return cls(**{key.split("_")[0]: d[key] / divisor for key, divisor in units.items()})
        except ValueError as exc:  # a range of BearingParams: name the file too
            raise BearingFileError(f"{where}: {label + ': ' if label else ''}{exc}") from None


# Table 2 of the paper: D = 31 mm, L = 20 mm, CR = 90 um, mu = 50 mPa s.
PAPER_BEARING = BearingParams(D=0.031, L=0.020, CR=90e-6, mu=0.05)
