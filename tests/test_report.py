"""Plots and tables of runs on any machine: the disk found from the rotor, the bearing orbit
scaled to what it covers, every variant's failure named."""

import numpy as np

from rotor_host.analyses.compare import print_table
from rotor_host.analyses.report import _reference_limits, disk_node_of, plot_runs


def _run(ecc_max, nodes=(2, 4, 7), bearing_nodes=(2, 7), disk_nodes=(4,), n=200):
    t = np.linspace(0, 0.1, n)
    CR = 1e-4
    y = np.zeros((n, len(nodes)))
    z = np.zeros((n, len(nodes)))
    for i, node in enumerate(nodes):
        amp = ecc_max * CR if node in bearing_nodes else 3e-5 * (1 + i)
        y[:, i] = amp * np.cos(2 * np.pi * 30 * t) + 0.1 * CR
        z[:, i] = amp * np.sin(2 * np.pi * 30 * t) - 0.3 * CR
    nb = len(bearing_nodes)
    return {"t": t, "nodes": np.array(nodes), "bearing_nodes": np.array(bearing_nodes), "CR": np.full(nb, CR),
            "disk_nodes": np.array(disk_nodes), "y": y, "z": z, "Fy": np.ones((n, nb)), "Fz": np.ones((n, nb)),
            "eccentricity": np.hypot(y[:, :nb], z[:, :nb]) / CR}


def test_the_disk_comes_from_the_rotor_not_node_6(tmp_path):
    a = _run(0.05)
    assert disk_node_of(a) == 4
    del a["disk_nodes"]  # an older run: the recorded non-bearing node that moves most
    assert disk_node_of(a) == 4
    assert disk_node_of({**_run(0.05), "disk_nodes": np.array([9])}) == 4  # a disk not recorded: same fallback
    png = plot_runs({"x": _run(0.05)}, tmp_path / "p.png", history=True)
    assert png.stat().st_size > 10_000


def test_a_small_orbit_fills_its_panel_and_one_near_the_wall_shows_the_clearance():
    small = _reference_limits(_run(0.02), 0, 4, False)
    (ylo, yhi), (zlo, zhi) = small[2]
    assert small["clearance"] is False and yhi - ylo < 0.1  # zoomed to the 0.04 CR wide orbit
    assert ylo < 0.1 - 0.02 and yhi > 0.1 + 0.02 and zlo < -0.3 - 0.02 and zhi > -0.3 + 0.02  # holding it
    near = _reference_limits(_run(0.6), 0, 4, False)  # reaches eccentricity ~0.9: the wall matters
    assert "clearance" not in near and near[2][0][1] >= 1.0


def test_compare_table_names_each_failure_and_the_domain_excess():
    rows = [{"label": "Reynolds", "status": "ok", "message": ""},
            {"label": "Taylor 5", "status": "failed", "message": "bearing 1: eccentricity ratio 1.01 >= 1",
             "out_of_domain_pct": 12.5, "domain_excess_pct": 80.0},
            {"label": "linear", "status": "crossed clearance", "message": ""}]
    text = print_table(rows)
    assert "- Taylor 5: failed: bearing 1: eccentricity ratio 1.01 >= 1" in text
    assert "- Taylor 5: 12.5 % of the recorded states outside the surrogate's fitted domain, up to 80 %" in text
    assert "- linear: crossed clearance" in text and "- Reynolds" not in text
