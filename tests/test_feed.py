"""The plain bore fed along its line of thickest film (``[geometry] feed = "thickest"``,
``physics.bore.feed``): Raimondi & Boyd's full bearing as their table has it, the placement itself, the
refusals, and the commands that place it (demo's record, a scene's bearings, stability per speed)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from bearing_fmu.internals import registry
from bearing_fmu.physics.bore.feed import place_feed, thickest_line
from bearing_fmu.physics.bore.geometry import FEED_WIDTH_DEG, Geometry
from bearing_fmu.physics.operating import operating_point
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds
from bearing_fmu.physics.statics import equilibrium

from test_film import H0C, RB_FLOW_LD1, RB_RCF, RB_S  # Raimondi & Boyd's table, with its sources

N_HZ = 15.0


def rb(l_over_d: float) -> BearingParams:
    return BearingParams(D=0.1, L=0.1 * l_over_d, CR=1e-4, mu=0.01, geometry=Geometry(feed="thickest"))


@pytest.mark.parametrize("l_over_d", [1.0, 0.5, 0.25])
def test_raimondi_boyd_full_bearing(l_over_d):
    """Loaded at each row's Sommerfeld number S, the bearing fed at its thickest film reaches the row's
    h0/c within 2 % (within 0.6 % for h0/c >= 0.1; the 2 % at h0/c = 0.03, where S changes fastest with
    h0/c) and (r/c) f within 1 %; at L/D = 1 the flow variable Q / (r c N l) within 1 % (3.966, 4.302,
    4.576 against 3.99, 4.33, 4.62). The side flow never exceeds the inflow (the plain full bore's
    reformed film gave Qs / Q = 1.013 at h0/c 0.03), and its share grows as the film thins (a thinner
    film carries less oil round, more leaves at the ends)."""
    prm = rb(l_over_d)
    share = []
    for h0c, s_ref, f_ref in zip(H0C, RB_S[l_over_d], RB_RCF[l_over_d]):
        W = (prm.R / prm.CR) ** 2 * prm.mu * N_HZ * prm.L * prm.D / s_ref
        rec = operating_point(prm, (0.0, -W), N_HZ)
        h = 1.0 - rec["eccentricity"]
        assert abs(h / h0c - 1) < (0.006 if h0c >= 0.1 else 0.02), (h0c, h)
        rcf = rec["friction_coefficient"] * prm.R / prm.CR
        assert abs(rcf / f_ref - 1) < 0.01, (h0c, rcf, f_ref)
        if l_over_d == 1.0 and h0c in RB_FLOW_LD1:
            assert abs(rec["flow_variable"] / RB_FLOW_LD1[h0c] - 1) < 0.01, (h0c, rec["flow_variable"])
        share.append(rec["side_flow_m3_s"] / rec["inflow_m3_s"])
        # the line opposite the minimum film (sampled every 0.1 deg)
        assert abs((rec["feed_deg"] - rec["min_film_deg"]) % 360.0 - 180.0) < 0.1
    assert all(0.0 < a < b < 1.0 for a, b in zip(share, share[1:])), share


def test_the_line_is_at_its_own_thickest_film():
    """The fixed point: the placed line lies (within the 0.01 deg tolerance) at the thickest film of the
    equilibrium it gives; placing a placed bore changes nothing; no load puts it at the top."""
    prm, load, om = rb(1.0), (300.0, -2000.0), 2 * math.pi * N_HZ
    placed = place_feed(prm, load, om)
    assert len(placed.geometry.grooves) == 1 and placed.geometry.feed == "thickest"
    assert math.degrees(placed.geometry.groove_width) == pytest.approx(FEED_WIDTH_DEG)
    y, z = equilibrium(Reynolds(placed), load, om)
    turn = (thickest_line(y, z) - placed.geometry.grooves[0] + math.pi) % (2 * math.pi) - math.pi
    assert abs(math.degrees(turn)) < 0.02
    assert place_feed(placed, load, om) is placed
    assert place_feed(prm, (0.0, 0.0), om).geometry.grooves == (0.0,)
    plain = BearingParams(D=0.1, L=0.1, CR=1e-4, mu=0.01)
    assert place_feed(plain, load, om) is plain


def test_refusals_name_the_key():
    """feed = 'thickest' belongs to the plain full bore; unplaced, no solver takes it (an internal
    neither: the callers that know the load and speed place it) and the refusal says how."""
    for kw in ({"lobes": 2, "preload": 0.3}, {"arc": (0.0, math.pi)}, {"grooves": (0.0, math.pi)}):
        with pytest.raises(ValueError, match="feed = 'thickest'"):
            Geometry(feed="thickest", **kw)
    with pytest.raises(ValueError, match="feed = 'thickest' puts the feed line"):
        Reynolds(rb(1.0))
    with pytest.raises(ValueError, match="needs the static load and the speed"):
        registry.create("reynolds", rb(1.0), {}, registry.Context(load=(0.0, -100.0), omega=100.0))
    placed = place_feed(rb(1.0), (0.0, -100.0), 100.0)
    assert registry.create("reynolds", placed, {}).params.geometry.grooves == placed.geometry.grooves


def test_bearing_file_and_record(tmp_path: Path):
    """A bearing file's feed key: read, placed by demo's record (its angle and the placed bore named),
    refused with grooves; a placed bore's table (what a surrogate records) reads back as placed."""
    text = "[bearing]\nD_mm = 100.0\nL_mm = 100.0\nCR_um = 100.0\nmu_Pa_s = 0.01\n[geometry]\nfeed = \"thickest\"\n"
    (tmp_path / "b.toml").write_text(text)
    prm = BearingParams.from_toml(tmp_path / "b.toml")
    assert prm.geometry.feed_unplaced
    rec = operating_point(prm, (0.0, -2000.0), N_HZ)
    assert rec["feed_deg"] == pytest.approx(rec["attitude_deg"], abs=0.05)  # weight down: the line at phi
    assert "thickest film at" in rec["bore"]
    (tmp_path / "c.toml").write_text(text + "grooves_deg = [0.0, 180.0]\n")
    with pytest.raises(ValueError, match="feed = 'thickest' places one feed line itself"):
        BearingParams.from_toml(tmp_path / "c.toml")
    placed = place_feed(prm, (0.0, -2000.0), 2 * math.pi * N_HZ).geometry
    table = placed.as_table()
    (tmp_path / "d.toml").write_text("[bearing]\nD_mm = 100.0\nL_mm = 100.0\nCR_um = 100.0\nmu_Pa_s = 0.01\n"
                                     "[geometry]\nfeed = \"thickest\"\n"
                                     f"grooves_deg = [{table['grooves_deg'][0]!r}]\n")
    back = BearingParams.from_toml(tmp_path / "d.toml").geometry
    assert back.close_to(placed) and not back.feed_unplaced


def test_stability_places_the_line_per_speed(tmp_path: Path):
    """A rotor on two bearings fed at their thickest film: the stability analysis places each line at
    each speed's equilibrium (the attitude, and so the line, turns as the speed rises)."""
    from rotor_host.analyses.linear.stability import Stability
    from rotor_host.bundled import find
    from rotor_host.model.rotor import Rotor

    rotor = Rotor.from_toml(find("rotor_paper.toml"))
    rotor.bearings = [p.with_geometry(Geometry(feed="thickest")) for p in rotor.bearings]
    st = Stability(rotor, "reynolds")
    lines = []
    for hz in (15.0, 40.0):
        st.at(hz)
        lines.append(math.degrees(st.internals[0].params.geometry.grooves[0]))
    assert lines[1] > lines[0] + 1.0, lines  # lighter relative load at speed: a larger attitude angle
