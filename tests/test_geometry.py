"""The bore of a bearing (bearing_fmu.physics.bore.geometry): the [geometry] table of a bearing file,
what is refused by name, the film of a lobed bore against the exact geometry of its circles,
and the solver's circumferential grid (faces on every edge)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearing_fmu.physics.bore.geometry import FULL_BORE, Geometry
from bearing_fmu.physics.params import PAPER_BEARING, BearingFileError, BearingParams

HEAD = "[bearing]\nD_mm = 31.0\nL_mm = 20.0\nCR_um = 90.0\nmu_Pa_s = 0.05\n"


def _read(tmp_path, text):
    f = tmp_path / "b.toml"
    f.write_text(text)
    return BearingParams.from_toml(f)


def test_absent_geometry_is_the_full_bore_as_before(tmp_path):
    p = _read(tmp_path, HEAD)
    assert p == PAPER_BEARING and p.geometry is FULL_BORE and p.geometry.is_full_bore
    assert repr(p) == "BearingParams(D=0.031, L=0.02, CR=9e-05, mu=0.05)"
    assert p.as_dict() == {"D": 0.031, "L": 0.02, "CR": 9e-05, "mu": 0.05}
    assert _read(tmp_path, HEAD + "[geometry]\n").geometry == FULL_BORE  # an empty table: the defaults


def test_geometry_table_in_si(tmp_path):
    p = _read(tmp_path, HEAD + "[geometry]\ngrooves_deg = [270.0, 90.0]\ngroove_width_deg = 30\n"
                              "supply_pressure_kPa = 150\n")
    g = p.geometry
    assert g.grooves == (math.radians(90.0), math.radians(270.0))  # sorted, radians
    assert g.groove_width == math.radians(30.0) and g.supply_pressure == 150e3
    assert not g.is_full_bore and "2 axial grooves at 90, 270 deg" in g.describe()
    assert "geometry=Geometry(" in repr(p)
    # top-level keys with a [geometry] table; negative angles taken modulo 360
    q = _read(tmp_path, "D_mm = 31.0\nL_mm = 20.0\nCR_um = 90.0\nmu_Pa_s = 0.05\n[geometry]\nlobes = 2\n"
                        "preload = 0.5\nlobe_angle_deg = -90\narc_deg = [-60, 240]\n")
    assert q.geometry.lobes == 2 and q.geometry.preload == 0.5 and q.geometry.arc == (math.radians(-60), math.radians(240))


@pytest.mark.parametrize("table, words", [
    ("grooves_deg = [90, 105]", "grooves_deg: the grooves at 90 deg and 105 deg overlap"),
    ("grooves_deg = [0, 350]\ngroove_width_deg = 10", "grooves_deg: the grooves at 350 deg and 0 deg overlap"),
    ("grooves_deg = [90]\narc_deg = [100, 260]", "the groove at 90 deg (80 deg .. 100 deg) is not inside arc_deg"),
    ("grooves_deg = [300]\narc_deg = [100, 260]", "the groove at 300 deg"),
    ("preload = 0.4", "preload = 0.4 needs lobes >= 2"),
    ("lobes = 2\npreload = 0.5\nlobe_offset = 1.0", "lobe_offset = 1 makes the film step at the lobe boundary at 90 deg"),
    ("supply_pressure_kPa = 100", "supply_pressure_kPa > 0 needs grooves_deg"),
    ("groove_width_deg = 10", "groove_width_deg needs grooves_deg"),
    ("lobe_offset = 0.7", "lobe_offset needs lobes >= 2"),
    ("lobe_angle_deg = 10", "lobe_angle_deg needs lobes >= 2"),
    ("arc_deg = [0, 360]", "arc_deg = [0, 360]: end - start must be in (0, 360)"),
    ("arc_deg = [10, 12]", "arc_deg spans 2 deg: at least 5 deg of film"),
    ("lobes = 9", "lobes = 9 must be an integer >= 1 and <= 8"),
    ("supply_pressure_kPa = -1", "supply_pressure_kPa = -1 must be a finite number >= 0 and <= 10000"),
    ("groove_width_deg = 180\ngrooves_deg = [90]", "groove_width_deg = 180 must be a finite number > 0 and < 180"),
])
def test_what_does_not_fit_together_is_refused_by_name(tmp_path, table, words):
    with pytest.raises(BearingFileError) as exc:
        _read(tmp_path, HEAD + "[geometry]\n" + table + "\n")
    msg = str(exc.value)
    assert msg.startswith(f"{tmp_path / 'b.toml'}: [geometry] ") and words in msg, msg


def test_what_fits_together_is_taken():
    Geometry(grooves=(math.pi / 2, 1.5 * math.pi), lobes=2, preload=0.5, lobe_offset=1.0)  # offset halves
    Geometry(arc=(math.radians(90), math.radians(270)), grooves=(math.radians(100),))  # groove on the arc's edge
    Geometry(arc=(math.radians(200), math.radians(340)), lobes=2, preload=0.3, lobe_offset=0.8,
             lobe_angle=math.pi / 2)  # its steps (at 0 and 180 deg) lie outside the arc
    with pytest.raises(TypeError, match="geometry must be a Geometry"):
        BearingParams(0.031, 0.02, 9e-5, 0.05, geometry={"lobes": 2})


@pytest.mark.parametrize("lobes, m, offset, angle", [(2, 0.5, 0.5, 0.0), (3, 0.3, 0.5, 0.4), (2, 0.4, 1.0, 0.0),
                                                     (4, 0.6, 0.7, 1.0)])
def test_lobed_film_is_the_gap_between_the_circles(lobes, m, offset, angle):
    """h / CR = (1 - m cos(theta - theta_p)) / (1 - m) + (y sin - z cos) / CR (module docstring)
    against the exact gap along the ray from the bearing centre between the journal circle
    (radius R, centre e) and the lobe's circle (radius R + C_pad, centre moved by m C_pad away from
    its preload point): equal to O(C / R), here 1e-3."""
    R, CR = 0.05, 5e-5
    g = Geometry(lobes=lobes, preload=m, lobe_offset=offset, lobe_angle=angle,
                 grooves=tuple(g for g in g_boundaries(lobes, angle)) if offset != 0.5 else ())
    Cp = g.pad_clearance(CR)
    rng = np.random.default_rng(1)
    for _ in range(20):
        e = rng.uniform(-0.7, 0.7, 2) * CR
        th = rng.uniform(0, 2 * math.pi)
        if g.is_prescribed(th):
            continue
        u = np.array([-math.sin(th), math.cos(th)])  # (y, z) toward the bore at theta
        k = int(g.lobe_of(th))
        Ok = -(Cp - CR) * np.array([-math.sin(g.preload_points()[k]), math.cos(g.preload_points()[k])])
        s = u @ Ok + math.sqrt((u @ Ok) ** 2 - Ok @ Ok + (R + Cp) ** 2)  # the lobe along the ray
        t = u @ e + math.sqrt((u @ e) ** 2 - e @ e + R ** 2)  # the journal surface along the ray
        h = CR * g.base_film(th) + e[0] * math.sin(th) - e[1] * math.cos(th)
        assert abs(h - (s - t)) < 1e-3 * CR, (th, h, s - t)
    # the smallest clearance of a centred journal is CR, at the preload points
    th = np.linspace(0, 2 * math.pi, 7201)
    film = g.base_film(th)[[not g.is_prescribed(t) for t in th]]
    assert film.min() >= 1.0 - 1e-9
    assert np.allclose(g.base_film(g.preload_points(), np.arange(lobes)), 1.0)
    # (an offset lobe's preload point lies in the groove at its trailing edge: the film is thicker)
    assert g.min_film(0.0, 0.0, CR) >= CR * (1 - 1e-12)
    if offset == 0.5:
        assert g.min_film(0.0, 0.0, CR) == pytest.approx(CR, rel=1e-6)


def g_boundaries(lobes, angle):
    """Groove centres on the lobe boundaries (where an offset lobe's film steps)."""
    return [angle + (k + 0.5) * 2 * math.pi / lobes for k in range(lobes)]


def test_offset_half_lobe_is_continuous_at_its_boundaries():
    g = Geometry(lobes=3, preload=0.4, lobe_angle=0.3)
    for t in g.lobe_boundaries():
        a, b = g.base_film(t - 1e-9), g.base_film(t + 1e-9)
        assert abs(a - b) < 1e-7


@pytest.mark.parametrize("geo", [
    Geometry(grooves=(math.pi / 2, 1.5 * math.pi)),
    Geometry(grooves=(math.radians(37.0),), groove_width=math.radians(13.0), supply_pressure=2e5),
    Geometry(arc=(math.radians(120), math.radians(240))),
    Geometry(grooves=(math.pi / 2, 1.5 * math.pi), lobes=2, preload=0.5, lobe_offset=1.0),
    Geometry(lobes=3, preload=0.2, lobe_angle=0.1),
])
@pytest.mark.parametrize("n", [32, 128])
def test_grid_has_a_face_on_every_edge(geo, n):
    grid = geo.theta_grid(n)
    assert grid.left.shape == (n,) and np.isclose(grid.width.sum(), 2 * math.pi) and np.all(grid.width > 0)
    faces = np.mod(grid.left, 2 * math.pi)
    for e in geo.edges():
        assert np.min(np.abs(np.angle(np.exp(1j * (faces - e))))) < 1e-12
    # prescribed cells: the grooves at the supply pressure, ambient outside the arc; one cell per stretch
    for i in np.flatnonzero(grid.fixed):
        mid = grid.centre[i]
        in_groove = any(abs(math.remainder(mid - c, 2 * math.pi)) < 0.5 * geo.groove_width for c in geo.grooves)
        assert grid.supply[i] == (geo.supply_pressure if in_groove else 0.0)
    assert np.all(grid.supply[~grid.fixed] == 0.0)
    # film cells next to a prescribed cell take the face as the Dirichlet boundary: half their width
    nxt = np.roll(np.arange(n), -1)
    edge = ~grid.fixed & grid.fixed[nxt]
    assert np.allclose(grid.dist[edge], 0.5 * grid.width[edge])
    assert np.all(grid.dist[grid.fixed & grid.fixed[nxt]] == 0.0)


def test_grid_needs_two_cells_per_film_segment():
    g = Geometry(grooves=tuple(math.radians(a) for a in (0, 60, 120, 180, 240, 300)), groove_width=math.radians(10))
    with pytest.raises(ValueError, match=r"n_theta = 16 is too few cells .* at least 18"):
        g.theta_grid(16)
    assert g.theta_grid(18).fixed.sum() == 6
