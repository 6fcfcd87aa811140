"""The limit-cycle envelope (rotor_host.analyses.limit_cycle) against hand computations, and its command on a
short real run. The dt study itself is tested in tests/test_dt_study.py."""

import json
from pathlib import Path

import numpy as np
import pytest

from rotor_host.analyses.limit_cycle import (Envelope, command, envelope, envelope_change, limit_cycle,
                                             settled_since)

SCENES = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "scenes"


def test_envelope_by_hand():
    t = np.arange(0, 11) * 0.1  # 0.0 .. 1.0 s; windows of 0.4 s: [0, 0.4), [0.4, 0.8); 0.8.. incomplete
    e = np.zeros((11, 2))
    e[:, 0] = [0.1, 0.2, 0.9, 0.3, 0.5, 0.4, 0.6, 0.45, 9.0, 9.0, 9.0]
    e[:, 1] = [0.1, 0.1, 0.1, 0.1, 0.1, 0.7, 0.1, 0.1, 9.0, 9.0, 9.0]  # the other bearing: max over both
    env = envelope({"t": t, "eccentricity": e}, 0.4)
    np.testing.assert_allclose(env.t, [0.4, 0.8])
    np.testing.assert_allclose(env.e_max, [0.9, 0.7])  # the 9.0 samples lie in the incomplete window
    np.testing.assert_allclose(env.e_min, [0.1, 0.45])  # min of the per-sample max over bearings


def test_settled_since_by_hand():
    env = Envelope(np.arange(1.0, 7.0), np.array([0.5, 0.9, 0.975, 0.965, 0.97, 0.972]), np.zeros(6), 1.0)
    assert settled_since(env, 1.0) == pytest.approx(2.0)  # 0.965..0.975 spans 1 % CR <= 2 %
    assert settled_since(env, 0.4) == pytest.approx(3.0)  # 0.965..0.972 spans 0.7 % <= 0.8 %
    assert settled_since(Envelope(np.empty(0), np.empty(0), np.empty(0), 1.0)) is None


def _arrays_from_envelope(t, ecc):
    return {"t": t, "eccentricity": ecc[:, None]}


def test_drift_inside_the_band_is_not_a_held_limit_cycle():
    t = np.linspace(0, 20, 20001)
    # a ramp 0.960 -> 0.978 stays inside +-1 % CR of 0.969 but is no limit cycle
    ramp, _ = limit_cycle(_arrays_from_envelope(t, 0.960 + 0.018 * t / 20), 10.0, revs=1)
    assert ramp.settled_since_s == pytest.approx(0.0, abs=0.11)
    assert ramp.drift_pct_cr == pytest.approx(1.8, abs=0.05)
    assert not ramp.holds
    # an envelope swinging by +-0.5 % around 0.97 (period 4 s) is held, without trend
    swing, _ = limit_cycle(_arrays_from_envelope(t, 0.97 + 0.005 * np.sin(2 * np.pi * t / 4)), 10.0, revs=1)
    assert swing.settled_since_s == pytest.approx(0.0, abs=0.11)
    assert abs(swing.drift_pct_cr) < 0.2 and swing.holds
    assert swing.band == pytest.approx((0.965, 0.975), abs=2e-4)


def test_envelope_change_by_hand():
    a = Envelope(np.array([1.0, 2.0, 3.0]), np.array([0.9, 0.95, 0.97]), np.zeros(3), 1.0)
    b = Envelope(np.array([1.0, 2.0]), np.array([0.9, 0.953]), np.zeros(2), 1.0)
    assert envelope_change(a, b) == pytest.approx(0.3)  # the third window is beyond b
    with pytest.raises(ValueError):
        envelope_change(a, Envelope(a.t, a.e_max, a.e_min, 2.0))


def test_command_on_a_short_scene(tmp_path):
    # the shipped force map as the bearing (the scene's [map]): the same 1000 steps and windows as
    # the default Reynolds grid at a tenth of the cost (max eccentricity 0.33951 against 0.33951);
    # the library call the command line makes (rotor-host limit-cycle SCENE --t-end 0.1 ...)
    rc = command(source=SCENES / "paper_22hz.toml", t_end=0.1, revs=1, hold=0.01, internal="map", out=tmp_path,
                 quiet=True)
    data = json.loads((tmp_path / "limitcycle_paper_22hz.json").read_text())
    assert data["meta"]["status"] == "ok" and data["meta"]["steps"] == 1000
    assert len(data["t"]) == 2  # 0.1 s at 22 Hz: two complete revolutions
    # the windows hold all but the last 0.2 revolution: their max is the run's, or a little below
    assert 0.21 < max(data["e_max"]) <= max(data["meta"]["max_eccentricity"]) + 1e-12
    assert (tmp_path / "limitcycle_paper_22hz.md").exists() and (tmp_path / "limitcycle_paper_22hz.png").exists()
    assert rc in (0, 1)


def test_a_dying_whirl_is_not_a_limit_cycle():
    # a whirl of size 0.004 (max - min eccentricity) decaying by half over the run stays inside
    # +-1 % CR of one value, the absolute band, but its size falls by ~40 % over the last half:
    # judged relative to its size it dies out
    t = np.linspace(0, 10, 100001)
    size = 0.004 * np.exp(-t * np.log(2) / 10)
    ecc = 0.5 + size * np.sin(2 * np.pi * 10 * t)
    lc, _ = limit_cycle(_arrays_from_envelope(t, ecc), 10.0, revs=2)
    assert lc.settled_since_s == pytest.approx(0.0, abs=0.3)  # the absolute band alone would call it settled
    assert lc.amplitude_trend_pct < -10 and not lc.holds and lc.kind == "dies out"
    assert lc.verdict().startswith("verdict: no limit cycle: the whirl dies out")
    steady, _ = limit_cycle(_arrays_from_envelope(t, 0.5 + 0.004 * np.sin(2 * np.pi * 10 * t)), 10.0, revs=2)
    assert steady.holds and steady.kind == "holds" and abs(steady.amplitude_trend_pct) < 1
    assert steady.verdict().startswith("verdict: the limit cycle holds")
