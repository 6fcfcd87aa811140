"""Run-up and coast-down: the speed profile, the unbalance force under acceleration, the
waterfall spectra, and the paper rotor run up through its critical speed into oil whip.

Independent references: the profile's angle against numerical quadrature of its speed; the
unbalance force against minus the mass times the second derivative of its position (finite
differences); the spectrum of synthetic whirls of known radius, frequency and direction; the
paper rotor's first critical speed (22 Hz, the paper) and whirl threshold (~43 Hz, docs/stability.md).
What the summary calls a critical speed: only a 1x peak near a damped natural frequency the run
crosses (the paper rotor's first bending pair, 22.30 and 22.40 Hz on the shipped map: docs/campbell.md).
"""

import json
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
    assert 20.0 <= s["peak_1x_hz"] <= 28.0, s
    assert s["whirl_onset_hz"] is not None and 43.0 <= s["whirl_onset_hz"] <= 60.0, s
    assert 0.35 <= s["whirl_ratio"] <= 0.5 and 19.0 <= s["whirl_hz"] <= 27.0, s
    np.testing.assert_allclose(np.load(run.npz)["speed_hz"][[0, -1]], [10.0, 60.0])


# ------------------------------------------------------------------ what the summary calls a critical speed

def _synthetic_run(folder, f0, f1, amplitude, *, scene=None, t_end=2.0, dt=1e-3):
    """A saved "run" whose node 6 whirls forward at 1x with radius ``amplitude(speed)`` [m] while
    the speed goes linearly from f0 to f1 Hz; its json names ``scene`` as the run's source, as
    ``run_scene`` does. No integration: the summary's logic alone."""
    t = np.arange(0.0, t_end + dt / 2, dt)
    speed = f0 + (f1 - f0) * t / t_end
    angle = 2 * math.pi * np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * dt)])
    r = amplitude(speed)
    y6, z6 = r * np.cos(angle), r * np.sin(angle)
    arrays = {"t": t, "nodes": np.array([3, 6]), "bearing_nodes": np.array([3, 9]), "speed_hz": speed,
              "y": np.stack([0.05 * y6, y6], axis=1), "z": np.stack([0.05 * z6, z6], axis=1)}
    npz = folder / "run.npz"
    np.savez(npz, **arrays)
    (folder / "run.json").write_text(json.dumps({"source": None if scene is None else str(scene)}))
    return npz, arrays


def _response(fc, zeta=0.02, e=1e-5):
    """The unbalance response of a Jeffcott rotor: e r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2), r = f / fc."""
    return lambda f: e * (f / fc) ** 2 / np.sqrt((1 - (f / fc) ** 2) ** 2 + (2 * zeta * f / fc) ** 2)


@pytest.fixture
def paper_map_scene(write_scene):
    from conftest import MODELS

    return write_scene(RUNUP.format(t0=0.0, t1=1.0, f0=10.0, f1=30.0, map=MODELS / "maps" / "paper_bearing.json",
                                    t_end=1.0))


@pytest.mark.slow
def test_peak_is_a_critical_speed_only_where_one_is_crossed(paper_map_scene, tmp_path):
    """The paper rotor on its map crosses its first bending pair (22.30, 22.40 Hz) in a 10 -> 40 Hz
    run: a 1x peak at 22.7 Hz (a Jeffcott response with fc = 22.7 Hz) is that critical speed; a
    peak at 32 Hz (9.6 Hz off: more than 10 % of 22.4 Hz plus the 3.75 Hz a 0.25 s window spans
    at 15 Hz/s) is a "1x peak", not a critical speed. A 5 -> 15 Hz run crosses none: its 1x
    peak, the response growing as speed squared below the critical, is the end of the run, and
    the summary says no critical speed was crossed (the issue's "resonance at 155.6 Hz")."""
    from rotor_host.analyses.linear.crossings import run_criticals, scene_criticals
    from rotor_host.analyses.waterfall import peak_line
    from rotor_host.scenes.scene import load_scene

    crit = scene_criticals(load_scene(paper_map_scene), 10.0, 40.0)
    assert [round(c["speed_hz"], 1) for c in crit.criticals] == [22.3, 22.4] and not crit.note
    npz, arrays = _synthetic_run(tmp_path, 10.0, 40.0, _response(22.7), scene=paper_map_scene)
    s = summary(spectra(arrays, 6), crit.criticals)
    assert s["critical_hz"] == pytest.approx(22.4, abs=0.05), s
    assert peak_line(s, 10, 40).startswith("critical speed 22.4 Hz crossed, 1x peak at 2")
    _, arrays = _synthetic_run(tmp_path, 10.0, 40.0, _response(32.0), scene=paper_map_scene)
    s = summary(spectra(arrays, 6), crit.criticals)
    assert s["critical_hz"] is None and 31.0 <= s["peak_1x_hz"] <= 33.0, s
    assert peak_line(s, 10, 40).endswith("not a critical speed (critical speed(s) crossed: 22.3 Hz, 22.4 Hz)")
    _, arrays = _synthetic_run(tmp_path, 5.0, 15.0, _response(22.4), scene=paper_map_scene)
    below = run_criticals(npz, arrays)  # the json beside the npz names the scene
    assert below.criticals == [] and (below.lo_hz, below.hi_hz) == (5.0, 15.0)
    s = summary(spectra(arrays, 6), below.criticals)
    assert s["peak_at_end"] and s["critical_hz"] is None
    assert peak_line(s, 5, 15).endswith(", the end of the run (%.1f um 1x), not a critical speed (no critical "
                                        "speed crossed in 5-15 Hz)" % (s["peak_1x_amplitude_m"] * 1e6))


def _waterfall(capsys, *argv):
    from rotor_host.cli import main

    try:
        code = main(["waterfall", *map(str, argv)])
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err.strip().splitlines()[-1] if out.err.strip() else ""


def test_waterfall_refuses_what_it_cannot_draw(tmp_path, capsys):
    """Exit 2 and one line naming the option or the run: a run at one constant speed (a waterfall
    is spectra against a changing speed), a window of 1 ns (shorter than 16 samples of the 1 ms
    record and than 2 revolutions at the top speed, 30 Hz: 67 ms), orbits asked at 1000 Hz in a
    10-30 Hz run (formerly drawn at the nearest speed without a word)."""
    npz, _ = _synthetic_run(tmp_path, 22.0, 22.0, lambda f: 1e-5 + 0 * f)
    code, _, err = _waterfall(capsys, npz)
    assert code == 2 and "one constant speed, 22 Hz" in err and "[speed_profile]" in err
    npz, _ = _synthetic_run(tmp_path, 10.0, 30.0, _response(22.4))
    code, _, err = _waterfall(capsys, npz, "--window-s", "1e-9")
    assert code == 2 and err.endswith("--window-s 1e-09: shorter than 16 recorded samples (0.016 s at the record "
                                      "step 0.001 s) or 2 revolutions at the run's top speed 30 Hz (0.0667 s): give "
                                      "at least 0.0667 s (default 0.25 s)")
    code, _, err = _waterfall(capsys, npz, "--orbits-at-hz", "15", "1000")
    assert code == 2 and "--orbits-at-hz 1000: outside the run's speeds 10-30 Hz" in err
    assert not (tmp_path / "run_waterfall.png").exists()


def test_waterfall_without_its_scene_says_the_critical_speeds_are_unknown(tmp_path, capsys):
    """A run whose scene cannot be read any more: the peak is a "1x peak", never a critical speed,
    and the line says why the critical speeds are not known."""
    npz, _ = _synthetic_run(tmp_path, 10.0, 30.0, _response(22.4), t_end=1.0)
    code, out, _ = _waterfall(capsys, npz, "--nodes", "6", "--orbits-at-hz", "20")
    assert code == 0 and "node 6: 1x peak at 2" in out and "critical speeds not computed" in out
    assert "critical speed 2" not in out and (tmp_path / "run_waterfall.png").stat().st_size > 10_000


def test_run_of_a_run_up_below_its_critical_calls_no_resonance(paper_map_scene, tmp_path, capsys, monkeypatch):
    """`rotor-host run` of a run-up (its summary: ``report.run_and_report``): the paper rotor from 5
    to 15 Hz stays below its 22 Hz critical, so the 1x peak, at the top of the run, is "not a
    critical speed (no critical speed crossed in 5-15 Hz)", not a "resonance". The integration
    is replaced by a synthetic run (speed squared response) and the figures are not written, to
    keep the test short."""
    from rotor_host.analyses import report, waterfall
    from rotor_host.analyses.report import run_and_report
    from rotor_host.scenes import run as run_module
    from rotor_host.scenes.scene import load_scene

    _, arrays = _synthetic_run(tmp_path, 5.0, 15.0, _response(22.4), t_end=1.0)
    n = arrays["t"].size
    arrays.update(Fy=np.zeros((n, 2)), Fz=np.full((n, 2), -16.7), CR=np.array([90e-6, 90e-6]))
    meta = {"status": "ok", "message": "", "steps": n, "t_reached_s": 1.0, "wall_time_s": 0.1, "setup_time_s": 0.0,
            "newton_mean_evaluations_per_step": 2.0, "step_cuts": 0, "max_eccentricity": [0.5, 0.5],
            "crossed_clearance": False}
    fake = run_module.SceneRun(arrays, meta, tmp_path / "out" / "up_map.npz", tmp_path / "out" / "up_map.json")
    monkeypatch.setattr(run_module, "run_scene", lambda scene, out, progress=True: fake)
    monkeypatch.setattr(report, "plot_runs", lambda runs, path, **kw: path)
    monkeypatch.setattr(waterfall, "save_figure", lambda fig, path: waterfall.pyplot().close(fig) or path)
    scene = load_scene(paper_map_scene)
    assert run_and_report(scene, tmp_path / "out", progress=False) == 0
    out = capsys.readouterr().out
    assert "resonance" not in out
    line = next(x for x in out.splitlines() if x.startswith("node 6: "))
    assert ", the end of the run" in line and line.split("; ")[0].endswith(
        "not a critical speed (no critical speed crossed in 5-15 Hz)")
