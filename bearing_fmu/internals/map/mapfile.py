"""Any force map file: the full bore's 2-D table (version 1; version 3 with its flow tables,
``forcemap``) or a grooved or partial-arc bore's 3-D table (version 2; version 4 with its flow
tables, ``groovemap``) or fed grooves' 4-D table (version 6; 7 with its flow tables, ``supplymap``),
and the map internal for each (a lobed bore's: ``lobemap``, the sum of its
lobes' partial-arc maps, from the 3-D map of its lobe's arc)."""

from __future__ import annotations

import copy
import json
from pathlib import Path

from ...physics.params import BearingParams
from .forcemap import ForceMap
from .groovemap import FLOW_VERSION as GROOVED_FLOW_VERSION
from .groovemap import VERSION as GROOVED_VERSION
from .groovemap import GroovedForceMap, GroovedMapTable, grooved_from_data
from .lobemap import LobedForceMap
from .supplymap import FLOW_VERSION as SUPPLY_FLOW_VERSION
from .supplymap import VERSION as SUPPLY_VERSION
from .supplymap import SupplyForceMap, SupplyMapTable, supply_from_data
from .tablefile import load_map
from .tables import FLOW_VERSION, FORMAT, MapTable

VERSIONS = (1, GROOVED_VERSION, FLOW_VERSION, GROOVED_FLOW_VERSION, SUPPLY_VERSION, SUPPLY_FLOW_VERSION)


_READ: dict = {}  # (path, mtime, size) -> the table read: a file is parsed once per process


def load_any_map(path) -> MapTable | GroovedMapTable:
    """The table of a map file of either version, checked as its loader checks it. A file read
    before in this process and unchanged since (path, modification time, size) is not parsed again:
    each bearing of a run and each run of a sweep's worker gets a copy of the table read first."""
    path = Path(path)
    try:
        st = path.stat()
        key = (str(path.resolve()), st.st_mtime_ns, st.st_size)
    except OSError:
        return _load_any_map(path)  # not there: the loader names it
    if key not in _READ:
        _READ[key] = _load_any_map(path)
    return copy.deepcopy(_READ[key])  # a caller may change its table; the kept one stays as read


def _load_any_map(path: Path) -> MapTable | GroovedMapTable:
    try:
        data = json.loads(path.read_text())
    except (FileNotFoundError, json.JSONDecodeError):
        return load_map(path)  # its messages for a missing or damaged file
    grooved = (GROOVED_VERSION, GROOVED_FLOW_VERSION)
    if isinstance(data, dict) and data.get("format") == FORMAT and data.get("version") in grooved:
        return grooved_from_data(path, data)
    if isinstance(data, dict) and data.get("format") == FORMAT and data.get("version") in (SUPPLY_VERSION,
                                                                                           SUPPLY_FLOW_VERSION):
        return supply_from_data(path, data)
    if isinstance(data, dict) and data.get("format") == FORMAT and data.get("version") not in VERSIONS:
        raise ValueError(f"force map file {path}: version {data.get('version')!r}, this code reads 1 and "
                         f"{FLOW_VERSION} (the full bore's 2-D map, {FLOW_VERSION} with flow tables), "
                         f"{GROOVED_VERSION} and {GROOVED_FLOW_VERSION} (a grooved or partial-arc bore's 3-D map, "
                         f"{GROOVED_FLOW_VERSION} with flow tables), {SUPPLY_VERSION} and {SUPPLY_FLOW_VERSION} (fed "
                         f"grooves' 4-D map, {SUPPLY_FLOW_VERSION} with flow tables)")
    return load_map(path)


def map_internal(params: BearingParams, table, source: str = "", hint: str = ""):
    """The map internal of a loaded table for ``params`` (refusing another L/D or bore; ``hint``
    added to the refusal of a grooved map for a full-bore bearing)."""
    if not isinstance(table, GroovedMapTable):
        return ForceMap(params, table, source)
    if isinstance(table, SupplyMapTable):  # fed grooves (supplymap)
        return SupplyForceMap(params, table, source)
    if params.geometry.lobes > 1:  # the sum of its lobes' partial-arc maps (lobemap)
        return LobedForceMap(params, table, source)
    try:
        return GroovedForceMap(params, table, source)
    except ValueError as exc:
        if hint and params.geometry.is_full_bore:
            raise ValueError(f"{exc}; {hint}") from None
        raise


def open_map(path, params: BearingParams):
    return map_internal(params, load_any_map(path), str(path))


def from_options(params: BearingParams, options, context):
    """The registry's factory of the ``map`` internal."""
    if not options["map"]:
        raise ValueError("internal 'map' needs the option map (a force map JSON file)")
    return open_map(context.path(options["map"]), params)
