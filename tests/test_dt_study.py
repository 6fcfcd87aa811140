"""The dt study: its orbit-change measure against a hand computation, and a short real study."""

from pathlib import Path

import numpy as np
import pytest

from rotor_host.analyses.dt_study import dt_study, orbit_change

SCENES = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "scenes"


def _arrays(t, y, z, cr=1e-4):
    # two recorded nodes, the bearing is node 3 (column 1)
    return {"t": t, "nodes": np.array([1, 3]), "bearing_nodes": np.array([3]), "CR": np.array([cr]),
            "y": np.column_stack([np.zeros_like(t), y]), "z": np.column_stack([np.zeros_like(t), z])}


def test_orbit_change_by_hand():
    tc = np.array([0.0, 0.2, 0.4])
    tf = np.array([0.0, 0.1, 0.2, 0.3, 0.4])
    coarse = _arrays(tc, np.zeros(3), np.zeros(3))
    # fine run differs by 3e-6 m in y and 4e-6 m in z at t = 0.2 only: |d| = 5e-6 m = 5 % of CR
    yf = np.array([0.0, 9.0, 3e-6, 9.0, 0.0])  # the off-grid values (t = 0.1, 0.3) must be ignored
    zf = np.array([0.0, 9.0, 4e-6, 9.0, 0.0])
    rms, mx = orbit_change(coarse, _arrays(tf, yf, zf))
    assert mx == pytest.approx(5.0)
    assert rms == pytest.approx(5.0 / np.sqrt(3))


def test_orbit_change_up_to_where_the_fine_run_got():
    tc = np.array([0.0, 0.2, 0.4])
    tf = np.array([0.0, 0.1, 0.2])  # the fine run stopped at 0.2 s
    coarse = _arrays(tc, np.array([0.0, 1e-6, 50e-6]), np.zeros(3))
    rms, mx = orbit_change(coarse, _arrays(tf, np.zeros(3), np.zeros(3)))
    assert mx == pytest.approx(1.0)  # the 50 % at t = 0.4 is beyond the fine run


def test_short_study_converges():
    study = dt_study(SCENES / "paper_22hz.toml", "reynolds", dt=2e-4, t_end=0.02, halvings=2, log=lambda *_: None)
    assert study.rows[0]["change_max"] is None and study.rows[1]["change_max"] is not None
    assert study.converged_dt == pytest.approx(2e-4)
    assert all(r["status"] == "ok" for r in study.rows)


def test_orbit_through_the_wall_is_not_converged():
    # The linear model on the eccentricity-0.95 scene crosses the clearance circle within 0.15 s
    # (docs/stability.md); its orbit hardly depends on dt, and that must not read as converged.
    study = dt_study(SCENES / "harsh_ecc095_10hz.toml", "linear", t_end=0.15, halvings=1, log=lambda *_: None)
    assert all("crossed clearance" in r["status"] for r in study.rows)
    assert study.rows[1]["change_max"] < 1.0
    assert study.converged_dt is None
    assert [r["steps"] for r in study.rows] == [1500, 3000]
