"""The plain full bore fed along its line of thickest film (``[geometry] feed = "thickest"``).

Raimondi & Boyd's full (360 deg) bearing takes its oil in at ambient pressure along the line of
thickest film, wherever the load puts it; the Swift-Stieber full bore (``feed = "film"``) lets the
film take oil in wherever it reforms, upstream of that line, which gives 3.5-8 % more inflow and
11 % more side flow against their table (docs/thermal.md). The line of thickest film lies opposite
the journal's displacement, which depends on the feed: ``place_feed`` iterates the equilibrium
under the static load with an ambient feed line FEED_WIDTH_DEG wide at the thickest film of the
previous iterate until the line moves less than ``tol_deg`` (2-4 equilibria: the attitude moves
little with the feed).

In a transient the line stays where the static equilibrium put it, as a feed hole stays in the
housing: the journal's orbit moves the film around a fixed supply (a feed that followed the
orbit would be no machine's). So a placed bore is an ordinary one-groove bore to every solver,
map and FMU; only its place comes from the static load.
"""

from __future__ import annotations

import math

from .geometry import FEED_WIDTH_DEG, Geometry
from ..params import BearingParams
from ..solver.reynolds import Reynolds
from ..statics import equilibrium

__all__ = ["place_feed", "place_feeds", "thickest_line"]


def thickest_line(y: float, z: float) -> float:
    """theta [rad, 0 .. 2 pi) of the thickest film of the full bore with the journal at (y, z) [m]:
    h = CR + y sin(theta) - z cos(theta) is largest along the displacement's opposite, (sin, -cos)
    = (y, z) / e."""
    return math.atan2(y, -z) % (2.0 * math.pi)


def place_feed(params: BearingParams, load, omega: float, *, tol_deg: float = 0.01, max_iter: int = 30,
               name: str = "the bearing") -> BearingParams:
    """``params`` with its feed line placed at the thickest film of its static equilibrium under
    ``load`` = (Wy, Wz) [N] at ``omega`` [rad/s]; ``params`` itself for any other bore, a placed one included. Without a load
    (W = 0) the journal sits centred and the line is placed at the top (theta = 0). ValueError
    when the line does not settle in ``max_iter`` placements (not observed)."""
    geo = params.geometry
    if not geo.feed_unplaced:
        return params
    if load is None or omega is None:
        geo.require_placed(name)
    width = math.radians(FEED_WIDTH_DEG)

    def placed(theta: float) -> BearingParams:
        return params.with_geometry(Geometry(grooves=(theta,), groove_width=width, feed="thickest"))

    if math.hypot(*load) == 0.0:
        return placed(0.0)
    # the first line from the Swift-Stieber bore's equilibrium, then each from the last placement's
    y, z = equilibrium(Reynolds(params.with_geometry(Geometry())), load, omega, name=name)
    theta = thickest_line(y, z)
    for _ in range(max_iter):
        trial = placed(theta)
        y, z = equilibrium(Reynolds(trial), load, omega, start=(y, z), name=name)
        new = thickest_line(y, z)
        turn = (new - theta + math.pi) % (2.0 * math.pi) - math.pi
        if abs(math.degrees(turn)) < tol_deg:
            return trial if turn == 0.0 else placed(new)
        theta = new
    raise ValueError(f"{name}: feed = 'thickest': the feed line did not settle in {max_iter} placements "
                     f"(last at {math.degrees(theta):.4g} deg)")


def place_feeds(bearings, loads, omega: float, where: str = "") -> list[BearingParams]:
    """``place_feed`` of every bearing of a rotor (BearingParams, with its static load (Wy, Wz) [N]);
    ``where`` prefixes the names in messages (a scene file)."""
    return [place_feed(p, (float(w[0]), float(w[1])), omega, name=f"{where}bearing {k + 1}")
            for k, (p, w) in enumerate(zip(bearings, loads))]
