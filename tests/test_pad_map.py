"""The tilting pads from one partial-arc force map (bearing_fmu/internals/tilting_pad/padmap.py): the
preloaded pad in its frame is the circular arc of clearance C_pad with the journal shifted by the
preload, checked where the map's spline passes through its own Reynolds solves (its nodes), and
the map's pads against the Reynolds pads in a closed loop on the paper rotor (slow)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.map.tables import state_for
from bearing_fmu.internals.tilting_pad.assembly import PadAssembly
from bearing_fmu.internals.tilting_pad.padmap import PadMapSolver, build_pad_map, pad_arc_params
from bearing_fmu.physics.params import BearingParams

BUNDLED = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
PARAMS = BearingParams.from_toml(BUNDLED / "bearing_paper_5pad_lbp.toml")


def test_the_pads_map_is_the_preloaded_pad_frame_at_its_nodes():
    # the spline interpolates its table: at a node (eps, phi, beta) the map's pad is the Reynolds solve
    # of the circular arc there, and that must equal the pad frame's own (lobed, preloaded) Reynolds
    # solver with the journal shifted back by d = C_pad - C_bearing: the module's reduction, to 1e-9
    tab = build_pad_map(PARAMS, n_theta=24, n_x=4, n_eps=10, n_phi=9, n_beta=8)
    pad = PadMapSolver(PARAMS, tab)
    frame = PadAssembly(PARAMS, 24, 4).solvers[0]
    arc = pad_arc_params(PARAMS)
    d = arc.CR - PARAMS.CR
    assert d == pytest.approx(0.3 * arc.CR)
    checked = 0
    for i in (2, 5, 8):
        for j in (1, 4, 7):
            for k in (0, 3, 6):
                y, z, vy, vz = state_for(tab.eps[i], tab.beta[k], arc, tab.phi[j], 2 * math.pi * 44.0)
                try:
                    want = np.array(frame.force(y, z + d, vy, vz, 2 * math.pi * 44.0))
                except ValueError:  # beyond the pad frame's wall (the arc's circle is the map's)
                    continue
                got = np.array(pad.force(y, z + d, vy, vz, 2 * math.pi * 44.0))
                S = PARAMS.mu * PARAMS.R * PARAMS.L * (PARAMS.R / arc.CR) ** 2 * 2 * math.pi * 44.0  # [N]
                scale = max(np.abs(want).max(), 1e-6 * S)
                np.testing.assert_allclose(got, want, rtol=0, atol=1e-7 * scale)
                checked += 1
    assert checked >= 20


@pytest.mark.slow
def test_the_map_pads_follow_the_reynolds_pads_in_a_closed_loop(tmp_path):
    # the paper rotor on five pads at 44 Hz, 10 ms, the pads from a 64^3 map (built here from the same
    # 24 x 4 pad solver, ~55 s on 2 cores) against the Reynolds pads: the orbits within 0.01 % CR (the
    # other maps' bar). Measured: 0.095 % CR RMS at 32^3, 0.015 % at 48^3, 0.0015 % at 64^3
    from bearing_fmu.internals.map.groovemap import save_grooved_map
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    path = save_grooved_map(build_pad_map(PARAMS, n_theta=24, n_x=4, n_eps=64, n_phi=64, n_beta=64, workers=2),
                            tmp_path / "pads.json")
    scene = load_scene(BUNDLED / "scenes" / "paper_5pad_lbp_44hz.toml")
    orbits = []
    for opts in ({"reynolds": {"n_theta": 24, "n_x": 4}},
                 {"reynolds": {"n_theta": 24, "n_x": 4}, "tilting_pad": {"pad_map": str(path)}}):
        res = run_scene(scene.with_internal("tilting_pad", options=opts, t_end_s=0.01), out_dir=tmp_path)
        assert res.ok, res.meta
        orbits.append((np.asarray(res.arrays["y"]), np.asarray(res.arrays["z"])))
    (y0, z0), (y1, z1) = orbits
    rms = math.sqrt(np.mean((y1 - y0) ** 2 + (z1 - z0) ** 2)) / 90e-6
    assert rms < 1e-4, rms
