"""Every pad of a tilting-pad bearing from one 3-D partial-arc force map (the pad model "map").

A pad's film in its own frame (``physics.bore.pads``, *The pad frame*) is

    h = C_pad - d cos(theta - pi) - e' . u(theta) = C_pad - (e' + d u(pi)) . u(theta),   u(pi) = (0, -1),

with e' the pad's equivalent journal (the journal turned into the frame, plus the tilt's a delta
along y'): the film of a *circular* partial arc of clearance C_pad, [pi - o beta, pi + (1 - o) beta],
with the journal at e' + (0, -d). So the grooved bores' 3-D map (F = S r G(eps, phi, beta), exact
for a circular film with ambient edges: docs/forcemap.md) of that arc, built once with CR = C_pad,
serves every pad of every bearing with this arc, offset, L/D and pad clearance ratio, at every tilt
(a tilt is a journal motion across the pad) and speed; its derivatives are the map's (the shift is
a constant). ``build_pad_map`` tabulates it from the Reynolds solver (``map.groovemap``'s builder,
unchanged); ``PadMapSolver`` answers as the pad's Reynolds solver does.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

from ...physics.bore.geometry import Geometry
from ...physics.bore.pads import PAD_FRAME_PIVOT
from ...physics.params import BearingParams


def pad_arc_params(params: BearingParams) -> BearingParams:
    """The circular partial arc every pad of ``params``' tilting-pad bore is (clearance C_pad [m])."""
    pg = params.geometry.pads
    o, b = pg.offset, pg.arc
    return replace(params, CR=pg.pad_clearance(params.CR),
                   geometry=Geometry(arc=(PAD_FRAME_PIVOT - o * b, PAD_FRAME_PIVOT + (1.0 - o) * b)))


def pad_map_cells(params: BearingParams, n_theta: int | None = None) -> int:
    """The Reynolds cells around the pads' arc bore of a pads' map: ``n_theta`` on each pad's arc (None:
    the tilting-pad internal's default, ``PadAssembly.default_cells``), plus the cell outside the arc,
    so the map's pads are the Reynolds pads of the internal at that grid."""
    from .assembly import PadAssembly

    cells = PadAssembly.default_cells(params.geometry.pads) if n_theta is None else n_theta
    return cells + len(pad_arc_params(params).geometry.segments()[0]) - 1


def build_pad_map(params: BearingParams, *, n_theta: int | None = None, n_x: int | None = None, workers: int = 1,
                  **sizes):
    """The pads' 3-D map (a ``GroovedMapTable``, force only) of ``params``' tilting pads from the Reynolds
    solver, ``n_theta`` cells on each pad's arc (None: the tilting-pad internal's default) x ``n_x``;
    ``sizes``: n_eps, n_phi, n_beta, eps_max, n_phase of ``tabulate_grooved``. (``bearing-fmu map --bearing
    FILE`` builds the same table as row tasks into the map store: ``internals.map.build``.)"""
    from ..map.groovemap import tabulate_grooved

    return tabulate_grooved(pad_arc_params(params), n_theta=pad_map_cells(params, n_theta), n_x=n_x,
                            workers=workers, flows=False, **sizes)


class PadMapSolver:
    """Pad force in its frame from the pads' map ``table`` (a ``GroovedMapTable`` or its file): the
    partial-arc solver's ``force_and_jacobian(y', z', vy', vz', omega)`` with the journal shifted by the
    preload (module docstring)."""

    def __init__(self, params: BearingParams, table):
        from ..map.groovemap import GroovedForceMap
        from ..map.mapfile import load_any_map

        arc = pad_arc_params(params)
        if isinstance(table, (str, Path)):
            source = str(table)
            table = load_any_map(table)
        else:
            source = "(in memory)"
        self.map = GroovedForceMap(arc, table, source)
        self.shift = arc.CR - params.CR  # d = C_pad - C_bearing [m]
        self.params = arc

    def y_range(self, z: float) -> tuple[float, float]:
        """The y' [m] the map covers at z' (its eps < eps_max of C_pad about the shifted centre): a tilt
        moves the pad's journal along y', so this bounds the tilts (``PadAssembly.tilt_range``). The
        partial-arc Reynolds solver also takes a journal beyond the pad's circle past its edges; the
        map does not, which only the widest tilts of an equilibrium's bracket reach."""
        r = self.map._eps_max * (1.0 - 1e-9) * self.params.CR
        zc = z - self.shift
        if abs(zc) >= r:
            return 0.0, 0.0
        w = math.sqrt(r * r - zc * zc)
        return -w, w

    def force_and_jacobian(self, y, z, vy, vz, omega):
        return self.map.force_and_jacobian(y, z - self.shift, vy, vz, omega)

    def force(self, y, z, vy, vz, omega):
        return self.map.force(y, z - self.shift, vy, vz, omega)


__all__ = ["pad_arc_params", "pad_map_cells", "build_pad_map", "PadMapSolver"]
