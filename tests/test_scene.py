"""Scenes: reading with clear errors, bearing loads, initial equilibrium, failure handling.

Expected values come from statics of the rigid rotor (the reactions of a shaft on two
supports are statically determinate) and from the equilibrium of each bearing alone
(bearing_fmu.physics.statics.equilibrium), not from the scene code itself.
"""

import math
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.physics.params import PAPER_BEARING
from rotor_host.model.rotor import Rotor
from rotor_host.scenes.run import bearing_loads, run_scene
from rotor_host.scenes.scene import SceneError, load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "rotor_host" / "bundled" / "scenes"
ROTOR = ROOT / "rotor_host" / "bundled" / "rotor_paper.toml"


def write_scene(tmp_path, body: str, name="s.toml") -> Path:
    p = tmp_path / name
    p.write_text(f'rotor = "{ROTOR.as_posix()}"\n' + textwrap.dedent(body))
    return p


@pytest.mark.parametrize("path", sorted(SCENES.glob("*.toml")), ids=lambda p: p.stem)
def test_bundled_scenes_load(path):
    s = load_scene(path)
    assert s.speed_hz > 0 and s.dt_s > 0 and s.t_end_s > 0


def test_paper_scene_values():
    # paper section 3: 8.5 g at 37 mm on the disk (node 6) at 22 Hz
    s = load_scene(SCENES / "paper_22hz.toml")
    assert s.speed_hz == 22.0 and s.unbalances[0].node == 5
    assert s.unbalances[0].mass_kg == 8.5e-3 and s.unbalances[0].radius_m == pytest.approx(0.037)
    # G12.8 (ISO 1940): e * Omega = m r / M_rotor * 2 pi f, in mm/s
    rotor = Rotor.from_toml(ROTOR)
    grade = 8.5e-3 * 37.0 / rotor.mass * 2 * math.pi * 22.0
    assert grade == pytest.approx(12.8, abs=0.1)
    # 1.7 kg at 37 mm: G1170 at 10 Hz and G2338 at 20 Hz (paper section 3)
    assert 1.7 * 37.0 / rotor.mass * 2 * math.pi * 10.0 == pytest.approx(1170, rel=0.01)
    assert 1.7 * 37.0 / rotor.mass * 2 * math.pi * 20.0 == pytest.approx(2338, rel=0.01)


@pytest.mark.parametrize("body, match", [
    ('internal = "reynolds"\nspeed_hz = 22\n', r"missing key\(s\) time"),
    ('internal = "magic"\nspeed_hz = 22\n[time]\nt_end_s = 0.1\ndt_s = 1e-4\n', "internal = 'magic'"),
    ('internal = "reynolds"\nspeed_hz = -1\n[time]\nt_end_s = 0.1\ndt_s = 1e-4\n', "speed_hz = -1"),
    ('internal = "reynolds"\nspeed_hz = 22\n[time]\nt_end_s = 0.1\ndt_s = 1e-4\n[[unbalance]]\nnode = 12\n'
     'mass_kg = 0.01\nradius_mm = 37\n', "node = 12 is outside the rotor's nodes 1..11"),
    ('internal = "reynolds"\nspeed_hz = 22\n[time]\nt_end_s = 0.1\ndt_s = 3e-2\n', "whole number of steps"),
    ('internal = "taylor"\nspeed_hz = 22\n[time]\nt_end_s = 0.1\ndt_s = 1e-4\n', "needs the key 'surrogate'"),
    ('internal = "reynolds"\nspeed_hz = 22\nspeed = 3\n[time]\nt_end_s = 0.1\ndt_s = 1e-4\n', "unknown key.*speed"),
    ('internal = "reynolds"\nspeed_hz = 22\n[time]\nt_end_s = 0.1\ndt_s = 1e-4\nnewton_tangent = "exact"\n',
     "newton_tangent = 'exact'; choose one of bearing, frozen, fd, linear"),
])
def test_bad_scene_files(tmp_path, body, match):
    with pytest.raises(SceneError, match=match):
        load_scene(write_scene(tmp_path, body))


def test_bearing_loads_are_the_static_reactions():
    rotor = Rotor.from_toml(ROTOR)
    f = rotor.weight_vector(9.81) + rotor.point_load_vector([(2, 0.0, -500.0), (8, 30.0, -800.0)])
    W = bearing_loads(rotor, f)
    # force balance: the two journals carry the total load
    assert W[:, 1].sum() == pytest.approx(-(rotor.mass * 9.81 + 1300.0), rel=1e-12)
    assert W[:, 0].sum() == pytest.approx(30.0, rel=1e-12)
    # moment balance about bearing 1 (x of node 3): the symmetric weight splits evenly,
    # a point load at a bearing node goes to that bearing alone
    assert W[0, 1] == pytest.approx(-(rotor.mass * 9.81 / 2 + 500.0), rel=1e-9)
    assert W[1, 1] == pytest.approx(-(rotor.mass * 9.81 / 2 + 800.0), rel=1e-9)
    assert W[1, 0] == pytest.approx(30.0, abs=1e-9)


def test_initial_state_puts_each_journal_at_its_own_equilibrium(paper_scene):
    from bearing_fmu.physics.solver.reynolds import Reynolds
    from bearing_fmu.physics.statics import equilibrium

    run = run_scene(load_scene(paper_scene(t_end=2e-4, grid=(48, 8), unbalance_g=None)))
    rey = Reynolds(PAPER_BEARING, n_theta=48, n_x=8)
    W = run.meta["bearing_loads_N"][0]
    y0, z0 = equilibrium(rey, W, 2 * math.pi * 22)
    a = run.arrays
    col = list(a["nodes"]).index(3)
    assert a["y"][0, col] == pytest.approx(y0, rel=1e-6) and a["z"][0, col] == pytest.approx(z0, rel=1e-6)
    # no unbalance: the rotor stays at rest at equilibrium
    assert np.abs(a["y"][:, col] - y0).max() < 1e-6 * PAPER_BEARING.CR


def test_failed_run_keeps_what_it_computed(tmp_path, paper_scene):
    # a huge unbalance drives the Reynolds journal into the wall: the run stops with a
    # diagnosis naming the bearing and the eccentricity, and the partial result is on disk.
    # 3 kg (of the rotor's 3.4 kg: a heavier unbalance is refused as absurd) at 100 mm on the
    # bearing's node, at 66 Hz: m r Omega^2 = 52 kN, more than the 50 kg at 50 mm and 22 Hz this
    # test took before that rule (which reached the wall after 125 steps)
    p = paper_scene(t_end=0.2, dt=2e-4, grid=(32, 4), speed_hz=66.0,
                    unbalance=[{"node": 3, "mass_kg": 3.0, "radius_mm": 100}])
    run = run_scene(load_scene(p), tmp_path / "out")
    assert run.meta["status"] == "failed"
    assert "bearing 1" in run.meta["message"] and "eccentricity ratio" in run.meta["message"]
    saved = np.load(run.npz)
    assert 1 < len(saved["t"]) < 1001 and saved["t"][-1] == pytest.approx(run.meta["t_reached_s"])
    assert np.all(np.isfinite(saved["y"]))


@pytest.mark.slow
def test_taylor_scene_does_not_import_reynolds(paper_scene):
    """Leave out what a scene does not use: a Taylor scene run in-process never imports (or
    compiles) the Reynolds solver."""
    surrogates = sorted((ROOT / "rotor_host" / "bundled" / "surrogates").glob("paper_22hz*.json"))
    assert surrogates, "the shipped 22 Hz surrogate (rotor_host/bundled/surrogates/paper_22hz*.json)"
    p = paper_scene(internal="taylor", surrogate=surrogates[0], t_end=1e-3, unbalance_g=None)
    code = (f"import sys; from rotor_host.scenes.scene import load_scene; from rotor_host.scenes.run import run_scene; "
            f"r = run_scene(load_scene({str(p)!r})); assert r.ok, r.meta['message']; "
            f"print('bearing_fmu.physics.solver.reynolds' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"


def test_taylor_override_without_a_surrogate_names_what_is_missing(tmp_path):
    # `rotor-host run harsh_ecc095_10hz.toml --internal taylor`: the scene names no surrogate
    scene = load_scene(SCENES / "harsh_ecc095_10hz.toml").with_internal("taylor", via="direct", t_end_s=1e-3)
    with pytest.raises(SceneError, match="needs a surrogate file, and the scene names none"):
        run_scene(scene, None)


@pytest.mark.slow
def test_newton_tangents_reach_the_same_orbit_at_their_own_cost():
    """The Newton tangent changes how the step equations are solved, not which: every
    tangent that converges must land on the exact-Newton orbit to the Newton tolerance
    (independent check: the same Newmark equations solved by different iterations). The
    bearings' own tangent needs the fewest evaluations: the film damping times 2/dt dominates
    the step tangent, so a tangent frozen at the equilibrium or the rotor's alone converge
    slowly (benchmarks/bench_tangent.py)."""
    base = load_scene(SCENES / "paper_22hz.toml").with_internal("taylor", via="direct", t_end_s=0.01)
    runs = {t: run_scene(base.with_internal("taylor", newton_tangent=t)) for t in ("bearing", "frozen", "linear")}
    ref = runs["bearing"]
    assert ref.ok and ref.meta["newton_tangent"] == "bearing"
    # the increment test stops a slowly contracting chord iteration early: its error is about
    # the last correction / (1 - contraction), so the linear tangent (contraction ~0.97) lands
    # 5e-5 CR off where the frozen one (~0.1) lands 2e-10 CR off
    atol = {"bearing": 0.0, "frozen": 1e-8, "linear": 1e-3}
    for t, run in runs.items():
        assert run.ok, (t, run.meta["message"])
        for c in ("y", "z"):
            np.testing.assert_allclose(run.arrays[c], ref.arrays[c], rtol=0, atol=atol[t] * PAPER_BEARING.CR)
    evals = {t: r.meta["newton_mean_evaluations_per_step"] for t, r in runs.items()}
    assert evals["bearing"] < 2.5 < evals["frozen"] < evals["linear"]


@pytest.mark.slow
def test_a_direct_run_shows_its_first_domain_warning_and_counts_the_rest():
    # the Taylor scene driven with the rotor's own tangent leaves its fitted domain at many
    # iterates (test_newton_tangents_...: 200 warnings before): one warning on screen, the count
    # and the first in the run's json
    import warnings

    scene = load_scene(SCENES / "paper_22hz.toml").with_internal("taylor", via="direct", t_end_s=0.01,
                                                                 newton_tangent="linear")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = run_scene(scene)
    shown = [w for w in caught if "fitted domain" in str(w.message)]
    report = run.meta["internal_warnings"]
    assert report["count"] > 1 and len(shown) == 1
    assert report["first"] in str(shown[0].message) and "counted in its json" in str(shown[0].message)
