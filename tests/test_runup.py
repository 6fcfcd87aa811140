"""Run-up and coast-down: the speed profile, the unbalance force under acceleration, the
waterfall spectra, and the paper rotor run up through its critical speed into oil whip.

Independent references: the profile's angle against numerical quadrature of its speed; the
unbalance force against minus the mass times the second derivative of its position (finite
differences); the spectrum of synthetic whirls of known radius, frequency and direction; the
paper rotor's first critical speed (22 Hz, the paper) and whirl threshold (~43 Hz, docs/stability.md).
"""

import math

import numpy as np
import pytest

from rotor_host.analyses.waterfall import spectra, summary
from rotor_host.model.speed import SpeedProfile
from rotor_host.scenes.run import external_force
from rotor_host.scenes.scene import SceneError, load_scene

RUNUP = """
    internal = "map"
    via = "direct"
    [speed_profile]
    times_s = [{t0}, {t1}]
    speeds_hz = [{f0}, {f1}]
    [map]
    map = "{map}"
    [time]
    t_end_s = {t_end}
    dt_s = 1e-4
    [[unbalance]]
    node = 6
    mass_kg = 8.5e-3
    radius_mm = 37.0
    [record]
    nodes = [3, 6]
    every = 2
"""


def test_profile_angle_speed_and_acceleration():
    p = SpeedProfile((0.5, 2.0, 3.0), (10.0, 40.0, 25.0))
    assert p.hz(0.0) == 10.0 and p.hz(1.25) == pytest.approx(25.0) and p.hz(9.0) == 25.0
    assert p.alpha(1.0) == pytest.approx(2 * math.pi * 20.0) and p.alpha(2.5) == pytest.approx(-2 * math.pi * 15.0)
    assert p.alpha(0.2) == 0.0 and p.alpha(3.5) == 0.0
    # expected angle: the trapezoid rule on omega(t), exact for a piecewise linear omega whose
    # corners (0.5, 2, 3 s) are grid points, whatever the step (1 ms here: 3701 calls, not 370001)
    t = np.linspace(0.0, 3.7, 3701)
    w = np.array([p.omega(x) for x in t])
    quad = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])  # trapezoids: exact here
    for k in (10, 1235, 2500, 3700):
        assert p.angle(t[k]) == pytest.approx(quad[k], rel=1e-9)


def test_unbalance_force_under_acceleration_is_minus_m_times_the_mass_acceleration(write_scene, map_file):
    # the force the mass puts on the rotor is -m d2/dt2 (r (cos theta, sin theta)), theta the
    # integrated angle: m r Omega^2 outward and m r dOmega/dt against the turning
    scene = load_scene(write_scene(RUNUP.format(t0=0.0, t1=2.0, f0=10.0, f1=50.0, map=map_file, t_end=0.1)))
    from rotor_host.model.rotor import Rotor

    rotor = Rotor.from_toml(scene.rotor_path)
    f_ext = external_force(scene, rotor, np.zeros(rotor.n_dof))
    iy, iz = rotor.dof(5, "y"), rotor.dof(5, "z")
    m, r = 8.5e-3, 0.037
    pos = lambda t: r * np.array([math.cos(scene.speed.angle(t)), math.sin(scene.speed.angle(t))])  # noqa: E731
    h = 1e-5
    for t in (0.3, 1.1, 1.9):
        acc = (pos(t + h) - 2 * pos(t) + pos(t - h)) / h**2
        f = f_ext(t)
        np.testing.assert_allclose([f[iy], f[iz]], -m * acc, rtol=1e-5)


@pytest.mark.parametrize("direction", [1, -1])
def test_spectrum_of_a_circular_whirl(direction):
    t = np.arange(0, 2.0, 1e-4)
    f_whirl, A = 23.0, 4e-5
    arrays = {"t": t, "nodes": np.array([1]), "bearing_nodes": np.array([1]),
              "y": (A * np.cos(2 * math.pi * f_whirl * t))[:, None],
              "z": (direction * A * np.sin(2 * math.pi * f_whirl * t))[:, None],
              "speed_hz": np.linspace(30.0, 50.0, t.size)}
    sp = spectra(arrays, 1, window_s=0.5)
    k = np.argmax(sp.amp[2])
    assert sp.freq_hz[k] == pytest.approx(direction * f_whirl, abs=2.0)  # forward > 0, backward < 0
    assert sp.amp[2, k] == pytest.approx(A, rel=0.2)  # Hann window, frequency off-bin: within 20 %
    assert sp.speed_hz[0] == pytest.approx(32.5, abs=0.1)  # the mean speed of the first window


def test_profile_faults_are_named(write_scene, map_file):
    base = RUNUP.format(t0=0.0, t1=1.0, f0=10.0, f1=50.0, map=map_file, t_end=0.1)
    with pytest.raises(SceneError, match=r"\[speed_profile\] times_s must increase strictly"):
        load_scene(write_scene(base.replace("times_s = [0.0, 1.0]", "times_s = [1.0, 0.0]")))
    with pytest.raises(SceneError, match="same length"):
        load_scene(write_scene(base.replace("speeds_hz = [10.0, 50.0]", "speeds_hz = [10.0]")))
    with pytest.raises(SceneError, match=r"speed_hz = 30 differs from the \[speed_profile\] speed at t = 0, 10 Hz"):
        load_scene(write_scene("speed_hz = 30.0\n" + base))
    with pytest.raises(SceneError, match="missing key 'speed_hz'"):
        load_scene(write_scene(base.split("[speed_profile]")[0] + base.split("speeds_hz = [10.0, 50.0]")[1]))


@pytest.mark.slow
def test_paper_rotor_run_up_through_the_critical_into_oil_whip(write_scene, tmp_path):
    # 10 -> 60 Hz in 6 s with the shipped map: the 1x response peaks near the 22 Hz critical
    # (a little above it: a run-up passes the peak before the response has built up), and a
    # forward whirl near 0.4-0.5x, locked near the first critical, takes over well above the
    # ~43 Hz threshold of the steady analysis (it needs time to grow during the run-up)
    from conftest import MODELS

    from rotor_host.scenes.run import run_scene

    scene = load_scene(write_scene(RUNUP.format(t0=0.0, t1=6.0, f0=10.0, f1=60.0,
                                                map=MODELS / "maps" / "paper_bearing.json", t_end=6.0)))
    run = run_scene(scene, tmp_path / "out")
    assert run.ok
    s = summary(spectra(run.arrays, 6))
    assert 20.0 <= s["resonance_hz"] <= 28.0, s
    assert s["whirl_onset_hz"] is not None and 43.0 <= s["whirl_onset_hz"] <= 60.0, s
    assert 0.35 <= s["whirl_ratio"] <= 0.5 and 19.0 <= s["whirl_hz"] <= 27.0, s
    np.testing.assert_allclose(np.load(run.npz)["speed_hz"][[0, -1]], [10.0, 60.0])
