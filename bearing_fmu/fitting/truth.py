"""The truth a fit draws its samples from: the Reynolds solver, or a force map (``truth_map``).

A fit asks its truth two things:

* the statics: the equilibrium under the load (the expansion point) and, anchored, the force
  and derivatives there. Always the Reynolds solver (one equilibrium and one adjoint Jacobian),
  so an anchored surrogate keeps Reynolds' static force and Lund coefficients exactly;
* the samples: the designed samples, the tube samples about a scene's series and the designed
  held-out samples. Reynolds' too, unless the recipe names a ``truth_map``: then the force map
  (bearing_fmu/internals/map/, docs/forcemap.md) answers them, 50-100x cheaper per sample (3-10 us
  against 250-700 us on the default 128 x 16 grid, docs/taylor.md) and within the map's accuracy
  of Reynolds.

A scene's series stay the scene's Reynolds run. The map is checked before any solver work: it
must serve the bearing (its L/D, the map's own check), be tabulated from the same Reynolds grid
and cavitation model as the statics (one truth, not two) and reach the samples' eccentricity.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

from ..physics.params import BearingParams


@dataclass
class Truth:
    """The fit's truth: ``statics`` (equilibrium, anchor: Reynolds or a caller's internal),
    ``samples`` (the internal the samples are drawn from: ``statics`` itself or a ForceMap)
    and, for a map, its file ``map_path`` (as given) and table."""

    statics: object
    samples: object
    map_path: str | None = None
    table: object = None

    @property
    def is_map(self) -> bool:
        return self.table is not None

    def check_reach(self, ecc_max: float, what: str) -> None:
        """Samples up to eccentricity ``ecc_max`` [-] can be drawn: a map refuses states at or
        beyond its last point; ``what`` names the bound for the message."""
        if self.is_map and not ecc_max < self.table.eps_max:
            raise ValueError(f"fit: {what} = {ecc_max:g} reaches the truth map's last point, eccentricity "
                             f"{self.table.eps_max:g} ({self.map_path}), beyond which the map refuses a state: "
                             f"keep it below {self.table.eps_max:g}, or leave truth_map out (Reynolds)")

    def provenance(self) -> dict:
        """What the surrogate file records of its truth: ``truth`` ('Reynolds', or 'force map'
        with the map in ``truth_map``: file name, resolution, its Reynolds grid, its own
        provenance and a hash of the file), the Reynolds grid of the statics (``truth_n_theta``,
        ``truth_n_x``, ``truth_cavitation``)."""
        prov = {"truth": type(self.statics).__name__}
        for attr in ("n_theta", "n_x", "cavitation"):
            if hasattr(self.statics, attr):
                prov[f"truth_{attr}"] = getattr(self.statics, attr)
        if self.is_map:
            t = self.table
            prov["truth"] = "force map"
            prov["truth_statics"] = f"equilibrium and anchor from {type(self.statics).__name__}"
            prov["truth_map"] = {
                "file": Path(self.map_path).name, "sha256": _digest(self.map_path),
                "n_eps": t.n_eps, "n_beta": t.n_beta, "eps_max": t.eps_max, "L_over_D": t.L_over_D,
                "reynolds": {"n_theta": t.n_theta, "n_x": t.n_x, "cavitation": t.cavitation},
                "provenance": dict(t.provenance),
            }
        return prov


def make_reynolds(params: BearingParams, grid: tuple[int, int] | None = None, cavitation: str = "reynolds"):
    """The truth (imported lazily: the surrogate never needs it) on ``grid`` (n_theta, n_x;
    None: the solver's default)."""
    from ..physics.solver.reynolds import Reynolds

    if grid is None:
        return Reynolds(params, cavitation=cavitation)
    return Reynolds(params, n_theta=int(grid[0]), n_x=int(grid[1]), cavitation=cavitation)


def _digest(path) -> str:
    """The first 16 hex digits of the file's SHA-256: which map, even if a file of that name changes."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16]


def _reynolds_words(n_theta, n_x, cavitation) -> str:
    """'Reynolds 128x16' (the cavitation model named unless it is the default, 'reynolds')."""
    return f"Reynolds {n_theta}x{n_x}" + ("" if cavitation in (None, "reynolds") else f" {cavitation} cavitation")


def truth_line(provenance: dict, map_shown: str | None = None, scene: bool = False) -> str:
    """The report's line on the truth, from a surrogate file's provenance (``Truth.provenance``);
    ``map_shown``: the map's path as the user gave it (default: the stored file name); ``scene``:
    a scene-trained fit (its series are Reynolds)."""
    prov = provenance or {}
    if "truth" not in prov:  # a direct fit_surrogate call records no truth
        return "truth: not recorded"
    grid = (prov.get("truth_n_theta"), prov.get("truth_n_x"))
    statics = _reynolds_words(*grid, prov.get("truth_cavitation")) if None not in grid else str(prov["truth"])
    m = prov.get("truth_map")
    if prov.get("truth") != "force map" or not isinstance(m, dict):
        return f"truth: {statics}"
    rey = m.get("reynolds", {})
    where = map_shown if map_shown is not None else m.get("file")
    text = (f"truth: force map {m.get('n_eps')}x{m.get('n_beta')} from "
            f"{_reynolds_words(rey.get('n_theta'), rey.get('n_x'), rey.get('cavitation'))} ({where})")
    if scene:
        return text + f" for the designed samples; series, equilibrium and anchor: {statics}"
    return text + f"; equilibrium and anchor: {statics}"


def fit_truth(recipe, params: BearingParams, statics=None, *, grid_hint: str = "") -> Truth:
    """The truth of ``recipe`` for the bearing ``params``. ``statics``: the internal of the
    equilibrium and the anchor (None: Reynolds on ``recipe.grid``, else on the map's grid and
    cavitation model, else the solver's default). With ``recipe.truth_map`` the map is read
    and checked (file, L/D, its Reynolds grid against the statics') before the solver is built;
    ``grid_hint`` ends the message of a grid mismatch (how to resolve it for this command)."""
    path = recipe.truth_map
    table = sampler = None
    if path is not None:
        table, sampler = _load(path, params)
    if statics is None:
        grid = recipe.grid if recipe.grid is not None or table is None else (table.n_theta, table.n_x)
        _check_grid(table, path, grid, "reynolds" if table is None else table.cavitation, grid_hint)
        statics = make_reynolds(params, grid, "reynolds" if table is None else table.cavitation)
    elif table is not None and hasattr(statics, "n_theta"):
        _check_grid(table, path, (statics.n_theta, statics.n_x), getattr(statics, "cavitation", "reynolds"),
                    grid_hint)
    return Truth(statics, statics if sampler is None else sampler, path, table)


def _load(path, params: BearingParams):
    """(table, ForceMap) of the map file ``path`` for ``params``; one line naming the setting
    and the file on a fault (missing, damaged, another L/D)."""
    from ..internals.map.mapfile import load_any_map, map_internal

    try:
        table = load_any_map(path)
        return table, map_internal(params, table, source=str(path))
    except FileNotFoundError as exc:
        raise FileNotFoundError(f"fit: truth_map: {exc}") from None
    except ValueError as exc:
        raise ValueError(f"fit: truth_map: {exc}") from None


def _check_grid(table, path, grid, cavitation: str, hint: str) -> None:
    """The statics' Reynolds grid (None: the solver's default) and cavitation model are the map's."""
    if table is None:
        return
    from ..physics.solver.reynolds import DEFAULT_N_THETA, DEFAULT_N_X

    n_theta, n_x = grid if grid is not None else (DEFAULT_N_THETA, DEFAULT_N_X)
    if (n_theta, n_x, cavitation) != (table.n_theta, table.n_x, table.cavitation):
        raise ValueError(f"fit: truth_map {path} is tabulated from "
                         f"{_reynolds_words(table.n_theta, table.n_x, table.cavitation)}, the fit's Reynolds truth "
                         f"(equilibrium, anchor) is {_reynolds_words(n_theta, n_x, cavitation)}: samples and "
                         f"statics must come from one truth" + (f"; {hint}" if hint else ""))


__all__ = ["Truth", "fit_truth", "make_reynolds", "truth_line"]
