"""Bearing geometry and lubricant, validated once, in SI units."""

from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, dataclass
from pathlib import Path

from .schema import Key, check_keys

# the keys of a bearing file ([bearing] table, or the top level): each carries its unit
BEARING_KEYS = (
    Key("D_mm", "bearing (journal) diameter [mm]", allowed="> 0"),
    Key("L_mm", "bearing length [mm]", allowed="> 0"),
    Key("CR_um", "radial clearance [um]", allowed="> 0 and < D/2"),
    Key("mu_Pa_s", "dynamic viscosity of the oil [Pa s]", allowed="> 0"),
    Key("name", "label", None, "text"),
    Key("description", "free text", None, "text"),
)


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
        """Read a bearing file with keys ``D_mm``, ``L_mm``, ``CR_um``, ``mu_Pa_s`` in ``[bearing]``."""
        path = Path(path)
        with path.open("rb") as fh:
            data = tomllib.load(fh)
        return cls.from_mapping(data.get("bearing", data), where=str(path))

    @classmethod
    def from_mapping(cls, data: dict, where: str = "bearing") -> "BearingParams":
        """Build from a mapping whose keys carry their unit (``D_mm``, ``L_mm``, ``CR_um``, ``mu_Pa_s``)."""
        # divisors, not factors: 31 / 1000 is exactly the float 0.031, 31 * 1e-3 is not
        units = {"D_mm": 1e3, "L_mm": 1e3, "CR_um": 1e6, "mu_Pa_s": 1.0}
        check_keys(data, BEARING_KEYS, where, KeyError)
        vals = {}
        for key, divisor in units.items():
            v = data[key]
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise ValueError(f"{where}: {key} must be a number, got {v!r}")
            vals[key.split("_")[0]] = float(v) / divisor
        return cls(**vals)


# Table 2 of the paper: D = 31 mm, L = 20 mm, CR = 90 um, mu = 50 mPa s.
PAPER_BEARING = BearingParams(D=0.031, L=0.020, CR=90e-6, mu=0.05)
