"""The force map in closed loop, end to end: the paper's 22 Hz scene run with the map follows
the same scene run with the Reynolds solver the map was built from, called directly; and the
map through the bearing FMU gives the direct map run.

References: (1) the Reynolds internal itself at the map's truth grid (64 x 8, coarse so the
test is quick; the map's accuracy does not depend on the truth grid, docs/forcemap.md);
(2) the map internal called in-process, which the FMU evaluates with the very same code.
"""

from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.map.tablefile import save_map
from bearing_fmu.internals.map.tables import tabulate
from bearing_fmu.physics.params import PAPER_BEARING
from rotor_host.analyses.report import errors_against
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml"
TRUTH = {"n_theta": 64, "n_x": 8}  # the map's Reynolds grid and the reference's
T_END = 0.1  # s: the unbalance response's first 2.2 shaft revolutions from the static equilibrium
# Measured 2026-11-24 (AMD EPYC) with the default table (96 x 96, k = 0, 4 attitudes) from
# Reynolds 64 x 8: orbit RMS 0.0017 % CR, max 0.0040 % CR, force NRMSE 0.0023 % (the first
# default, 48 x 96 with k = 2: 0.0027 / 0.0061 % CR). The bounds leave 5x margin; a map whose
# force is 1 % too large moves the orbit by 0.19 % CR RMS, one shifted by one table cell in beta
# by 1.4 % CR.
ORBIT_RMS_BOUND_PCT_CR = 0.01
ORBIT_MAX_BOUND_PCT_CR = 0.02
FMU_RTOL = 1e-9  # the FMU runs the same kernel (measured: equal bit for bit); 1e-9 of each array's largest value


def _scene(internal, via, options):
    return load_scene(SCENE).with_internal(internal, via=via, t_end_s=T_END, options=options)


@pytest.mark.slow
def test_map_orbit_follows_reynolds_called_directly(tmp_path):
    # the default table (96 x 96, 4 attitudes) from Reynolds 64 x 8: 36864 coarse solves, ~1.5 s
    table = tabulate(PAPER_BEARING, workers=1, **TRUTH)
    path = save_map(table, tmp_path / "map_64x8.json")
    rey = run_scene(_scene("reynolds", "direct", {"reynolds": TRUTH}), tmp_path, stem="reynolds")
    fmap = run_scene(_scene("map", "direct", {"map": {"map": path}}), tmp_path, stem="map")
    assert rey.ok and fmap.ok, (rey.meta["message"], fmap.meta["message"])
    err = errors_against(rey.arrays, fmap.arrays)
    assert err["orbit_rms_pct_cr"] < ORBIT_RMS_BOUND_PCT_CR, err
    assert err["orbit_max_pct_cr"] < ORBIT_MAX_BOUND_PCT_CR, err
    # the run is not trivially at rest: the bearing journals (recorded nodes 3 and 9) move by
    # 0.37 CR peak to peak in 0.1 s
    bearings = [list(rey.arrays["nodes"]).index(n) for n in rey.arrays["bearing_nodes"]]
    assert np.ptp(rey.arrays["y"][:, bearings], axis=0).min() > 0.1 * PAPER_BEARING.CR


@pytest.mark.slow
def test_map_through_the_fmu_equals_the_direct_map(tmp_path, fmu, map_file):
    # the session FMU bundles map_file (a coarse map: the contract, not the accuracy, is tested)
    opts = {"map": {"map": map_file}}
    direct = run_scene(_scene("map", "direct", opts), tmp_path, stem="direct")
    s = _scene("map", "fmu", opts)
    s.fmu = fmu
    cosim = run_scene(s, tmp_path, stem="fmu")
    assert direct.ok and cosim.ok, (direct.meta["message"], cosim.meta["message"])
    for key in ("y", "z", "vy", "vz", "Fy", "Fz"):
        a, b = direct.arrays[key], cosim.arrays[key]
        np.testing.assert_allclose(b, a, rtol=0, atol=FMU_RTOL * np.abs(a).max(), err_msg=key)
    # the same Newton path: the FMU's stiffness and damping outputs are the map's Jacobian
    assert cosim.meta["force_evaluations"] == direct.meta["force_evaluations"]
