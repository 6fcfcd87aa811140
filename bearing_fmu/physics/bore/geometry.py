"""The bore of a bearing: axial grooves, a partial arc, lobes with preload (the ``[geometry]``
table of a bearing file). Absent, the bore is the full 360 deg circle (``FULL_BORE``).

Angles are the theta of DESIGN.md's film h = CR + y sin(theta) - z cos(theta): theta = 0 is the
top of the bore (+z), 90 deg the side at -y, 180 deg the bottom, 270 deg the side at +y; the
journal surface moves toward increasing theta for omega > 0. Files give degrees and kPa, the
``Geometry`` holds radians and Pa.

Grooves, arcs
-------------
An axial groove of width ``groove_width`` centred at each ``grooves`` angle runs the whole length
at the supply pressure (Dirichlet on its cells; ambient, 0, by default). ``arc = (start, end)``
keeps the film only from start to end (increasing theta); outside it p = 0 (ambient). Their
edges are cell faces of the solver's grid (``theta_grid``), so the Dirichlet value sits on the
edge itself, not half a cell beyond.

The film of a lobed bore (the derivation)
-----------------------------------------
Each of the N lobes is a circular arc of radius R + C_pad about its own centre O_k. With the
journal centred, the lobe's clearance is smallest, C_bearing = CR (the file's ``CR_um``: the
clearance of the assembled bore, what a feeler gauge measures), at its preload point theta_p,k;
the preload is m = 1 - C_bearing / C_pad, so C_pad = CR / (1 - m).
Write u(theta) = (-sin theta, cos theta) for the unit vector (y, z) from the bearing centre O
toward the bore at theta (theta = 0: up; the film h = CR - e . u(theta) for a journal centre at
e = (y, z) in a circular bore is DESIGN.md's h = CR + y sin(theta) - z cos(theta)). The bore
point at theta_p,k is at O + (R + CR) u(theta_p,k), and it lies on the lobe's circle, so
O_k = O - d u(theta_p,k) with d = C_pad - CR = m C_pad: each lobe's centre is moved away from
the lobe, along its preload direction. With h << R the film along the ray at theta is the lobe
radius minus the distance from O_k to the journal surface, to first order in (e - O_k)/R:

    h = (R + C_pad) - R - (e - O_k) . u(theta) = C_pad - e . u(theta) + O_k . u(theta)
      = C_pad - d cos(theta - theta_p,k) + y sin(theta) - z cos(theta),

since u(theta_p,k) . u(theta) = cos(theta - theta_p,k). Scaled by CR:
h / CR = (1 - m cos(theta - theta_p,k)) / (1 - m) + (y sin(theta) - z cos(theta)) / CR. Checks:
m = 0 gives the circular film; at theta_p,k with e = 0, h = C_pad - d = CR; the film is >= CR - |e|
everywhere, so a journal inside the circle of radius CR never touches a lobe.

Lobe k spans 360/N deg centred at ``lobe_angle`` + k 360/N; its leading edge (the one the
journal surface reaches first for omega > 0) is at theta_lead,k = lobe_angle + (k - 1/2) 360/N
and its preload point at theta_p,k = theta_lead,k + ``lobe_offset`` 360/N: offset 0.5 puts it
mid-lobe (elliptical or lemon bore with N = 2: lobes at top and bottom for lobe_angle = 0),
offset 1.0 at the trailing edge (offset halves with N = 2: every lobe converges all the way).
The offset is over the whole lobe, from lobe boundary to lobe boundary, grooves included
(ROSS measures it over the pad between grooves; the same for offset 0.5). With offset 0.5 the
film is continuous at the lobe boundaries; otherwise it steps there, and a step lies inside a
groove or outside the arc (``check`` refuses it anywhere else: the solver's face fluxes assume
a continuous film).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...io.schema import Choice, Key, List, Number
from .pads import PAD_KEYS, PadGeometry, pads_from_mapping
from .thetagrid import ThetaGrid

TWO_PI = 2.0 * math.pi
MAX_LOBES = 8
MAX_SUPPLY_KPA = 10_000.0  # 10 MPa: feed pressures are 0.05-0.5 MPa, hydrostatic pockets a few MPa
MIN_PAD_DEG = 5.0  # the film between two edges (a pad, an arc) is at least this wide
# feed = "thickest": the feed line's width, one cell of the default grid (the line of Raimondi & Boyd)
FEED_WIDTH_DEG = 360.0 / 128
FEEDS = ("film", "thickest")
_SNAP = 1e-9  # [rad] edges closer than this are one edge


def _deg(x: float) -> str:
    return f"{math.degrees(x):.6g} deg"


# the keys of the [geometry] table: each carries its unit; checked by the schema (type, range),
# what depends on several keys by Geometry.check (naming the keys)
GEOMETRY_KEYS = (
    Key("grooves_deg", "axial groove centres, in the film's theta (0 top, 90 and 270 the horizontal split, "
        "increasing with the rotation) [deg]", [], "angles, taken modulo 360", kind=List(Number())),
    Key("groove_width_deg", "width of every groove [deg] (with grooves_deg)", 20.0, "> 0 and < 180",
        kind=Number(0.0, 180.0, exclusive_minimum=True, exclusive_maximum=True)),
    Key("circumferential_groove_mm", "width of a 360 deg feed groove at mid-length [mm]: the film in two lands of "
        "(L - width) / 2, fed along the groove at supply_pressure_kPa (the plain circular bore only)", 0.0,
        "0 (none) or > 0 and < L", kind=Number(0.0)),
    Key("supply_pressure_kPa", "oil pressure in the grooves above ambient [kPa] (with grooves_deg or "
        "circumferential_groove_mm)", 0.0,
        f"0 .. {MAX_SUPPLY_KPA:g}", kind=Number(0.0, MAX_SUPPLY_KPA)),
    Key("arc_deg", "a partial arc [start, end]: film only from start to end in increasing theta, ambient "
        "outside [deg]", None, "end - start in (0, 360)", kind=List(Number(), length=2)),
    Key("lobes", "number of lobes of the bore (1: circular)", 1, f"1 .. {MAX_LOBES}",
        kind=Number(1, MAX_LOBES, integer=True)),
    Key("preload", "m = 1 - C_bearing / C_pad (CR_um is C_bearing, the assembled clearance)", 0.0,
        "0 <= m < 1; > 0 needs lobes >= 2 or pads", kind=Number(0.0, 1.0, exclusive_maximum=True)),
    Key("lobe_offset", "where the lobe's clearance is smallest, as a fraction of the lobe from its leading "
        "edge (0.5 symmetric, 1.0 offset halves)", 0.5, "0 .. 1", kind=Number(0.0, 1.0)),
    Key("lobe_angle_deg", "theta of the middle of the first lobe [deg] (0: lobes centred at the top, and "
        "for 2 lobes at the bottom)", 0.0, "an angle", kind=Number()),
    Key("feed", "where a plain full bore takes its oil in: 'film' (wherever the film reforms, Swift-Stieber) "
        "or 'thickest' (along the line of thickest film at the static equilibrium, as Raimondi & Boyd's full "
        f"bearing: an ambient feed line {FEED_WIDTH_DEG:.4g} deg wide, placed by iteration with the load)", "film",
        "film or thickest; thickest on the plain full bore only", kind=Choice(FEEDS)),
    *PAD_KEYS,  # a tilting-pad bore (physics.bore.pads)
)


def _wrap(a: float) -> float:
    """An angle [rad] in [0, 2 pi)."""
    a = math.fmod(a, TWO_PI)
    return a + TWO_PI if a < 0.0 else (0.0 if a >= TWO_PI else a)


def _within(a: float, start: float, span: float, tol: float = _SNAP) -> bool:
    """Whether angle a [rad] lies in the arc [start, start + span] (tolerance tol)."""
    return _wrap(a - start + tol) <= span + 2.0 * tol


@dataclass(frozen=True)
class Geometry:
    """The bore of a bearing, in SI (angles in rad, pressure in Pa); see the module docstring.

    grooves         : axial groove centres [rad], sorted in [0, 2 pi)
    groove_width    : every groove's width [rad]
    supply_pressure : oil pressure in the grooves above ambient [Pa]
    circumferential_groove : width [m] of a 360 deg feed groove at mid-length (0: none); the film is
                      then two lands of (L - width) / 2 fed along it at supply_pressure (Dirichlet on
                      the lands' inner edges, ambient at the outer ends; plain circular bore only)
    arc             : (start, end) of a partial arc [rad], end - start in (0, 2 pi), or None
    lobes           : number of lobes (1: circular)
    preload         : m = 1 - C_bearing / C_pad, in [0, 1)
    lobe_offset     : preload point as a fraction of the lobe from its leading edge, in [0, 1]
    lobe_angle      : theta of the middle of the first lobe [rad]
    pads            : a tilting-pad bore (``physics.bore.pads.PadGeometry``; its preload its own), or None
    feed            : "film", or "thickest": the plain bore fed along its line of thickest film at the
                      static equilibrium; placed (``physics.bore.feed.place_feed``) it is one groove of
                      FEED_WIDTH_DEG there, unplaced (no groove yet) no solver takes it
    """

    grooves: tuple[float, ...] = ()
    groove_width: float = math.radians(20.0)
    supply_pressure: float = 0.0
    arc: tuple[float, float] | None = None
    lobes: int = 1
    preload: float = 0.0
    lobe_offset: float = 0.5
    lobe_angle: float = 0.0
    pads: PadGeometry | None = None
    feed: str = "film"
    circumferential_groove: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "grooves", tuple(sorted(_wrap(float(g)) for g in self.grooves)))
        if self.arc is not None:
            object.__setattr__(self, "arc", (float(self.arc[0]), float(self.arc[1])))
        object.__setattr__(self, "lobes", int(self.lobes))
        problem = self.check()
        if problem is not None:
            raise ValueError(f"Geometry: {problem}")

    # ------------------------------------------------------------------ what it is
    @property
    def is_full_bore(self) -> bool:
        """The plain 360 deg circular bore: the solver's original path, bit for bit."""
        return self.is_circle and self.feed == "film" and not self.circumferential_groove

    @property
    def is_circle(self) -> bool:
        """The film is the circular one all round (no axial groove, arc, lobes or pads): the full bore,
        or the lands of a circumferential groove (their film, closure and minimum in closed form)."""
        return not self.grooves and self.arc is None and self.lobes == 1 and self.pads is None

    @property
    def feed_unplaced(self) -> bool:
        """feed = "thickest" not yet placed at a static equilibrium (``physics.bore.feed.place_feed``)."""
        return self.feed == "thickest" and not self.grooves

    def require_placed(self, what: str) -> None:
        """ValueError for an unplaced feed line, naming ``what`` needed it placed."""
        if self.feed_unplaced:
            raise ValueError(f"{what}: feed = 'thickest' puts the feed line where the film is thickest at the static "
                             "equilibrium, which needs the static load and the speed (demo, run, stability and the "
                             "FMUs of a scene place it); to fix the line yourself, write feed = 'film' with "
                             "grooves_deg = [the angle demo prints]")

    def describe(self) -> str:
        """The bore in a few words (for messages and the demo)."""
        if self.is_full_bore:
            return "full 360 deg circular bore"
        if self.circumferential_groove:
            return (f"full 360 deg circular bore with a circumferential feed groove "
                    f"{self.circumferential_groove * 1e3:.4g} mm wide at mid-length (supply "
                    f"{self.supply_pressure / 1e3:.4g} kPa)")
        if self.feed == "thickest":
            return ("full 360 deg circular bore fed along the line of thickest film "
                    + (f"at {math.degrees(self.grooves[0]):.4g} deg (the static equilibrium's; an ambient line "
                       f"{math.degrees(self.groove_width):.3g} deg wide)" if self.grooves
                       else "(placed at the static equilibrium)"))
        if self.pads is not None:
            return self.pads.describe()
        parts = []
        if self.grooves:
            parts.append(f"{len(self.grooves)} axial groove{'s' if len(self.grooves) > 1 else ''} at "
                         + ", ".join(f"{math.degrees(g):.4g}" for g in self.grooves)
                         + f" deg ({math.degrees(self.groove_width):.4g} deg wide, supply "
                         f"{self.supply_pressure / 1e3:.4g} kPa)")
        if self.arc is not None:
            parts.append(f"partial arc {math.degrees(self.arc[0]):.4g} .. {math.degrees(self.arc[1]):.4g} deg")
        if self.lobes > 1:
            parts.append(f"{self.lobes} lobes, preload {self.preload:.4g}, offset {self.lobe_offset:.4g}, first "
                         f"lobe centred at {math.degrees(self.lobe_angle):.4g} deg")
        return "; ".join(parts)

    def lobe_boundaries(self) -> list[float]:
        """The lobes' boundaries [rad] (none for a circular bore)."""
        if self.lobes < 2:
            return []
        step = TWO_PI / self.lobes
        return [_wrap(self.lobe_angle + (k + 0.5) * step) for k in range(self.lobes)]

    def groove_edges(self) -> list[tuple[float, float]]:
        """(start, end) [rad] of every groove, start in [0, 2 pi), end = start + width."""
        w = self.groove_width
        return [(_wrap(g - 0.5 * w), _wrap(g - 0.5 * w) + w) for g in self.grooves]

    # ------------------------------------------------------------------ checks
    def check(self) -> str | None:
        """What does not fit together, naming the keys, or None."""
        w = self.groove_width
        if not (math.isfinite(w) and 0.0 < w < math.pi):
            return f"groove_width_deg = {math.degrees(w):.6g} must be > 0 and < 180"
        if not (math.isfinite(self.supply_pressure) and 0.0 <= self.supply_pressure <= MAX_SUPPLY_KPA * 1e3):
            return f"supply_pressure_kPa = {self.supply_pressure / 1e3:.6g} must be in 0 .. {MAX_SUPPLY_KPA:g}"
        c = self.circumferential_groove
        if not (math.isfinite(c) and c >= 0.0):
            return f"circumferential_groove_mm = {c * 1e3!r} must be >= 0"
        if c and not (self.is_circle and self.feed == "film"):
            return ("circumferential_groove_mm is the plain circular bore's feed (two lands fed along a 360 deg "
                    "groove): leave out grooves_deg, arc_deg, lobes, pads and feed = 'thickest'")
        if self.supply_pressure > 0.0 and not (self.grooves or c):
            return ("supply_pressure_kPa > 0 needs grooves_deg or circumferential_groove_mm (the oil is supplied "
                    "through the grooves)")
        if not 1 <= self.lobes <= MAX_LOBES:
            return f"lobes = {self.lobes} must be in 1 .. {MAX_LOBES}"
        if not (math.isfinite(self.preload) and 0.0 <= self.preload < 1.0):
            return f"preload = {self.preload!r} must be >= 0 and < 1"
        if self.preload > 0.0 and self.lobes < 2:
            return f"preload = {self.preload:g} needs lobes >= 2 (a preloaded bore has lobes; lobes = 1 is circular)"
        if not (math.isfinite(self.lobe_offset) and 0.0 <= self.lobe_offset <= 1.0):
            return f"lobe_offset = {self.lobe_offset!r} must be in 0 .. 1"
        if self.feed not in FEEDS:
            return f"feed = {self.feed!r} must be one of {', '.join(FEEDS)}"
        if self.feed == "thickest" and (len(self.grooves) > 1 or self.arc is not None or self.lobes > 1
                                        or self.pads is not None or self.supply_pressure > 0.0):
            return ("feed = 'thickest' is the plain full bore's feed line (Raimondi & Boyd's full bearing): leave out "
                    "grooves_deg, supply_pressure_kPa, arc_deg, lobes and pads, or use feed = 'film'")
        g = self.grooves
        min_pad = math.radians(MIN_PAD_DEG)
        if len(g) > 1:
            for i, (a, b) in enumerate(zip(g, g[1:] + (g[0] + TWO_PI,))):
                if b - a - w < min_pad:
                    return (f"grooves_deg: the grooves at {_deg(a)} and {_deg(_wrap(b))} overlap or leave less than "
                            f"{MIN_PAD_DEG:g} deg of film between them (groove_width_deg = {math.degrees(w):.6g}: "
                            f"centres must be at least {math.degrees(w + min_pad):.6g} deg apart)")
        if self.arc is not None:
            start, end = self.arc
            span = end - start
            if not (math.isfinite(start) and math.isfinite(end)) or not 0.0 < span < TWO_PI:
                return (f"arc_deg = [{math.degrees(start):.6g}, {math.degrees(end):.6g}]: end - start must be in "
                        "(0, 360) (a 360 deg arc is the full bore: leave arc_deg out)")
            if span < min_pad:
                return f"arc_deg spans {_deg(span)}: at least {MIN_PAD_DEG:g} deg of film"
            for (a, b), c in zip(self.groove_edges(), g):
                ins_a, ins_b = _within(a, start, span), _within(b, start, span)
                if not (ins_a and ins_b) or not _within(c, start, span):
                    return (f"grooves_deg: the groove at {_deg(c)} ({_deg(a)} .. {_deg(_wrap(b))}) is not inside "
                            f"arc_deg [{math.degrees(start):.6g}, {math.degrees(end):.6g}]: a groove lies within "
                            "the arc, its edges at most on the arc's edges")
        thin = self._thin_film(min_pad)
        if thin is not None:
            a, b = thin
            return (f"the film from {_deg(_wrap(a))} to {_deg(_wrap(b))} is {_deg(b - a)} wide: grooves_deg "
                    f"(groove_width_deg = {math.degrees(w):.6g}) and arc_deg must leave at least {MIN_PAD_DEG:g} deg "
                    "of film between a groove's edge and the next edge (another groove's, the arc's)")
        if self.lobes >= 2 and self.preload > 0.0 and abs(self.lobe_offset - 0.5) > 1e-12:
            for t in self.lobe_boundaries():
                if not self.is_prescribed(t):
                    return (f"lobe_offset = {self.lobe_offset:g} makes the film step at the lobe boundary at {_deg(t)}: "
                            "the boundary must lie inside a groove (grooves_deg) or outside arc_deg, as in an "
                            "offset-halves bearing with grooves at the split")
        return None

    def _thin_film(self, min_pad: float) -> tuple[float, float] | None:
        """(start, end) [rad] of the first stretch of film (consecutive segments without a prescribed
        pressure; a lobe boundary does not end one) narrower than ``min_pad`` [rad], or None."""
        if not self.grooves and self.arc is None:
            return None
        segs, fixed, _supply = self.segments()
        n, k0 = len(segs), fixed.index(True)
        start, width = None, 0.0
        for j in range(1, n + 1):
            a, b = segs[(k0 + j) % n]
            if not fixed[(k0 + j) % n]:
                start, width = (a if start is None else start), width + (b - a)
                continue
            if start is not None and width < min_pad - _SNAP:
                return start, start + width
            start, width = None, 0.0
        return None

    def is_prescribed(self, t: float) -> bool:
        """Whether angle t [rad] has a prescribed pressure (inside a groove, or outside the arc)."""
        for a, b in self.groove_edges():
            if _within(t, a, b - a, -_SNAP):
                return True
        if self.arc is not None:
            start, end = self.arc
            if not _within(t, start, end - start, _SNAP):
                return True
        return False

    # ------------------------------------------------------------------ the film
    def pad_clearance(self, CR: float) -> float:
        """C_pad = CR / (1 - m) [m] (CR for a circular bore)."""
        return CR / (1.0 - self.preload)

    def preload_points(self) -> np.ndarray:
        """theta_p,k [rad] of every lobe (see the module docstring)."""
        step = TWO_PI / max(self.lobes, 1)
        k = np.arange(max(self.lobes, 1))
        return self.lobe_angle + (k - 0.5 + self.lobe_offset) * step

    def lobe_of(self, theta) -> np.ndarray:
        """Index of the lobe each angle [rad] lies in (0 for a circular bore)."""
        theta = np.asarray(theta, float)
        if self.lobes < 2:
            return np.zeros(theta.shape, dtype=np.int64)
        step = TWO_PI / self.lobes
        return np.floor(np.mod(theta - self.lobe_angle + 0.5 * step, TWO_PI) / step).astype(np.int64) % self.lobes

    def base_film(self, theta, lobe=None) -> np.ndarray:
        """h / CR of the centred journal at angles theta [rad]: (1 - m cos(theta - theta_p,k)) / (1 - m),
        k the lobe of each angle (or ``lobe``, to take one lobe's side at a boundary)."""
        theta = np.asarray(theta, float)
        if self.lobes < 2 or self.preload == 0.0:
            return np.ones(theta.shape)
        k = self.lobe_of(theta) if lobe is None else np.asarray(lobe, dtype=np.int64)
        m = self.preload
        return (1.0 - m * np.cos(theta - self.preload_points()[k])) / (1.0 - m)

    def min_film(self, y: float, z: float, CR: float, n: int = 3600) -> float:
        """Smallest film thickness [m] over the film region (edges included), journal at (y, z) [m],
        sampled every 360/n deg and at every edge."""
        return self.min_film_at(y, z, CR, n)[0]

    def min_film_at(self, y: float, z: float, CR: float, n: int = 3600) -> tuple[float, float]:
        """(h_min [m], theta [rad]) of the smallest film over the film region, as ``min_film``; the full
        bore's exactly, at the angle opposite the journal's displacement."""
        if self.is_circle and (y or z):
            return CR - math.hypot(y, z), math.atan2(-y, z) % TWO_PI  # h = CR - e cos(theta - theta_min)
        th = np.concatenate([np.arange(n) * (TWO_PI / n), np.array(self.edges())])
        th = th[[not self.is_prescribed(t) for t in th]]
        h = CR * self.base_film(th) + y * np.sin(th) - z * np.cos(th)
        k = int(np.argmin(h))
        return float(h[k]), float(th[k] % TWO_PI)

    def closure(self, y: float, z: float, CR: float) -> float:
        """How far the journal at (y, z) [m] closes the film: max over the film of
        (e . u(theta)) / (CR H0(theta)), so that h = CR H0 (1 - that) >= 0 while it is < 1. For the
        full bore it is the eccentricity ratio |e| / CR (the same float operations as before); a
        lobed bore or a partial arc lets the journal beyond CR where its bore is farther away.
        Sampled every 0.1 deg and at every edge (the maximum between samples exceeds the sampled
        one by < 1e-6)."""
        if self.is_circle:
            return math.hypot(y, z) / CR
        a, b = self._closure_weights
        return float(np.max(y * a + z * b)) / CR

    def closure_weights(self) -> tuple[np.ndarray, np.ndarray]:
        """(-sin(theta), cos(theta)) / H0(theta) over the film's sample angles: ``closure`` is the
        largest y a + z b over them, divided by CR (the native solver checks the wall with them)."""
        return self._closure_weights

    @cached_property
    def _closure_weights(self) -> tuple[np.ndarray, np.ndarray]:
        """(-sin(theta), cos(theta)) / H0(theta) over the film's sample angles (see ``closure``)."""
        th = np.concatenate([np.arange(3600) * (TWO_PI / 3600), np.array(self.edges())])
        th = th[[not self.is_prescribed(t) for t in th]]
        h0 = self.base_film(th)
        if self.lobes > 1 and self.preload > 0.0:  # an edge on a lobe boundary: both sides' film
            lo = self.base_film(th, (self.lobe_of(th) - 1) % self.lobes)
            at_boundary = np.isin(th, np.array(self.lobe_boundaries()))
            h0 = np.where(at_boundary, np.minimum(h0, lo), h0)
        return -np.sin(th) / h0, np.cos(th) / h0

    def edges(self) -> list[float]:
        """Every angle [rad] the grid puts a cell face on: groove and arc edges, lobe boundaries."""
        out = [e for a, b in self.groove_edges() for e in (a, _wrap(b))]
        if self.arc is not None:
            out += [_wrap(self.arc[0]), _wrap(self.arc[1])]
        out += self.lobe_boundaries()
        out = sorted(out)
        merged: list[float] = []
        for e in out:
            if not merged or e - merged[-1] > _SNAP:
                merged.append(e)
        if len(merged) > 1 and merged[0] + TWO_PI - merged[-1] <= _SNAP:
            merged.pop()
        return merged

    # ------------------------------------------------------------------ the solver's grid
    def segments(self) -> tuple[list[tuple[float, float]], list[bool], list[float]]:
        """The stretches between consecutive ``edges``: ((start, end) [rad] with end > start, the
        last one wrapping past 2 pi), whether each has a prescribed pressure, and that pressure
        [Pa] (a groove's supply, 0 outside the arc). What ``theta_grid`` divides into cells (the
        native solver does the same from these, bearing_fmu/fmu/native/c/reynolds_solver.c)."""
        edges = self.edges()
        segs = [(a, b) for a, b in zip(edges, edges[1:] + [edges[0] + TWO_PI])]
        fixed = [self.is_prescribed(0.5 * (a + b)) for a, b in segs]
        supply = [self.supply_pressure if f and any(_within(0.5 * (a + b), ga, gb - ga) for ga, gb in
                                                    self.groove_edges()) else 0.0 for (a, b), f in zip(segs, fixed)]
        return segs, fixed, supply

    def supply_edges(self) -> list[tuple[float, float]]:
        """(theta [rad], sign) of every edge between a prescribed stretch and the film, in the order of
        ``segments`` (the solver's faces there, ``film.supply_edges``): sign +1 where the film lies
        beyond the edge in theta, -1 before it (the oil enters the film against theta there)."""
        segs, fixed, _supply = self.segments()
        n = len(segs)
        return [(segs[k][1] % TWO_PI, 1.0 if fixed[k] else -1.0) for k in range(n)
                if fixed[k] != fixed[(k + 1) % n]]

    def theta_grid(self, n_theta: int) -> ThetaGrid:
        """The circumferential cells of the Reynolds solver for this bore: a face on every edge
        (``edges``), one cell per groove and per stretch outside the arc (their pressure is
        prescribed), the other n_theta - (those) cells spread over the film segments in
        proportion to their length (uniform inside each, at least 2 per segment)."""
        if not self.edges():  # the circle all round (a circumferential groove's lands): the full bore's cells
            z, dth = np.zeros(n_theta), TWO_PI / n_theta
            return ThetaGrid(self, (np.arange(n_theta) - 0.5) * dth, np.full(n_theta, dth), z.astype(bool), z)
        segs, fixed, supply_of = self.segments()
        film = [k for k, f in enumerate(fixed) if not f]
        n_film = n_theta - (len(segs) - len(film))
        if n_film < 2 * len(film):
            raise ValueError(f"n_theta = {n_theta} is too few cells for this bore ({self.describe()}): it needs "
                             f"at least {2 * len(film) + len(segs) - len(film)}")
        length = np.array([segs[k][1] - segs[k][0] for k in film])
        ideal = n_film * length / length.sum()
        cells = np.maximum(2, np.floor(ideal)).astype(int)
        while cells.sum() < n_film:  # largest remainder first
            cells[int(np.argmax(ideal - cells))] += 1
        while cells.sum() > n_film:
            spare = np.where(cells > 2, cells - ideal, -np.inf)
            cells[int(np.argmax(spare))] -= 1
        count = dict(zip(film, cells.tolist()))
        left, width, is_fixed, supply = [], [], [], []
        for k, (a, b) in enumerate(segs):
            n = count.get(k, 1)
            left += [a + (b - a) * i / n for i in range(n)]
            width += [(b - a) / n] * n
            is_fixed += [fixed[k]] * n
            supply += [supply_of[k]] * n
        return ThetaGrid(self, np.array(left), np.array(width), np.array(is_fixed), np.array(supply))

    def as_table(self) -> dict:
        """The bore as a bearing file's [geometry] table writes it (degrees, kPa; only what
        differs from the defaults): what a surrogate file records; ``read_geometry`` reads it."""
        out: dict = {} if self.pads is None else self.pads.as_table()
        if self.grooves:
            out.update(grooves_deg=[math.degrees(g) for g in self.grooves],
                       groove_width_deg=math.degrees(self.groove_width),
                       supply_pressure_kPa=self.supply_pressure / 1e3)
        if self.arc is not None:
            out["arc_deg"] = [math.degrees(a) for a in self.arc]
        if self.lobes > 1:
            out.update(lobes=self.lobes, preload=self.preload, lobe_offset=self.lobe_offset,
                       lobe_angle_deg=math.degrees(self.lobe_angle))
        if self.feed != "film":
            out["feed"] = self.feed
        if self.circumferential_groove:
            out.update(circumferential_groove_mm=self.circumferential_groove * 1e3,
                       supply_pressure_kPa=self.supply_pressure / 1e3)
        return out

    def close_to(self, other: "Geometry", tol: float = 1e-9) -> bool:
        """The same bore to ``tol`` (radians, relative for the pressure): what a file recorded in
        degrees and read back compares equal to."""
        a, b = self.as_table(), other.as_table()
        if set(a) != set(b) or a.pop("feed", None) != b.pop("feed", None):
            return False
        flat = lambda t: np.concatenate([np.atleast_1d(np.asarray(t[k], float)) for k in sorted(t)]) if t else np.zeros(0)
        x, y = flat(a), flat(b)
        return x.shape == y.shape and bool(np.all(np.abs(x - y) <= tol * np.maximum(1.0, np.abs(x))))

    # ------------------------------------------------------------------ reading
    @classmethod
    def from_mapping(cls, d: dict, given: set, error) -> "Geometry":
        """From the schema-checked [geometry] values ``d`` (degrees, kPa); ``given`` the keys the
        file wrote; ``error(text)`` makes the exception (naming the file)."""
        pads = pads_from_mapping(d, given, error)  # a tilting-pad bore: its own keys (physics.bore.pads)
        if pads is not None:
            return cls(pads=pads)
        if d["feed"] == "thickest" and len(d["grooves_deg"]) > 1:
            raise error("feed = 'thickest' places one feed line itself: leave grooves_deg out (a file that records "
                        "a placed line has one angle there)")
        if d["groove_width_deg"] is not None and "groove_width_deg" in given and not d["grooves_deg"]:
            raise error("groove_width_deg needs grooves_deg (no groove is given)")
        for key in ("lobe_offset", "lobe_angle_deg"):
            if key in given and d["lobes"] < 2:
                raise error(f"{key} needs lobes >= 2")
        arc = d["arc_deg"]
        try:
            return cls(grooves=tuple(math.radians(g) for g in d["grooves_deg"]),
                       groove_width=math.radians(FEED_WIDTH_DEG if d["feed"] == "thickest"
                                                 and "groove_width_deg" not in given else d["groove_width_deg"]),
                       supply_pressure=d["supply_pressure_kPa"] * 1e3,
                       arc=None if arc is None else (math.radians(arc[0]), math.radians(arc[1])),
                       lobes=d["lobes"], preload=d["preload"], lobe_offset=d["lobe_offset"],
                       lobe_angle=math.radians(d["lobe_angle_deg"]), feed=d["feed"],
                       circumferential_groove=d["circumferential_groove_mm"] * 1e-3)
        except ValueError as exc:
            raise error(str(exc).removeprefix("Geometry: ")) from None


FULL_BORE = Geometry()
