"""``bearing-fmu map``: a bearing's force map built as row tasks, resumed after an interrupt, kept
in the map store.

The table's eps rows are the tasks (``parallel.rows``): a row of the full bore's default map is
96 x 4 x 2 Reynolds solves (about 0.5 s), of a grooved bore's 32 x 64 (about 1 s), hundreds of
times the scheduler's cost per task (docs/forcemap.md, "Building on a cluster"). They run on an
existing Dask scheduler (``scheduler``, checked first), on a local Dask cluster (``"local"``) or,
by default, on a local process pool of ``workers`` processes (the same processes without a
scheduler: on one machine it starts faster and runs as fast). Each row is appended to the partial
file beside the map (``MAP.partial``) as it comes; an interrupted build, or one whose workers
died, resumes from it when run again and says so. The finished map goes into the map store
(``store``) and, when asked, to ``output``; a map already in the store is copied, not built again
(``rebuild`` builds it anyway).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from ...io.interrupts import note_kept, note_lost
from ...physics.params import PAPER_BEARING, BearingParams
from . import groovemap as gm
from . import supplymap as sm
from .store import MapSettings, describe, map_bearing, map_key, settings_for, store_path
from .tablefile import save_map
from .tables import tabulate

LOCAL = "local"  # --scheduler local: a LocalCluster on this machine


def n_rows(settings: MapSettings) -> int:
    """The build's row tasks: one per eps, or per (eps, u) for fed grooves' 4-D map."""
    return settings.n_eps * (settings.n_sup or 1)


def partial_path(target: Path) -> Path:
    """The partial file of a build whose map goes to ``target``."""
    return target.with_name(target.name + ".partial")


CONNECT_TIMEOUT_S = 15.0  # [s] for a scheduler to accept the connection (as the sweep's)


def build_map(params: BearingParams, settings: MapSettings, partial: Path, *, workers: int = 1,
              scheduler: str | None = None, progress=None, log=None, bearing_file: str = ""):
    """The table of ``params``' map with ``settings``, its rows streamed into ``partial`` and
    resumed from it (``log(line)`` says so); on the process pool of ``workers``, or on Dask
    (``scheduler``: an address or ``LOCAL``). ``progress``: None, or ``progress(n_resumed)`` gives
    the callable called with the rows done after each row. The partial file is removed once the
    table is whole."""
    import hashlib
    from contextlib import ExitStack

    from ...parallel.rows import Partial

    with ExitStack() as stack:
        client = None
        if scheduler is not None:  # connected (or refused) before any file is written
            from ...parallel.cluster import dask_client

            client = stack.enter_context(dask_client(None if scheduler == LOCAL else scheduler, workers,
                                                     CONNECT_TIMEOUT_S))
        key = hashlib.sha256(f"{map_key(params, settings)} {params!r}".encode()).hexdigest()  # the rows' own inputs
        part = Partial(partial, key, n_rows(settings))
        done = part.load()
        if done and log is not None:
            log(f"resuming: {len(done)} of {n_rows(settings)} rows already solved in {partial}")
        part.start(resumed=bool(done))
        kw = dict(n_eps=settings.n_eps, n_beta=settings.n_beta, eps_max=settings.eps_max, n_theta=settings.n_theta,
                  n_x=settings.n_x, cavitation=settings.cavitation, n_phase=settings.n_phase, flows=settings.flows,
                  workers=workers, progress=progress(len(done)) if progress is not None else None, partial=part,
                  done=done, client=client)
        if settings.n_phi is None:
            table = tabulate(params, **kw)
        elif settings.n_sup is not None:
            table = sm.tabulate_supplied(params, n_phi=settings.n_phi, n_sup=settings.n_sup, **kw)
        else:
            table = gm.tabulate_grooved(params, n_phi=settings.n_phi, **kw)
    table.provenance.update(bearing_file=bearing_file or "paper bearing (Table 2)", resumed_rows=len(done),
                            store_key=map_key(params, settings))
    part.remove()
    return table


def save_any(table, path) -> Path:
    """The map file of a full-bore or grooved table."""
    return gm.save_grooved_map(table, path) if isinstance(table, gm.GroovedMapTable) else save_map(table, path)


def command(*, bearing=None, output=None, resolution=None, n_phi=None, grid=None, cavitation="reynolds",
            eps_max=None, phases=None, workers=None, scheduler=None, quiet=False, rebuild=False) -> int:
    """``bearing-fmu map`` of parsed options (``bearing``: a bearing file, default the paper bearing)."""
    import os
    import shutil

    from ...io.cache import cache_dir
    from ...io.outputs import ensure_output_file
    from .lobemap import map_params, map_problem

    if output is not None:
        ensure_output_file(output, "-o/--output")
    params = BearingParams.from_toml(bearing) if bearing else PAPER_BEARING
    name = str(bearing) if bearing else "the paper bearing"
    why = map_problem(params.geometry)
    if why:
        raise ValueError(f"map: {bearing}: [geometry] {why}")
    if params.geometry.lobes > 1:  # its map is its lobe's partial arc's, on the lobe's cells of its grid (lobemap)
        lobed = params.geometry.describe()
        try:
            params, grid = map_params(params, grid)
        except ValueError as exc:
            raise ValueError(f"map: --grid: {exc}") from None
        print(f"{name}: {lobed}; its map is the lobes' partial arc ({params.geometry.describe()}, C_pad = "
              f"{params.CR * 1e6:.6g} um, {grid[0] - 1} cells on the arc as on each lobe), summed over the lobes")
    if n_phi is not None and params.geometry.is_full_bore:
        raise ValueError(f"map: --phi-points is for a grooved or partial-arc bore; {name} has the full bore (its map "
                         "is 2-D)")
    settings = settings_for(params, resolution=resolution, n_phi=n_phi, grid=grid, cavitation=cavitation,
                            eps_max=eps_max, phases=phases)
    pads = params.geometry.pads
    if pads is not None:  # the pads' partial-arc map: one arc serves every pad and tilt (tilting_pad.padmap)
        params = map_bearing(params)
    cache_dir(store=True)
    stored = store_path(params, settings)
    if stored.is_file() and not rebuild:
        if output is not None:
            shutil.copyfile(stored, output)
        print(f"force map for L/D = {params.L / params.D:.6g}, {params.geometry.describe()}: found in the map store, "
              f"{stored} ({describe(stored)}); {f'copied to {output}' if output is not None else 'nothing to build'} "
              "(--rebuild builds it again)")
        return 0
    target = Path(output) if output is not None else stored
    partial = partial_path(target)
    rows = n_rows(settings)
    workers = workers if workers is not None else min(os.cpu_count() or 1, max(1, rows // 8))
    bars = []

    def progress(resumed: int):  # the bar starts at the rows resumed: its rate and time left count this run's
        from tqdm import tqdm

        bore = "" if settings.n_phi is None else ", grooved"
        bars.append(tqdm(total=rows, initial=resumed, unit="row",
                         desc=f"force map L/D {params.L / params.D:.4g}{bore}"))
        return lambda k: bars[0].update(k - bars[0].n)

    table = None
    try:
        try:
            table = build_map(params, settings, partial, workers=workers, scheduler=scheduler,
                              progress=None if quiet else progress, log=lambda line: print(line, file=sys.stderr),
                              bearing_file=str(bearing or ""))
            if pads is not None:
                table.provenance["pads"] = (f"the pads' map of {pads.describe()}: each pad in its frame is this arc "
                                            f"(clearance C_pad = {params.CR:.6g} m) with the journal shifted by the "
                                            "preload; tilting_pad's option pad_map")
        finally:
            for bar in bars:
                bar.close()
        path = save_any(table, target)
        if target != stored:
            save_any(table, stored)
    except KeyboardInterrupt as exc:  # wherever it lands: the map if it is whole, else the rows kept
        if table is not None:
            note_kept(exc, f"{save_any(table, target)} (the map was complete)")
        elif getattr(exc, "map_rows_done", 0) and partial.is_file():
            note_kept(exc, f"{exc.map_rows_done} of {rows} rows of the map in {partial} (run the same "
                           "command again to resume)")
        else:
            partial.unlink(missing_ok=True)
            note_lost(exc, f"0 of {rows} rows of the map had been computed")
        raise
    except RuntimeError as exc:  # a worker died, a row failed on the cluster
        raise RuntimeError(f"map: {exc}; {getattr(exc, 'map_rows_done', 0)} of {rows} rows kept in "
                           f"{partial}: run the same command again to resume") from None
    where = f"{scheduler if scheduler not in (None, LOCAL) else 'this machine'}"
    how = f"{workers} process(es)" if scheduler is None else f"Dask ({'a local cluster' if scheduler == LOCAL else where})"
    axes = (f"{settings.n_eps} x {settings.n_beta} points" if settings.n_phi is None else
            f"{settings.n_eps} x {settings.n_phi} x {settings.n_beta} points (eps x phi over "
            f"{math.degrees(table.period):g} deg x beta)" if settings.n_sup is None else
            f"{settings.n_eps} x {settings.n_phi} x {settings.n_beta} x {settings.n_sup} points (eps x phi over "
            f"{math.degrees(table.period):g} deg x beta x u = p_s / (p_s + mu (R/CR)^2 r): the fed grooves' 4-D "
            "map, any supply pressure)")
    resumed = table.provenance["resumed_rows"]
    print(f"force map for L/D = {table.L_over_D:.6g}{'' if settings.n_phi is None else ', ' + params.geometry.describe()}"
          + ("" if pads is None else f" (every pad of the {pads.n} tilting pads: tilting_pad's option pad_map)")
          + f": {axes}, eps <= {table.eps_max:g}, Reynolds {table.n_theta} x {table.n_x} ({table.cavitation}), "
          f"{table.provenance['solves']} solves{f' ({resumed} rows resumed)' if resumed else ''} in "
          f"{table.provenance['built_s']:.1f} s on {how}; wrote {path} ({path.stat().st_size / 1e3:.0f} kB)"
          + (f" and the map store's {stored}" if target != stored else " (the map store)"))
    return 0
