"""The circumferential cells of the Reynolds solver for a bore (``Geometry.theta_grid`` makes them):
the cells' edges, widths, prescribed pressures and the derived film and distance arrays."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True, eq=False)
class ThetaGrid:
    """Circumferential cells of the Reynolds solver for a bore (``Geometry.theta_grid``): cell i
    spans [left[i], left[i] + width[i]] [rad]; ``fixed`` cells have the prescribed pressure
    ``supply`` [Pa] (a groove's, 0 outside an arc). Derived arrays, per cell i and its right
    face i + 1/2 (the left face of cell i + 1, cyclically):

    centre      : cell centres [rad]
    right       : right faces [rad]
    face_film   : h / CR of the centred journal at the right face, on the side of a film cell
    centre_film : h / CR of the centred journal at the centre
    dist        : the distance [rad] across the right face over which the pressure difference acts:
                  centre to centre between film cells, centre to the face when the other side is
                  fixed (its pressure holds on the face itself), 0 between two fixed cells
    dfilm       : face_film(right) - face_film(left) of a film cell, both on its own lobe (the
                  Couette source of the lobes); 0 for fixed cells
    """

    geometry: object  # the physics.bore.geometry.Geometry that made the grid (not imported: it imports this module)
    left: np.ndarray
    width: np.ndarray
    fixed: np.ndarray
    supply: np.ndarray

    def __post_init__(self) -> None:
        g = self.geometry
        n = self.left.shape[0]
        nxt = np.roll(np.arange(n), -1)
        centre = self.left + 0.5 * self.width
        right = self.left + self.width
        lobe = g.lobe_of(centre)
        film = ~self.fixed
        # the face's film on the side of a film cell (the film may step at a fixed cell's face)
        side = np.where(film, lobe, lobe[nxt])
        face_film = g.base_film(right, side)
        own_left = g.base_film(self.left, lobe)
        dfilm = np.where(film, g.base_film(right, lobe) - own_left, 0.0)
        gap = np.mod(centre[nxt] - centre, TWO_PI)
        dist = np.where(film & film[nxt], gap,
                        np.where(film, 0.5 * self.width, np.where(film[nxt], 0.5 * self.width[nxt], 0.0)))
        for name, value in (("centre", centre), ("right", right), ("face_film", face_film),
                            ("centre_film", g.base_film(centre, lobe)), ("dist", dist), ("dfilm", dfilm)):
            object.__setattr__(self, name, value)

    def supply_force(self, R: float, L: float) -> np.ndarray:
        """(Fy, Fz) [N] of the prescribed pressures on the journal: p (sin, -cos) integrated over
        their cells, the whole length L [m], radius R [m]."""
        a, b = self.left, self.left + self.width
        fy = np.sum(self.supply * (np.cos(a) - np.cos(b)))
        fz = -np.sum(self.supply * (np.sin(b) - np.sin(a)))
        return np.array([fy, fz]) * R * L
