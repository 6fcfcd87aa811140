"""The map store: force maps kept under a hash of what determines them, found again by every command.

A map is determined by the bore (its grooves, their width, the arc, whether they are fed: not the
supply pressure, any p_s > 0 has the same map, ``supplymap``), L/D, the table's axes (the
resolution, the attitudes per period, eps_max, the phases averaged, fed grooves' u points), the Reynolds grid and
cavitation model of its truth, whether it has the flow tables, and the solver's code (a digest of
``physics/`` and the tabulating modules, ``cache.source_digest``). D, CR and mu are not: the map
serves every bearing of its L/D and bore (docs/forcemap.md). ``map_key`` hashes these; the store
(``cache.map_store``: ``$BEARING_FMU_MAP_STORE`` or the user cache's ``bearing_fmu/maps``) holds
the map under a name ending in the key, so a changed input or solver gives another name and an old
map is never served wrongly. ``bearing-fmu map`` writes every map it builds into it; a command that
needs a map and names none (a scene's ``[map] map`` left out) takes the one of its bearing at the
default settings (``stored_map``) and says which.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass
from pathlib import Path

from ...io.cache import map_store, source_digest
from ...physics.params import BearingParams
from . import groovemap as gm
from . import tables as tb
from .lobemap import map_params, map_problem
from .supplymap import DEFAULT_N_SUP

SOLVER_PARTS = ("physics", "internals/map/tables.py", "internals/map/groovemap.py")
SUPPLY_PART = "internals/map/supplymap.py"  # and this for the fed grooves' 4-D map
# the pads' map by default: 48 x 64 x 48 (eps x phi x beta), 2.8 MB; the five-pad scene's orbit within
# 0.0023 % CR RMS of the Reynolds pads over 20 ms (64^3: 0.0006 %, 5 MB; 64 x 32 x 64: 0.094 %: phi counts
# most; docs/geometry.md, Tilting pads)
PAD_MAP_N_EPS, PAD_MAP_N_BETA = 48, 48
# a tilting-pad bearing's map is its pads' partial-arc map (``map_bearing``): one per arc, pivot offset and L/D
STORED_FORMATS = (tb.FORMAT,)  # the kinds of data file the store keeps (a file option's ``file_format``)


@dataclass(frozen=True)
class MapSettings:
    """What determines a map besides the bearing's L/D and bore (None: not an axis of this map)."""

    n_eps: int
    n_beta: int
    n_phi: int | None  # grooved or partial-arc bore only
    eps_max: float
    n_theta: int
    n_x: int
    cavitation: str
    n_phase: int
    flows: bool = True
    n_sup: int | None = None  # fed grooves only: points in u of the 4-D map (supplymap)


def map_bearing(params: BearingParams) -> BearingParams:
    """The bearing whose bore a map of ``params`` tabulates: ``params`` itself, or for a tilting-pad bore
    the circular partial arc every pad is in its own frame (clearance C_pad; ``tilting_pad.padmap``: one
    map serves every pad and tilt, the preload a shift of the journal)."""
    if params.geometry.pads is None:
        return params
    from ..tilting_pad.padmap import pad_arc_params

    return pad_arc_params(params)


def settings_for(params: BearingParams, *, resolution=None, n_phi=None, grid=None, cavitation: str = "reynolds",
                 eps_max: float | None = None, phases: int | None = None, n_sup: int | None = None) -> MapSettings:
    """The settings of a map of ``params``' bore: the given ones, the rest the bore's defaults
    (the full bore's 2-D map, the grooved bore's 3-D map or, fed grooves, its 4-D map with ``n_sup``
    points in u; the Reynolds solver's grid). Tilting pads:
    the pads' arc map (``map_bearing``), ``grid``'s n_theta the cells on each pad's arc as the
    tilting_pad internal's option (default its own), the force only (the pads have no film report)."""
    from ...physics.solver.reynolds import Reynolds

    pads = params.geometry.pads is not None
    if pads:
        from ..tilting_pad.padmap import pad_map_cells

        grid = (pad_map_cells(params, grid[0] if grid else None), grid[1] if grid else None)
        params = map_bearing(params)
    full = params.geometry.is_full_bore
    rey = Reynolds(params, *(grid or (None, None)), cavitation)  # the solver's own defaults and checks
    n_eps, n_beta = resolution or ((tb.DEFAULT_N_EPS, tb.DEFAULT_N_BETA) if full else (
        (PAD_MAP_N_EPS, PAD_MAP_N_BETA) if pads else (gm.DEFAULT_N_EPS, gm.DEFAULT_N_BETA)))
    return MapSettings(n_eps, n_beta, None if full else (n_phi or gm.default_n_phi(params.geometry)),
                       tb.DEFAULT_EPS_MAX if eps_max is None else float(eps_max), rey.n_theta, rey.n_x, rey.cavitation,
                       phases or (tb.DEFAULT_N_PHASE if full else gm.DEFAULT_N_PHASE), flows=not pads,
                       n_sup=(n_sup or DEFAULT_N_SUP) if params.geometry.supply_pressure > 0.0 else None)


def map_key(params: BearingParams, settings: MapSettings) -> str:
    """The content hash of the map of ``params``' L/D and bore with ``settings`` (hex sha256)."""
    full = params.geometry.is_full_bore
    rec = {"L_over_D": f"{params.L / params.D:.10g}", "bore": None if full else gm.geometry_record(params.geometry),
           **asdict(settings), "solver": source_digest(*SOLVER_PARTS)}
    if settings.n_sup is None:  # every map but the fed grooves' keeps the key it had before they had one
        del rec["n_sup"]
    else:  # fed grooves: the 4-D map serves any p_s > 0 (supplymap), the key says the grooves are fed
        rec["supply"] = {"fed": params.geometry.supply_pressure > 0.0, "code": source_digest(SUPPLY_PART)}
    return hashlib.sha256(json.dumps(rec, sort_keys=True).encode()).hexdigest()


def store_path(params: BearingParams, settings: MapSettings) -> Path:
    """Where the store keeps this map (whether it is there or not)."""
    bore = "full" if params.geometry.is_full_bore else ("arc" if params.geometry.arc is not None else "grooved")
    bore += "_fed" if settings.n_sup is not None else ""
    return map_store() / f"map_LD{params.L / params.D:.4g}_{bore}_{map_key(params, settings)[:20]}.json"


def stored_map(params: BearingParams, settings: MapSettings | None = None) -> Path | None:
    """The store's map of ``params``' L/D and bore (default settings unless given; tilting pads: the
    pads' arc map, ``map_bearing``), or None."""
    path = store_path(map_bearing(params), settings or settings_for(params))
    return path if path.is_file() else None


def describe(path: Path) -> str:
    """'built DATE from BEARING' of a stored map, from its provenance (best effort)."""
    try:
        prov = json.loads(Path(path).read_text()).get("provenance", {})
        return f"built {prov.get('date', '?')} from {prov.get('bearing_file', '?')}"
    except (OSError, ValueError, AttributeError):
        return "unreadable provenance"


def stored_file(file_format: str, bearings) -> tuple[Path | None, str]:
    """(the store's file of ``file_format`` for every bearing of ``bearings``, a line saying which)
    or (None, why): one map serves one L/D and bore, and it must have been built (``bearing-fmu map
    --bearing FILE``); (None, '') for a kind of file the store does not keep (it keeps force maps)."""
    if file_format not in STORED_FORMATS:
        return None, ""
    bearings = list(bearings)
    if not bearings:
        return None, "no bearing to find a map for"
    first = bearings[0]
    for k, p in enumerate(bearings[1:], 2):
        if abs(p.L / p.D - first.L / first.D) > tb.LD_RTOL * first.L / first.D or p.geometry != first.geometry:
            return None, (f"bearing {k} has another L/D or bore than bearing 1 and one map file serves one of them: "
                          "name the map")
    why = map_problem(first.geometry)
    if why:
        return None, f"no map serves this bore: {why}"
    arc, grid = map_params(first)  # a lobed bore's map is its lobe's (lobemap); any other bore's its own
    path = stored_map(arc, None if grid is None else settings_for(arc, grid=grid))
    if path is None:
        return None, (f"the map store {map_store()} has no map for L/D {first.L / first.D:.4g}, "
                      f"{first.geometry.describe()} at the default settings: build it once with "
                      "`bearing-fmu map --bearing FILE` (it goes into the store)")
    return path, f"the map store's map for L/D {first.L / first.D:.4g}, {first.geometry.describe()}: {path} " \
                 f"({describe(path)})"
