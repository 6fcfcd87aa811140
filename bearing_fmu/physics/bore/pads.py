"""The bore of a tilting-pad journal bearing: N pads, each a partial arc free to rotate about its
pivot (the ``[geometry]`` keys ``pads``, ``pad_arc_deg``, ``pivots_deg``, ``pivot_offset``,
``preload``; optional ``pad_inertia_kg_m2``, ``pivot_stiffness_N_m``).

Angles are the theta of the film h = CR + y sin(theta) - z cos(theta) (``physics.bore.geometry``):
0 at the top (+z), 90 deg at -y, 180 deg at the bottom, 270 deg at +y, increasing with the
rotation. A pad's pivot is at theta_p (``pivots_deg``); the pad spans
[theta_p - o beta, theta_p + (1 - o) beta] with beta = ``pad_arc_deg`` and o = ``pivot_offset``
(the pivot's place from the leading edge, the one the journal surface reaches first: 0.5
centred, 0.6 the usual offset). Load between pads with 4 pads and the weight down:
pivots [45, 135, 225, 315]; load on pad: [0, 90, 180, 270].

The film of a tilted pad (the derivation)
-----------------------------------------
Write u(theta) = (-sin theta, cos theta) for the unit vector (y, z) from the bearing centre
toward the bore at theta (so a journal at e = (y, z) gives the circular film CR - e . u(theta),
DESIGN.md's h), and t_p = x x u(theta_p) = (-cos theta_p, -sin theta_p) for the unit tangent at
the pivot pointing toward increasing theta (x = y x z is the shaft axis; x x (y, z) = (-z, y)).

Preload: the pad's surface is a circle of radius R + C_pad whose centre lies on the line from
the bearing centre through the pivot, d = C_pad - CR = m C_pad beyond the bearing centre away from
the pad (m = ``preload`` = 1 - C_bearing / C_pad, C_bearing = ``CR_um``), so that the centred
journal has the clearance CR at the pivot. As for a lobe (``physics.bore.geometry``'s derivation), to
first order in the displacements over R:

    h0 = C_pad - d cos(theta - theta_p),      h0(theta_p) = C_pad - d = CR,

the film growing away from the pivot (d > 0: the pad converges toward the pivot from its leading
edge and diverges after it with the journal centred).

Tilt: the pad turns by delta (positive about +x, the sense of positive omega) about the pivot,
the point P = (R + C_pad) u(theta_p) of the pad's surface (the pad's thickness is not part of the
kinematics, as in Lund's and ROSS's pad models). The pad's surface point r = (R + C_pad) u(theta)
moves by delta x x (r - P); its outward (radial) part, which opens the film, is

    u(theta) . [delta x x (R + C_pad)(u(theta) - u(theta_p))] = -delta (R + C_pad) u(theta) . t_p
                                                           = -delta (R + C_pad) sin(theta - theta_p)

since u . (x x u) = 0 and u(theta) . t_p = sin(theta) cos(theta_p) - cos(theta) sin(theta_p). So

    h = C_pad - d cos(theta - theta_p) + y sin(theta) - z cos(theta) - delta (R + C_pad) sin(theta - theta_p).

Signs: a positive delta lifts the pad's trailing part (theta > theta_p) toward the journal
(h smaller there) and drops its leading part; delta = 0 is the pad of a fixed lobe. The tilt term is
exactly a journal displacement: -delta (R + C_pad) sin(theta - theta_p) = -(delta (R + C_pad) t_p) .
u(theta), so the pad's film is the fixed pad's film with the journal at the *equivalent* position
e + (R + C_pad) delta t_p and velocity v + (R + C_pad) ddelta/dt t_p (the squeeze term of the tilt
rate is the same substitution in dh/dt). Each pad is therefore solved by the existing partial-arc
solver unchanged (no new film term in a kernel), at that equivalent state.

The pad's moment about its pivot (about +x): the pressure pushes the pad's surface outward,
p dA u(theta) at r; (r - P) x p u(theta) = -(R + C_pad) p sin(theta - theta_p) (the x component of
u(a) x u(b) is sin(b - a)). With the film force on the journal F = -int p u(theta) dA (DESIGN.md's
(sin, -cos) direction), int p sin(theta - theta_p) dA = -F . t_p, so

    M = (R + C_pad) F . t_p = -(R + C_pad) (Fy cos(theta_p) + Fz sin(theta_p)):

the moment is the tangential part of the pad's journal force at the pivot, times the radius.
Virtual work checks it: a tilt d delta moves the equivalent journal by (R + C_pad) t_p d delta, and
the film does the work F . de on the journal and the same int p dh dA on the pad.

A flexible pivot
----------------
With ``pivot_stiffness_N_m`` = k_p the pad also translates along its pivot line, by u (outward, away
from the journal, positive) against the pivot's spring. Every point of the pad's surface moves by
u n_p, n_p = u(theta_p) the outward unit vector at the pivot; the radial part of that motion at theta,
which opens the film, is u u(theta) . u(theta_p) = u cos(theta - theta_p), so

    h = C_pad - d cos(theta - theta_p) + y sin(theta) - z cos(theta) - delta (R + C_pad) sin(theta - theta_p)
        + u cos(theta - theta_p),

and u cos(theta - theta_p) = -(-u n_p) . u(theta): the pad's film with the journal at e - u n_p, velocity
v - (du/dt) n_p. In the pad frame n_p' = u(pi) = (0, -1), so the equivalent journal is
(y' + (R + C_pad) delta, z' + u) and its velocity (vy' + (R + C_pad) ddelta/dt, vz' + du/dt): again the
partial-arc solver unchanged. Virtual work gives the pad's radial generalised force: a du moves the
equivalent journal by -n_p du, so the film's load on the pad along its outward normal is
P = -F . n_p = F'z (F the pad's force on the journal; F'z > 0 for a loaded pad, whose film pushes the
journal up, away from the pivot at the bottom), and the pivot's spring adds -k_p u:

    Q = P - k_p u = F'z - k_p u.

The pad's mass is not modelled (its inertia about the pivot is ``pad_inertia_kg_m2``; radially it is
massless), so Q = 0 at every instant: statically P = k_p u, and in motion the film's squeeze through
du/dt balances the spring. Coordinates per pad (delta, u): the tilt's moment M and the radial force Q
couple through the pad's own film (dM/du = (R + C_pad) dF'y/dz', dQ/d delta = (R + C_pad) dF'z/dy'), not
through another pad. Along the pivot line the film and the pivot act in series: with the pad's film
stiffness k_f = s . K_film s (s = -n_p, the tilt condensed) the pad's stiffness there is
k_f k_p / (k_f + k_p), 1/k = 1/k_f + 1/k_p, at the same film state.

The pad frame
-------------
Rotating the bearing's frame by alpha = pi - theta_p about x takes the pivot to the bottom
(theta = 180 deg): the journal state e' = Rot(alpha) e (Rot(a) (y, z) = (y cos a - z sin a,
y sin a + z cos a): u(theta + a) = Rot(a) u(theta)), the pad's film in the frame is the same
function of theta' = theta + alpha, and its force comes back as F = Rot(-alpha) F'. In the frame
t_p' = (1, 0), the equivalent journal is (y' + (R + C_pad) delta, z'), and M = (R + C_pad) F'y.
Every pad of one arc, offset and preload is thus one partial-arc bore (built by
``internals.tilting_pad.assembly.pad_frame_geometry``: this module does not import the fixed
bores' ``physics.bore.geometry``, which reads these keys) solved at N states: one solver (and later one
per-pad force map) serves all pads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...io.schema import Key, List, Number

TWO_PI = 2.0 * math.pi
MIN_PADS, MAX_PADS = 3, 12
PAD_FRAME_PIVOT = math.pi  # the pivot's theta in a pad's own frame: the bottom
_GAP_TOL = 1e-9  # [rad]: pads may touch (zero gap), not overlap

# the [geometry] keys of a tilting-pad bore (``preload`` is the lobes' key, shared: physics.bore.geometry)
PAD_KEYS = (
    Key("pads", "tilting-pad bearing: number of pads (absent: a fixed bore)", None, f"{MIN_PADS} .. {MAX_PADS}",
        kind=Number(MIN_PADS, MAX_PADS, integer=True)),
    Key("pad_arc_deg", "tilting pads: every pad's arc [deg] (with pads)", None,
        "> 0; the pads may not overlap", kind=Number(0.0, 360.0 / MIN_PADS, exclusive_minimum=True)),
    Key("pivots_deg", "tilting pads: the pivots' angles, in grooves_deg's theta (4 pads, load down between pads: "
        "[45, 135, 225, 315]; on pad: [0, 90, 180, 270]) [deg] (with pads)", None, "one angle per pad",
        kind=List(Number())),
    Key("pivot_offset", "tilting pads: the pivot's place on its pad as a fraction of the arc from the leading "
        "edge (0.5 centred)", 0.5, "> 0 and < 1", kind=Number(0.0, 1.0, exclusive_minimum=True,
                                                               exclusive_maximum=True)),
    Key("pad_inertia_kg_m2", "tilting pads: each pad's moment of inertia about its pivot [kg m^2] (0: massless "
        "pads, in moment equilibrium at every instant)", 0.0, ">= 0", kind=Number(0.0)),
    Key("pivot_stiffness_N_m", "tilting pads: the pivot's radial stiffness [N/m] (absent: rigid; each pad then "
        "also moves along its pivot line, massless, its film's load = k_p u; not in the bearing FMUs)", None, "> 0",
        kind=Number(0.0, exclusive_minimum=True)),
)
PAD_KEY_NAMES = tuple(k.name for k in PAD_KEYS)


def _wrap(a: float) -> float:
    a = math.fmod(a, TWO_PI)
    return a + TWO_PI if a < 0.0 else (0.0 if a >= TWO_PI else a)


def rotation(alpha: float) -> np.ndarray:
    """Rot(alpha): the rotation by alpha [rad] about +x in the (y, z) plane (from +y toward +z)."""
    c, s = math.cos(alpha), math.sin(alpha)
    return np.array([[c, -s], [s, c]])


@dataclass(frozen=True)
class PadGeometry:
    """A tilting-pad bore in SI (see the module docstring).

    pivots        : the N pivot angles theta_p [rad], in [0, 2 pi), in the file's order
    arc           : every pad's arc beta [rad]
    offset        : the pivot's place from the leading edge, a fraction of the arc, in (0, 1)
    preload       : m = 1 - C_bearing / C_pad, in [0, 1)
    inertia       : each pad's moment of inertia about its pivot [kg m^2] (0: massless)
    pivot_stiffness : radial pivot stiffness k_p [N/m], None = rigid (*A flexible pivot*)
    """

    pivots: tuple[float, ...]
    arc: float
    offset: float = 0.5
    preload: float = 0.0
    inertia: float = 0.0
    pivot_stiffness: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "pivots", tuple(_wrap(float(p)) for p in self.pivots))
        problem = self.check()
        if problem is not None:
            raise ValueError(problem)

    @property
    def n(self) -> int:
        return len(self.pivots)

    def check(self) -> str | None:
        """What does not fit, naming the keys, or None."""
        n = self.n
        if not MIN_PADS <= n <= MAX_PADS:
            return f"pads = {n} must be in {MIN_PADS} .. {MAX_PADS}"
        if not (math.isfinite(self.arc) and math.radians(5.0) <= self.arc < TWO_PI / MIN_PADS):
            return f"pad_arc_deg = {math.degrees(self.arc):.6g} must be >= 5 and < 120"
        if not (math.isfinite(self.offset) and 0.0 < self.offset < 1.0):
            return f"pivot_offset = {self.offset!r} must be > 0 and < 1 (0.5: the pivot in the pad's middle)"
        if not (math.isfinite(self.preload) and 0.0 <= self.preload < 1.0):
            return f"preload = {self.preload!r} must be >= 0 and < 1"
        if not (math.isfinite(self.inertia) and self.inertia >= 0.0):
            return f"pad_inertia_kg_m2 = {self.inertia!r} must be >= 0"
        if self.pivot_stiffness is not None and not (math.isfinite(self.pivot_stiffness) and self.pivot_stiffness > 0):
            return f"pivot_stiffness_N_m = {self.pivot_stiffness!r} must be > 0"
        lead = sorted((_wrap(p - self.offset * self.arc), p) for p in self.pivots)
        for (a, pa), (b, pb) in zip(lead, lead[1:] + [(lead[0][0] + TWO_PI, lead[0][1])]):
            if b - a < self.arc - _GAP_TOL:
                return (f"pivots_deg: the pads pivoted at {math.degrees(pa):.6g} and {math.degrees(pb):.6g} deg "
                        f"overlap (pad_arc_deg = {math.degrees(self.arc):.6g}, pivot_offset = {self.offset:g}: "
                        f"their leading edges are {math.degrees(b - a):.6g} deg apart)")
        return None

    def pad_clearance(self, CR: float) -> float:
        """C_pad = CR / (1 - m) [m]."""
        return CR / (1.0 - self.preload)

    def span(self, k: int) -> tuple[float, float]:
        """(leading, trailing) edge of pad k [rad], trailing = leading + arc."""
        lead = self.pivots[k] - self.offset * self.arc
        return lead, lead + self.arc

    def frame_angle(self, k: int) -> float:
        """alpha_k = pi - theta_p,k: the rotation from the bearing's frame to pad k's frame."""
        return PAD_FRAME_PIVOT - self.pivots[k]

    def describe(self) -> str:
        return (f"{self.n} tilting pads of {math.degrees(self.arc):.4g} deg pivoted at "
                + ", ".join(f"{math.degrees(p):.4g}" for p in self.pivots)
                + f" deg (offset {self.offset:.4g}, preload {self.preload:.4g}"
                + (f", pad inertia {self.inertia:.4g} kg m^2" if self.inertia > 0 else ", massless pads")
                + (f", pivot stiffness {self.pivot_stiffness:.4g} N/m)" if self.pivot_stiffness else ", rigid pivots)"))

    def as_table(self) -> dict:
        """The [geometry] keys of this bore (degrees)."""
        out = {"pads": self.n, "pad_arc_deg": math.degrees(self.arc),
               "pivots_deg": [math.degrees(p) for p in self.pivots], "pivot_offset": self.offset,
               "preload": self.preload}
        if self.inertia > 0.0:
            out["pad_inertia_kg_m2"] = self.inertia
        if self.pivot_stiffness is not None:
            out["pivot_stiffness_N_m"] = self.pivot_stiffness
        return out


def pads_from_mapping(d: dict, given: set, error) -> PadGeometry | None:
    """The pads of a schema-checked [geometry] table ``d`` (None when it has no ``pads``);
    ``given`` the keys written, ``error(text)`` makes the exception naming the file."""
    pad_only = [k for k in PAD_KEY_NAMES if k != "pads" and k in given]
    if "pads" not in given:
        if pad_only:
            raise error(f"{', '.join(pad_only)} need pads (the number of tilting pads)")
        return None
    fixed = [k for k in ("grooves_deg", "groove_width_deg", "supply_pressure_kPa", "arc_deg", "lobes",
                         "lobe_offset", "lobe_angle_deg") if k in given]
    if fixed:
        raise error(f"pads: a tilting-pad bore has no {', '.join(fixed)} (the pads are its arcs; the oil enters "
                    "between them at ambient pressure)")
    for key in ("pad_arc_deg", "pivots_deg"):
        if key not in given:
            raise error(f"pads = {d['pads']} needs {key}")
    if len(d["pivots_deg"]) != d["pads"]:
        raise error(f"pivots_deg has {len(d['pivots_deg'])} angles for pads = {d['pads']}: one per pad")
    try:
        return PadGeometry(pivots=tuple(math.radians(p) for p in d["pivots_deg"]),
                           arc=math.radians(d["pad_arc_deg"]), offset=d["pivot_offset"], preload=d["preload"],
                           inertia=d["pad_inertia_kg_m2"], pivot_stiffness=d["pivot_stiffness_N_m"])
    except ValueError as exc:
        raise error(str(exc)) from None


__all__ = ["PAD_KEYS", "PAD_KEY_NAMES", "PadGeometry", "pads_from_mapping", "rotation", "MIN_PADS", "MAX_PADS",
           "PAD_FRAME_PIVOT"]
