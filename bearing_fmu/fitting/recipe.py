"""The settings of a surrogate fit, each written once: ``FitRecipe``.

A recipe holds every setting of a fit with its meaning, unit, default and allowed values
(the dataclass fields and their metadata). From it come

* the checks: ``FitRecipe(...)`` refuses a value outside its range, naming the field and
  the range;
* the command lines: the options of ``bearing-fmu fit`` (group "designed") and of
  ``rotor-host fit`` (group "scene"), both with the shared settings (groups "model" and
  "truth"), are generated from the fields (``command_line_options`` / ``recipe_from_values``);
* the provenance: ``to_dict`` is stored in the surrogate file as ``provenance["recipe"]``
  and ``recipe_of`` reads it back for a refit. Files written before the recipe store
  ``provenance["fit_call"]`` instead; ``from_fit_call`` is the one place that reads those.

A recipe is designed-domain (no ``scenes``: the fit over declared position and velocity
discs at one load and speed, or a co-simulation time series ``from_npz``) or scene-trained
(``scenes`` given: the Reynolds series of those scenes, fitted by the host: ``rotor-host fit``); the
settings of the other kind must keep their defaults. Paths (scenes, the npz, the truth map)
are stored relative to the surrogate file, so a file and the files beside it can move together.

The truth (group "truth", both kinds): the Reynolds solver, or with ``truth_map`` a force map
(bearing_fmu/internals/map/) for the designed and tube samples and the designed held-out samples
(``fitting.truth``); a scene's series, the equilibrium and the anchor stay Reynolds.
"""

from __future__ import annotations

import math
import os
from dataclasses import MISSING, dataclass, field, fields, replace
from numbers import Integral, Real
from pathlib import Path
from typing import Mapping

from ..io.cliargs import existing_file, grid_words, parse_grid, typed
from ..io.schema import Invalid

GROUPS = {
    "model": "the model and its regression (both fit commands)",
    "truth": "the truth the designed and tube samples are drawn from (both fit commands)",
    "designed": "designed domain (bearing-fmu fit)",
    "scene": "scene training (rotor-host fit)",
}
SHARED = ("model", "truth")  # the groups of both kinds of recipe


class RecipeError(ValueError):
    """A setting outside its allowed values; names the field, the value and the range."""

    def __init__(self, name: str, value, allowed: str, why: str = ""):
        self.name, self.value, self.allowed, self.why = name, value, allowed, why
        super().__init__(f"fit: {name} = {value!r} must be {allowed}" + (f" ({why})" if why else ""))


# ----------------------------------------------------------------------------- allowed values

class _Kind:
    optional = False

    def describe(self) -> str:
        raise NotImplementedError

    def text(self) -> str:
        return self.describe() + (" or None" if self.optional else "")

    def check(self, v):
        """The value, normalised (ints to float for a number, lists to tuples), or ValueError."""
        raise NotImplementedError

    def cli(self) -> dict:
        return {}

    def to_json(self, v, folder: Path | None):
        return v

    def from_json(self, v, folder: Path | None):
        return v


class _Int(_Kind):
    def __init__(self, lo: int, optional: bool = False):
        self.lo, self.optional = lo, optional

    def describe(self):
        return f"an integer >= {self.lo}"

    def check(self, v):
        if v is None and self.optional:
            return None
        if isinstance(v, bool) or not isinstance(v, Integral) or v < self.lo:
            raise ValueError
        return int(v)

    def cli(self):
        return {"type": typed(self.describe(), int, self.check)}


class _Float(_Kind):
    def __init__(self, lo=None, hi=None, *, lo_open=False, hi_open=False, nonzero=False, optional=False):
        self.lo, self.hi, self.lo_open, self.hi_open = lo, hi, lo_open, hi_open
        self.nonzero, self.optional = nonzero, optional

    def describe(self):
        if self.lo is not None and self.hi is not None:
            return f"a number in {'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}{')' if self.hi_open else ']'}"
        if self.lo is not None:
            return f"a finite number {'>' if self.lo_open else '>='} {self.lo:g}"
        return "a finite nonzero number" if self.nonzero else "a finite number"

    def check(self, v):
        if v is None and self.optional:
            return None
        if isinstance(v, bool) or not isinstance(v, Real):
            raise ValueError
        v = float(v)
        bad = (not math.isfinite(v) or (self.nonzero and v == 0.0)
               or (self.lo is not None and (v <= self.lo if self.lo_open else v < self.lo))
               or (self.hi is not None and (v >= self.hi if self.hi_open else v > self.hi)))
        if bad:
            raise ValueError
        return v

    def cli(self):
        return {"type": typed(self.describe(), float, self.check)}


class _Flag(_Kind):
    def describe(self):
        return "true or false"

    def check(self, v):
        if not isinstance(v, bool):
            raise ValueError
        return v


class _Lambda(_Kind):
    _number = _Float(0.0)

    def describe(self):
        return "'cv' (chosen by cross validation) or a number >= 0"

    def check(self, v):
        return "cv" if v == "cv" else self._number.check(v)

    def cli(self):
        return {"type": typed(self.describe(), lambda s: s if s == "cv" else float(s), self.check)}


class _Paths(_Kind):
    """Files (tuple of str), stored relative to the surrogate file's folder."""

    def describe(self):
        return "a list of file paths"

    def check(self, v):
        if v is None:
            return ()
        if isinstance(v, (str, os.PathLike)):
            v = (v,)
        try:
            out = tuple(os.fspath(p) for p in v)
        except TypeError:
            raise ValueError from None
        return out

    def cli(self):
        return {"action": "append", "type": existing_file}

    def to_json(self, v, folder):
        return [_portable(p, folder) for p in v]

    def from_json(self, v, folder):
        v = [v] if isinstance(v, str) else v
        return tuple(_located(p, folder) for p in v) if isinstance(v, list) else v


class _Path(_Kind):
    optional = True

    def describe(self):
        return "a file path"

    def check(self, v):
        if v is None:
            return None
        if not isinstance(v, (str, os.PathLike)):
            raise ValueError
        return os.fspath(v)

    def cli(self):
        return {"type": existing_file}

    def to_json(self, v, folder):
        return None if v is None else _portable(v, folder)

    def from_json(self, v, folder):
        return _located(v, folder) if isinstance(v, str) else v


class _Grid(_Kind):
    """A Reynolds grid (n_theta, n_x) within the solver's own ranges (its options n_theta, n_x)."""

    optional = True

    def describe(self):
        return "n_theta, n_x with " + grid_words().split(": ", 1)[1].replace(", n_x", " and n_x")

    def check(self, v):
        if v is None:
            return None
        if isinstance(v, (str, bytes)) or not hasattr(v, "__len__") or len(v) != 2:
            raise ValueError
        n_theta, n_x = (_Int(1).check(n) for n in v)
        try:
            return parse_grid(f"{n_theta}x{n_x}")
        except Invalid:
            raise ValueError from None

    def cli(self):
        return {"type": typed("an integer >= 1", int, _Int(1).check), "nargs": 2, "metavar": ("N_THETA", "N_X")}

    def to_json(self, v, folder):
        return None if v is None else list(v)


def _portable(p, folder: Path | None) -> str:
    """A path as stored: relative to ``folder`` (posix), else absolute."""
    p = Path(p).resolve()
    return Path(os.path.relpath(p, folder)).as_posix() if folder is not None else str(p)


def _located(p: str, folder: Path | None) -> str:
    """A stored path made usable here: relative ones are relative to ``folder``."""
    q = Path(p)
    return str(q if q.is_absolute() or folder is None else (folder / q).resolve())


def _setting(default, group: str, allowed: _Kind, help: str, *, flag: str | None = None, metavar: str | None = None,
             default_text: str | None = None, flag_help: str | None = None):
    """A recipe field: its default, group, allowed values and meaning (``help``); for the
    command line its option (``flag``, default --field-name), ``metavar``, the text of a None
    default, and for a true/false setting the help of the option that flips it."""
    meta = {"group": group, "allowed": allowed, "help": help, "flag": flag, "metavar": metavar,
            "default_text": default_text, "flag_help": flag_help}
    return field(default=default, metadata=meta)


# ----------------------------------------------------------------------------- the recipe

@dataclass(frozen=True)
class FitRecipe:
    """Every setting of a surrogate fit (see the module doc); the defaults are those of the
    command lines. Units: positions in CR, velocities in omega CR (the surrogate's scaled u)."""

    # the model and its regression: both fit commands
    order: int = _setting(5, "model", _Int(1), "Taylor order: the polynomial's total degree (1 = the linear model)")
    lam: float | str = _setting("cv", "model", _Lambda(), "ridge penalty lambda per sample: 'cv' chooses it per force "
                                "component by cross validation (line search), a number fixes it", flag="--lambda",
                                metavar="LAMBDA")
    k_folds: int = _setting(5, "model", _Int(2), "cross-validation folds")
    prune: bool = _setting(True, "model", _Flag(), "drop the smallest terms while the cross-validation RMS error "
                           "stays within (1 + prune_tol) of the unpruned fit's", flag="--no-prune",
                           flag_help="keep all terms")
    prune_tol: float = _setting(0.05, "model", _Float(0.0), "pruning: allowed relative increase of the "
                                "cross-validation RMS error")
    anchor: bool = _setting(True, "model", _Flag(), "fix the constant and order-1 terms to the truth's force and "
                            "derivatives at the equilibrium", flag="--no-anchor",
                            flag_help="regress the constant and order-1 terms too (default: fixed to the truth's "
                                      "force and derivatives at the equilibrium)")
    wall_power: float = _setting(0.0, "model", _Float(0.0), "wall factor P: fit the polynomial to "
                                 "F (1 - eccentricity^2)^P and evaluate F = polynomial / (1 - eccentricity^2)^P, so it "
                                 "can follow the force's growth near the wall (0: the plain polynomial)", metavar="P")
    shape_order: int | None = _setting(None, "model", _Int(0, optional=True), "add the short-bearing shape columns "
                                       "S_y m_j, S_z m_j (S: the closed-form short-bearing force, m_j: monomials of "
                                       "order <= R) to the regression, so the surrogate carries the film's growth at "
                                       "the wall (docs/taylor.md)", metavar="R", default_text="none")
    seed: int = _setting(1, "model", _Int(0), "seed of the designed samples (the held-out design uses seed + 1000) "
                         "and of random cross-validation folds")

    # the truth of the samples: both fit commands
    truth_map: str | None = _setting(None, "truth", _Path(), "draw the designed and tube samples (and the designed "
                                     "held-out samples) from this force map (rotor_host/bundled/maps/*.json, built by "
                                     "`bearing-fmu map` for the bearing's L/D) instead of the Reynolds solver: "
                                     "50-100x cheaper per sample; a scene's series, the equilibrium and the anchor "
                                     "stay Reynolds, on the map's grid", metavar="MAP",
                                     default_text="none: the Reynolds solver")

    # designed domain: bearing-fmu fit
    speed_hz: float = _setting(22.0, "designed", _Float(nonzero=True), "shaft speed [Hz]")
    load_y: float = _setting(0.0, "designed", _Float(), "static load on the journal, y [N]")
    load_z: float = _setting(-16.7, "designed", _Float(), "static load on the journal, z [N] (-16.7: half the "
                             "paper rotor's weight)")
    ecc_max: float = _setting(0.7, "designed", _Float(0.0, 1.0, lo_open=True, hi_open=True),
                              "eccentricity bound of the designed samples [-]")
    v_max: float = _setting(0.5, "designed", _Float(0.0), "velocity bound of the designed samples [omega CR]")
    radius: float | None = _setting(None, "designed", _Float(0.0, lo_open=True, optional=True),
                                    "radius of the position disc about the equilibrium [CR]",
                                    default_text="the whole disc eccentricity <= ecc-max")
    n_train: int = _setting(3000, "designed", _Int(1), "designed training samples")
    n_test: int = _setting(1500, "designed", _Int(1), "designed held-out samples")
    grid: tuple[int, int] | None = _setting(None, "designed", _Grid(), "Reynolds grid of the truth (with "
                                            "truth_map: the map's, leave it out)",
                                            default_text="the solver's default, or the map's")
    from_npz: str | None = _setting(None, "designed", _Path(), "train on a co-simulation time series "
                                    "(.npz with y, z, vy, vz, Fy, Fz) instead of designed samples: the first 80 % "
                                    "trains, the last 20 % is held out", metavar="NPZ", default_text="none")

    # scene training: rotor-host fit
    scenes: tuple[str, ...] = _setting((), "scene", _Paths(), "train on the Reynolds time series of this scene "
                                       "(rotor_host/bundled/scenes/*.toml), the paper's way; its speed and bearing load are the "
                                       "surrogate's. Repeatable: several scenes (other unbalances, same speed and "
                                       "load) are fitted together", flag="--scene", metavar="SCENE")
    test_scenes: tuple[str, ...] = _setting((), "scene", _Paths(), "another scene at the same speed whose series is "
                                            "held out (repeatable)", flag="--test-scene", metavar="SCENE")
    bearing_number: int = _setting(1, "scene", _Int(1), "which bearing's series: its number, 1-based in rotor order")
    stride: int = _setting(2, "scene", _Int(1), "use every stride-th time step of the series")
    designed: int = _setting(2000, "scene", _Int(0), "Reynolds samples added over the domain the series spans (0 = "
                             "the series only, the paper's way, which holds on the training orbit only)", metavar="N")
    designed_ecc_max: float | None = _setting(None, "scene", _Float(0.0, 1.0, lo_open=True, hi_open=True,
                                                                    optional=True),
                                              "eccentricity bound of the designed samples [-]",
                                              default_text="the series'")
    designed_v_max: float | None = _setting(None, "scene", _Float(0.0, lo_open=True, optional=True),
                                            "velocity bound of the designed samples [omega CR]",
                                            default_text="the series'")
    designed_weight: float = _setting(1.0, "scene", _Float(0.0), "weight of a designed row against a series row in "
                                      "the least-squares fit")
    designed_tube: float | None = _setting(None, "scene", _Float(0.0, lo_open=True, optional=True),
                                           "draw the designed samples in a tube of this radius [CR and omega CR] "
                                           "about the training series' states instead of over the discs they span",
                                           default_text="the discs")
    ecc_weight: float = _setting(0.0, "scene", _Float(0.0), "weigh each row by (1 - eccentricity^2)^P, so the rows "
                                 "near the wall (forces without bound) do not dominate the fit (0: equal weights)",
                                 metavar="P")

    def __post_init__(self):
        for f in fields(self):
            allowed: _Kind = f.metadata["allowed"]
            v = getattr(self, f.name)
            try:
                ok = allowed.check(v)
            except ValueError:
                raise RecipeError(f.name, v, allowed.text()) from None
            object.__setattr__(self, f.name, ok)
        own = self.kind
        for f in fields(self):
            g = f.metadata["group"]
            if g not in (*SHARED, own) and getattr(self, f.name) != f.default:
                raise RecipeError(f.name, getattr(self, f.name), f"left at its default {f.default!r}",
                                  f"a {GROUPS[g]} setting; this recipe is {GROUPS[own]}")
        if self.truth_map is not None:
            # a map that would serve no sample is refused rather than recorded as the truth
            if self.from_npz is not None:
                raise RecipeError("truth_map", self.truth_map, "None", "from_npz gives the training forces: "
                                  "no sample is drawn from a truth")
            if own == "scene" and not self.designed:
                raise RecipeError("truth_map", self.truth_map, "None", "designed = 0: the fit draws no designed "
                                  "samples, its series and held-out blocks are the scenes' Reynolds runs")

    # ------------------------------------------------------------------ kinds
    @property
    def kind(self) -> str:
        """'scene' (trained on scene series) or 'designed' (designed domain or an npz series)."""
        return "scene" if self.scenes else "designed"

    @property
    def load(self) -> tuple[float, float]:
        """The designed fit's static load (Wy, Wz) [N]."""
        return (self.load_y, self.load_z)

    def with_order(self, order: int) -> "FitRecipe":
        return replace(self, order=order)

    # ------------------------------------------------------------------ provenance
    def to_dict(self, relative_to: str | Path | None = None) -> dict:
        """The recipe for JSON: the shared settings and those of its kind; paths relative to
        the folder ``relative_to`` (the surrogate file's), else absolute."""
        folder = None if relative_to is None else Path(relative_to).resolve()
        return {f.name: f.metadata["allowed"].to_json(getattr(self, f.name), folder)
                for f in fields(self) if f.metadata["group"] in (*SHARED, self.kind)}

    @classmethod
    def from_dict(cls, d: dict, where: str = "recipe", folder: str | Path | None = None) -> "FitRecipe":
        """The recipe of ``to_dict``; relative paths are relative to ``folder``. Missing keys
        take their defaults, unknown keys are refused."""
        if not isinstance(d, dict):
            raise ValueError(f"{where}: expected a JSON object, got {type(d).__name__}")
        known = {f.name: f for f in fields(cls)}
        unknown = sorted(set(d) - set(known))
        if unknown:
            raise ValueError(f"{where}: unknown setting(s) {', '.join(unknown)}; known: {', '.join(known)}")
        folder = None if folder is None else Path(folder)
        try:
            return cls(**{k: known[k].metadata["allowed"].from_json(v, folder) for k, v in d.items()})
        except RecipeError as exc:
            raise ValueError(f"{where}: {exc}") from None

    @classmethod
    def from_fit_call(cls, call: dict, where: str = "fit_call", folder: str | Path | None = None) -> "FitRecipe":
        """The recipe of a file written before FitRecipe: its ``provenance["fit_call"]``.

        Designed fits stored (load, speed_hz, ecc_max, v_max, radius, n_train, n_test, seed,
        grid, npz, anchor, lam, k_folds, prune, prune_tol, wall_power, shape_order); scene
        fits (scenes, or one scene in older files, bearing, stride, test_scenes, lam, prune,
        prune_tol, anchor, designed, designed_*, ecc_weight, wall_power, shape_order, seed),
        where a missing ``designed`` meant none. The order is the file's own (not stored)."""
        if not isinstance(call, dict):
            raise ValueError(f"{where}: expected a JSON object, got {type(call).__name__}")
        c = dict(call)
        if "scene" in c or "scenes" in c:
            c["scenes"] = c.pop("scenes") if "scenes" in c else [c.pop("scene")]
            c.setdefault("designed", 0)
            if "bearing" in c:
                c["bearing_number"] = c.pop("bearing")
        else:
            if "speed_hz" not in c:
                raise ValueError(f"{where}: names neither scenes nor a speed; fitted by an older version, "
                                 "fit it again")
            if "load" in c:
                ld = c.pop("load")
                if not isinstance(ld, list) or len(ld) != 2:
                    raise ValueError(f"{where}: key 'load' must be [Wy, Wz], got {ld!r}")
                c["load_y"], c["load_z"] = ld
            if "npz" in c:
                c["from_npz"] = c.pop("npz")
        return cls.from_dict(c, where, folder)


def recipe_of(surrogate, path: str | Path | None = None) -> FitRecipe:
    """The recipe a surrogate was fitted with, from its provenance (``recipe``, or the
    ``fit_call`` of older files); paths relative to the folder of ``path``, the file the
    surrogate was read from. Its ``order`` is the surrogate's."""
    prov = surrogate.provenance or {}
    where = f"{path if path is not None else 'surrogate'}: provenance"
    folder = None if path is None else Path(path).resolve().parent
    if "recipe" in prov:
        r = FitRecipe.from_dict(prov["recipe"], f"{where}: recipe", folder)
    elif prov.get("fit_call"):
        r = FitRecipe.from_fit_call(prov["fit_call"], f"{where}: fit_call", folder)
    else:
        raise ValueError(f"{where}: no fit recipe to refit from (fitted by an older version); fit it again "
                         "with `bearing-fmu fit` or `rotor-host fit`")
    return r if r.order == surrogate.order else r.with_order(surrogate.order)


# ----------------------------------------------------------------------------- command lines

def option_name(f) -> str:
    """The command-line option of a recipe field."""
    return f.metadata["flag"] or "--" + f.name.replace("_", "-")


def recipe_fields(group: str):
    """The fields of a command's recipe: the shared settings (model, truth) and those of ``group``."""
    return [f for f in fields(FitRecipe) if f.metadata["group"] in (*SHARED, group)]


def command_line_options(group: str) -> list[tuple[str, dict]]:
    """The recipe fields of ``group`` ('designed' or 'scene') and the shared ones as command-line
    options: (flag, keyword arguments of ``argparse.ArgumentParser.add_argument``), name, default
    and help from the fields. The command lines (``bearing_fmu.cli``, ``rotor_host.cli``) add them."""
    out = []
    for f in recipe_fields(group):
        allowed: _Kind = f.metadata["allowed"]
        flag = option_name(f)
        default = f.default if f.default is not MISSING else None
        if isinstance(allowed, _Flag):
            text = f.metadata["flag_help"] or f.metadata["help"]
            out.append((flag, {"dest": f.name, "action": "store_false" if default else "store_true",
                               "help": text.replace("%", "%%")}))
            continue
        shown = f.metadata["default_text"] or (default if not isinstance(default, tuple) else None)
        text = f.metadata["help"] + ("" if isinstance(allowed, _Paths) else f"; {allowed.describe()}")
        text += f" (default: {shown})" if shown is not None else ""
        text = text.replace("%", "%%")  # argparse formats help with %
        kw = {"dest": f.name, "default": None if isinstance(allowed, _Paths) else default, "help": text,
              **allowed.cli()}
        if f.metadata["metavar"]:
            kw["metavar"] = f.metadata["metavar"]
        out.append((flag, kw))
    return out


def recipe_from_values(values: Mapping, group: str) -> FitRecipe:
    """The recipe of parsed option values (field name -> value, e.g. ``vars()`` of the parsed
    command line, see ``command_line_options``); a value outside its range is refused naming
    the option."""
    flags = {f.name: option_name(f) for f in recipe_fields(group)}
    try:
        return FitRecipe(**{name: values.get(name) for name in flags})
    except RecipeError as exc:
        value = exc.value if not isinstance(exc.value, (tuple, list)) else " ".join(map(str, exc.value))
        allowed = exc.allowed.removesuffix(" or None")  # on the command line: leave the option out
        allowed = "left out" if allowed == "None" else allowed
        raise ValueError(f"{flags.get(exc.name, exc.name)} {value}: must be {allowed}"
                         + (f" ({exc.why})" if exc.why else "")) from None


__all__ = ["FitRecipe", "RecipeError", "recipe_of", "command_line_options", "recipe_from_values", "recipe_fields",
           "option_name", "GROUPS"]
