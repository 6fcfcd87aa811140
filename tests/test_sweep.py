"""rotor-host sweep: the swept values, what a run leaves in the summary, and sweeps on Dask.

The Dask tests, all marked slow (end to end: worker processes start and import the code, 6-10 s
each), run the paper rotor with the shipped force map called directly for 0.02 s per run, on an
existing cluster named by --scheduler (2 worker processes, started once for the module: 1-3 s)
and on the command's own LocalCluster of 2 workers (the default path), where one run fails
honestly (0.01 Hz: the film cannot carry the rotor's weight), and under Ctrl-C. The quick loop
keeps the parts: the swept values, one run (run_point), the summary, a missing scheduler.
"""

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import MODELS, ROOT, fill, start_command

from rotor_host.analyses.sweep import Point, points, run_point, settled_metrics, write_summary

SCENE = MODELS / "scenes" / "paper_22hz.toml"
CHEAP = ["--internal", "map", "--via", "direct", "--t-end", "0.02", "--quiet"]


def _cli(*argv):
    from rotor_host.cli import main

    return main([str(a) for a in argv])


# ------------------------------------------------------------------ the values swept

def _args(*argv):
    """The sweep's parsed arguments (its parser as the command line builds it)."""
    from rotor_host.cli import build_parser

    return build_parser().parse_args(["sweep", *[str(a) for a in argv]])


def test_ranges_include_both_ends():
    from rotor_host.analyses.sweep import swept_values as _flat

    # 12.5, 15, ..., 60: (60 - 12.5) / 2.5 + 1 = 20 values, 60 reached despite rounding
    v = _flat(_args(SCENE, "--speeds-hz", "12.5:60:2.5").speeds_hz, "--speeds-hz")
    assert len(v) == 20 and v[0] == 12.5 and v[-1] == 60.0 and np.allclose(np.diff(v), 2.5)
    # items are merged, sorted, each value once
    assert _flat(_args(SCENE, "--speeds-hz", "44", "20:24:2", "22").speeds_hz, "--speeds-hz") == [20, 22, 24, 44]
    assert _args(SCENE, "--unbalance-g", "0:8:4").unbalance_g == [[0.0, 4.0, 8.0]]  # a mass may be 0
    with pytest.raises(ValueError, match=r"^--speeds-hz: 1001 runs; a sweep takes at most 1000"):
        _flat(_args(SCENE, "--speeds-hz", "1:11:0.01").speeds_hz, "--speeds-hz")


@pytest.mark.parametrize("text", ["60:10:2", "10:60:0", "0:10:1", "0", "abc", "1:2", "nan"])
def test_bad_ranges_are_refused_by_the_option(text, capsys):
    with pytest.raises(SystemExit) as e:
        _args(SCENE, "--speeds-hz", text)
    assert e.value.code == 2
    assert "argument --speeds-hz: expected START:STOP:STEP Hz" in capsys.readouterr().err


def test_bad_input_names_the_option_before_any_work(tmp_path, capsys, paper_scene):
    with pytest.raises(SystemExit) as e:
        _cli("sweep", SCENE, "--speeds-hz", "60:10:2")
    assert e.value.code == 2 and "--speeds-hz" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # one of the two is required, not both
        _cli("sweep", SCENE, "--speeds-hz", "20", "--unbalance-g", "4")
    assert "not allowed with" in capsys.readouterr().err
    for extra, words in ((["--settle-s", "0.02"], "--settle-s 0.02: must be less than"),
                         (["--scheduler", "tcp://127.0.0.1:1", "--workers", "2"], "--workers: sets the size")):
        assert _cli("sweep", SCENE, "--speeds-hz", "20", *CHEAP, "--out", tmp_path, *extra) == 2
        assert words in capsys.readouterr().err
    no_unbalance = paper_scene(internal="map", via=None, t_end=0.02, unbalance_g=None,
                               map={"map": MODELS / "maps" / "paper_bearing.json"})
    assert _cli("sweep", no_unbalance, "--unbalance-g", "4", "--out", tmp_path, "--quiet") == 2
    assert "--unbalance-g: the scene" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        _cli("sweep", SCENE, "--speeds-hz", "20", "--scheduler", "localhost")
    assert "argument --scheduler: expected a Dask scheduler address such as tcp://" in capsys.readouterr().err
    # each run is at one constant speed: a run-up scene is refused
    assert _cli("sweep", MODELS / "scenes" / "paper_runup_10_60hz.toml", "--speeds-hz", "20", "--out", tmp_path,
                "--quiet") == 2
    assert "--speeds-hz: the scene" in (err := capsys.readouterr().err) and "has a [speed_profile]" in err
    # a Taylor surrogate answers at its own speed only (44 Hz here): a speed sweep with it is refused
    assert _cli("sweep", MODELS / "scenes" / "paper_44hz.toml", "--speeds-hz", "40", "44", "--internal", "taylor",
                "--out", tmp_path, "--quiet") == 2
    assert "the taylor internal answers only at the speed its data was made for (44 Hz" in capsys.readouterr().err
    assert not list(tmp_path.glob("sweep_*"))


@pytest.mark.slow
def test_no_scheduler_there_is_one_line():
    from rotor_host.analyses.sweep import dask_client

    with pytest.raises(ValueError, match=r"^--scheduler tcp://127.0.0.1:1: no Dask scheduler answered there"):
        with dask_client("tcp://127.0.0.1:1", None, connect_timeout_s=0.5):
            pass


@pytest.fixture
def not_a_scheduler():
    """An address on 127.0.0.1 that accepts TCP connections but says nothing (an HTTP server:
    test_an_http_server_at_scheduler_is_named)."""
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen(5)
        yield f"tcp://127.0.0.1:{s.getsockname()[1]}"


@pytest.fixture(params=["waits for a line", "answers at once"])
def http_server(request):
    """A tiny http.server on a free port of 127.0.0.1: one that waits for a request line (the
    Dask handshake has a newline byte in it on Python x.10 and x.y.10, and then it answers),
    and one that answers at once (Dask then read "HTTP/1.1" as a frame length: 3.07 EiB)."""
    import http.server
    import threading

    class Quiet(http.server.BaseHTTPRequestHandler):
        def log_message(self, *args):
            pass

    class Eager(Quiet):
        def handle(self):
            self.wfile.write(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")

    srv = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Eager if request.param == "answers at once" else Quiet)
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    yield f"tcp://127.0.0.1:{srv.server_address[1]}"
    srv.shutdown()
    srv.server_close()


@pytest.mark.slow  # a fit, a figure or a process end to end (about 1 s): the full suite's, out of the quick loop
def test_an_http_server_at_scheduler_is_named(tmp_path, http_server, monkeypatch, capsys):
    from bearing_fmu.parallel import cluster as dask_cluster

    monkeypatch.setattr(dask_cluster, "HANDSHAKE_TIMEOUT_S", 0.5)
    assert _cli("sweep", SCENE, "--speeds-hz", "22", *CHEAP, "--scheduler", http_server, "--out", tmp_path) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"rotor-host sweep: error: --scheduler {http_server}: an HTTP server answers there (HTTP/1."), err
    assert err.endswith("not a Dask scheduler; give the scheduler's own port (tcp://HOST:8786 by default), not its "
                        "dashboard's (8787) or another web server's")
    assert "MemoryError" not in err and not list(tmp_path.glob("sweep_*"))


@pytest.mark.slow  # a 5 s handshake timeout per peer; the connect refusal stays quick
def test_a_peer_that_is_not_a_scheduler_is_refused(tmp_path, not_a_scheduler, monkeypatch, capsys):
    from bearing_fmu.parallel import cluster as dask_cluster

    monkeypatch.setattr(dask_cluster, "HANDSHAKE_TIMEOUT_S", 1.0)
    t0 = time.monotonic()
    assert _cli("sweep", SCENE, "--speeds-hz", "22", *CHEAP, "--scheduler", not_a_scheduler, "--out", tmp_path) == 2
    assert time.monotonic() - t0 < 3.0
    assert capsys.readouterr().err.strip() == (
        f"rotor-host sweep: error: --scheduler {not_a_scheduler}: something accepts connections there but did not "
        "answer as a Dask scheduler within 1 s (no answer); give the scheduler's own port (8786 by default), not its "
        "dashboard's")
    assert not list(tmp_path.glob("sweep_*"))


@pytest.mark.slow
def test_a_silent_peer_ends_the_command_in_seconds(tmp_path, not_a_scheduler):
    """The command line with its defaults, as a user meets it: exit 2 in about 5 s (the handshake's
    5 s and the start-up; left to dask.distributed it would wait for ever). Bounded at 20 s: the
    tests run beside each other (pytest-xdist), and a loaded machine doubles the start-up."""
    proc = start_command("rotor-host", "sweep", SCENE, "--speeds-hz", "22", *CHEAP, "--scheduler", not_a_scheduler,
                         "--out", tmp_path)
    t0 = time.monotonic()
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 2 and time.monotonic() - t0 < 20.0, err
    assert f"--scheduler {not_a_scheduler}: something accepts connections there but did not answer as a Dask " \
           "scheduler within 5 s" in err


def test_points_have_distinct_stems():
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(SCENE).with_internal("map")
    pts = points(scene, [10.0, 12.5, 60.0])
    assert [p.stem for p in pts] == ["paper_22hz_map_10hz", "paper_22hz_map_12.5hz", "paper_22hz_map_60hz"]
    pts = points(scene, unbalance_g=[0.0, 8.5])
    assert [p.stem for p in pts] == ["paper_22hz_map_0g", "paper_22hz_map_8.5g"]
    assert all(p.speed_hz == 22.0 for p in pts)


# ------------------------------------------------------------- what a run leaves

def test_settled_metrics_by_hand():
    """A bearing eccentricity 0.3 + 0.1 sin(2 pi 5 t) and a disk circling its static position
    at 40 um, shaft at 5 Hz: after t = 0.5 s the range is 0.2..0.4 and the once-per-revolution
    samples all fall on 0.3 (synchronous: one point); the disk's distance is 40 um throughout."""
    t = np.arange(0, 1.0 + 1e-12, 1e-4)
    ecc = 0.3 + 0.1 * np.sin(2 * np.pi * 5 * t)
    q0 = np.array([1e-6, -2e-6, 3e-6, -4e-6])  # nodes 3 and 6: (y, z) each
    arrays = {"t": t, "nodes": np.array([3, 6]), "bearing_nodes": np.array([3]), "eccentricity": ecc[:, None],
              "q0": q0, "y": np.column_stack([np.zeros_like(t), q0[2] + 40e-6 * np.cos(2 * np.pi * 5 * t)]),
              "z": np.column_stack([np.zeros_like(t), q0[3] + 40e-6 * np.sin(2 * np.pi * 5 * t)])}
    m = settled_metrics(arrays, 0.5, 5.0, [6])
    (b,), (d,) = m["bearings"], m["disks"]
    assert b["node"] == 3 and b["ecc_max"] == pytest.approx(0.4, abs=1e-6) and b["ecc_min"] == pytest.approx(0.2, abs=1e-6)
    assert len(b["once_per_rev"]) == 3 and np.allclose(b["once_per_rev"], 0.3, atol=1e-9)  # t = 0.5, 0.7, 0.9
    assert d["node"] == 6 and d["amp_max_um"] == pytest.approx(40.0) and d["amp_min_um"] == pytest.approx(40.0)
    assert m["settled_samples"] == 5001
    # a run that stopped before the settled part: nothing to report, no NaN
    short = {k: (v[:100] if k in ("t", "eccentricity", "y", "z") else v) for k, v in arrays.items()}
    assert settled_metrics(short, 0.5, 5.0, [6]) == {"settled_samples": 0, "bearings": [], "disks": []}


def test_an_exception_in_the_worker_is_a_row(tmp_path):
    """A run that raises (here: the scene's force map missing on the worker) is reported as a
    row with status error and the exception named, not a lost task."""
    from dataclasses import replace

    from rotor_host.scenes.scene import load_scene

    scene = load_scene(SCENE).with_internal("map", via="direct", t_end_s=0.02)
    scene = replace(scene, options={**scene.options, "map": {"map": str(tmp_path / "gone.json")}})
    row = run_point(scene, Point(22.0, None, "gone_22hz"), str(tmp_path), 0.01, [6])
    assert row["status"] == "error" and row["message"].startswith("SceneError: ") and "gone.json" in row["message"]
    assert row["bearings"] == [] and "\n" not in row["message"]


def test_summary_names_failed_runs(tmp_path):
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(SCENE).with_internal("map", via="direct", t_end_s=0.02)
    ok = {"speed_hz": 22.0, "unbalance_g": None, "status": "ok", "message": "", "wall_s": 1.0, "integration_s": 0.5,
          "static_eccentricity": [0.21, 0.21],
          "bearings": [{"node": 3, "ecc_max": 0.25, "ecc_min": 0.2, "once_per_rev": [0.22]},
                       {"node": 9, "ecc_max": 0.25, "ecc_min": 0.2, "once_per_rev": [0.22]}],
          "disks": [{"node": 6, "amp_max_um": 150.0, "amp_min_um": 80.0, "once_per_rev_um": [100.0]}]}
    bad = {"speed_hz": 0.01, "unbalance_g": None, "status": "failed", "message": "static equilibrium: no",
           "wall_s": 0.1, "bearings": [], "disks": []}
    info = {"cluster": "local cluster", "workers": 2, "wall_s": 3.0, "run_s": 1.1}
    files = write_summary(tmp_path / "s", scene, [bad, ok], settle_s=0.01, bearing_nodes=[3, 9], disk_nodes=[6],
                          unbalance=False, info=info)
    md = files[0].read_text()
    assert "| 0.01 | failed | - |" in md and "| 22 | ok | 0.250 | 0.200 | 0.250 | 0.200 | 150.0 | 80.0 |" in md
    assert "- 0.01 Hz: failed: static equilibrium: no" in md
    assert json.loads(files[1].read_text())["rows"][0]["status"] == "failed"
    assert files[2].suffix == ".png" and files[2].stat().st_size > 10_000


# ------------------------------------------------------------------ sweeps on Dask

def _row(summary, speed):
    return next(r for r in summary["rows"] if r["speed_hz"] == speed)


@pytest.mark.slow
def test_speed_sweep_on_a_local_cluster(tmp_path, capsys):
    out = tmp_path / "out"
    assert _cli("sweep", SCENE, "--speeds-hz", "0.01", "22", "44", *CHEAP, "--workers", "2", "--execution", "cluster",
                "--out", out) == 0
    text = capsys.readouterr().out
    assert "2 of 3 runs ok" in text and "on 2 worker(s)" in text
    summary = json.loads((out / "sweep_paper_22hz_map.json").read_text())
    assert summary["workers"] == 2 and summary["settle_s"] == pytest.approx(0.01)  # default: the second half
    # 0.01 Hz: the film carries under 1 N at that speed (the run's own diagnosis), the weight
    # puts 16.7 N on each bearing, so there is no static equilibrium: a failed run, reported
    bad = _row(summary, 0.01)
    assert bad["status"] == "failed" and "static equilibrium" in bad["message"] and bad["bearings"] == []
    md = (out / "sweep_paper_22hz_map.md").read_text()
    assert "- 0.01 Hz: failed: static equilibrium" in md
    assert (out / "sweep_paper_22hz_map.png").stat().st_size > 10_000
    pids = set()
    for speed in (0.01, 22.0, 44.0):
        row, stem = _row(summary, speed), f"paper_22hz_map_{speed:g}hz"
        meta = json.loads((out / f"{stem}.json").read_text())
        assert meta["speed_hz"] == speed and meta["status"] == row["status"]  # each run kept, by its own name
        pids.add(row["pid"])
        if row["status"] != "ok":
            continue
        # the summary's values are those of the kept run: recomputed here from its npz
        a = np.load(out / f"{stem}.npz")
        late = a["t"] >= 0.01 - 1e-12
        assert [b["ecc_max"] for b in row["bearings"]] == pytest.approx(a["eccentricity"][late].max(axis=0).tolist())
        assert [b["ecc_min"] for b in row["bearings"]] == pytest.approx(a["eccentricity"][late].min(axis=0).tolist())
        c = list(a["nodes"]).index(6)  # the disk, recorded although the scene's [record] may omit it
        r = 1e6 * np.hypot(a["y"][late, c] - a["q0"][2 * c], a["z"][late, c] - a["q0"][2 * c + 1])
        assert row["disks"][0]["node"] == 6 and row["disks"][0]["amp_max_um"] == pytest.approx(r.max())
        assert len(row["bearings"][0]["once_per_rev"]) == math.floor(0.01 * speed + 1e-9) + 1
    assert os.getpid() not in pids  # the runs ran in the worker processes


@pytest.fixture(scope="module")
def scheduler():
    """An existing Dask cluster (2 worker processes, one thread each), as a user would start one."""
    import logging

    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.CRITICAL) as cluster:
        yield cluster.scheduler_address


@pytest.mark.slow
def test_unbalance_sweep_on_an_existing_cluster(tmp_path, scheduler):
    out = tmp_path / "out"
    assert _cli("sweep", SCENE, "--unbalance-g", "0:8:4", *CHEAP, "--scheduler", scheduler, "--out", out) == 0
    summary = json.loads((out / "sweep_paper_22hz_map_unbalance.json").read_text())
    assert summary["cluster"] == scheduler and summary["swept"] == "unbalance_g"
    amp = {r["unbalance_g"]: r["disks"][0]["amp_max_um"] for r in summary["rows"]}
    assert all(r["status"] == "ok" and r["speed_hz"] == 22.0 for r in summary["rows"])
    for m in (0, 4, 8):
        assert json.loads((out / f"paper_22hz_map_{m}g.json").read_text())["status"] == "ok"
    # without unbalance the rotor stays at its static equilibrium (it starts there)
    assert amp[0.0] < 1e-3
    # a small orbit on a nearly linear film: the response is proportional to the unbalance
    assert amp[8.0] / amp[4.0] == pytest.approx(2.0, rel=0.02)


@pytest.mark.slow
def test_a_full_disk_rescues_the_runs_and_the_summary(tmp_path, scheduler, tmpfs, capsys):
    """The runs write in the workers, the summary in the client: all of it lands beside the
    full folder, each run's row says where, and the sweep exits 1 (not 2)."""
    out = tmpfs(tmp_path / "out")
    fill(out, leave_bytes=4096)  # the probe and the summary's name lock fit, nothing else
    assert _cli("sweep", SCENE, "--speeds-hz", "20", "22", *CHEAP, "--scheduler", scheduler, "--out", out) == 1
    rescue = tmp_path / "out.rescued"
    summary = json.loads((rescue / "sweep_paper_22hz_map.json").read_text())
    assert [r["status"] for r in summary["rows"]] == ["ok", "ok"]
    for r in summary["rows"]:
        stem = f"paper_22hz_map_{r['speed_hz']:g}hz"
        assert r["files"] == [str(rescue / f"{stem}.npz"), str(rescue / f"{stem}.json")]
        assert r["rescued"][0]["path"] == str(out / f"{stem}.npz")
        assert json.loads((rescue / f"{stem}.json").read_text())["status"] == "ok"
    cap = capsys.readouterr()
    last = cap.err.strip().splitlines()[-1]
    assert last.startswith("rotor-host sweep: error: 7 result file(s) could not be written where asked (") and \
        last.endswith(f"No space left on device); they are in {rescue}")
    assert f"each run's .npz/.json in {rescue}\n" in cap.out  # where they are, not the full folder
    assert sorted(p.name for p in out.iterdir()) == ["filler"]


@pytest.mark.slow
def test_ctrl_c_keeps_the_runs_that_finished(tmp_path):
    """SIGINT to the whole process group (as Ctrl-C does, workers included) once the first run
    is written: exit 130, the summary of what finished, no worker process left behind."""
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    proc = subprocess.Popen([sys.executable, "-m", "rotor_host.cli", "sweep", str(SCENE), "--speeds-hz", "20:24:2",
                             "--internal", "map", "--via", "direct", "--t-end", "3", "--workers", "1",
                             "--out", str(out), "--quiet"], cwd=ROOT, env=env, start_new_session=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    first = out / "paper_22hz_map_20hz.json"
    t0 = time.monotonic()
    while not first.is_file() and proc.poll() is None and time.monotonic() - t0 < 120:
        time.sleep(0.05)
    assert proc.poll() is None, proc.communicate()
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "interrupted by SIGINT; kept:" in err and "Traceback" not in err
    summary = json.loads((out / "sweep_paper_22hz_map.json").read_text())
    assert summary["status"] == "interrupted" and "interrupted by SIGINT" in summary["note"]
    assert [r["speed_hz"] for r in summary["rows"]][:1] == [20.0] and len(summary["rows"]) < 3
    assert all(r["status"] == "ok" for r in summary["rows"])
    assert not list(out.glob("*.lock"))
    t0 = time.monotonic()  # the worker processes end with the command (multiprocessing's resource
    while time.monotonic() - t0 < 5:  # tracker, reparented, may take a moment to be reaped)
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        pytest.fail("a process of the sweep outlived it: " + subprocess.run(
            ["ps", "-g", str(proc.pid), "-o", "pid,stat,cmd"], capture_output=True, text=True).stdout)


@pytest.mark.slow
def test_fmu_sweep_equals_direct_sweep(tmp_path, scheduler, fmu, map_file, paper_scene):
    """The same two speeds through the bearing FMUs (loaded in the workers) and called directly:
    the FMU gives the direct call's forces to round-off (tests/test_cosim.py), so the summaries agree."""
    scene = paper_scene(internal="map", via="fmu", fmu=Path(fmu), t_end=0.02, map={"map": Path(map_file)})
    rows = {}
    for via in ("fmu", "direct"):
        out = tmp_path / via
        assert _cli("sweep", scene, "--speeds-hz", "22", "44", "--via", via, "--scheduler", scheduler, "--out", out,
                    "--quiet") == 0
        rows[via] = json.loads((out / "sweep_s_map.json").read_text())["rows"]
        assert json.loads((out / "s_map_44hz.json").read_text())["via"] == via
    for a, b in zip(rows["fmu"], rows["direct"]):
        assert a["status"] == b["status"] == "ok"
        assert a["bearings"][0]["ecc_max"] == pytest.approx(b["bearings"][0]["ecc_max"], rel=1e-9)
        assert a["disks"][0]["amp_max_um"] == pytest.approx(b["disks"][0]["amp_max_um"], rel=1e-9)


def test_titles_name_the_swept_quantity_and_range(tmp_path, monkeypatch):
    """The summary and the bifurcation diagram are titled by what was swept and over which range,
    not by the scene's description: paper_22hz.toml says "22 Hz (first critical speed), 8.5 g at
    37 mm on the disk" (its file), but swept over 12.5-60 Hz the title says shaft speed 12.5-60 Hz
    with that 8.5 g on node 6 held, and swept over 0-20 g it says unbalance 0-20 g at 22 Hz."""
    from rotor_host.analyses.sweep import summary as sweep_module
    from rotor_host.scenes.scene import load_scene

    titles = []
    monkeypatch.setattr(sweep_module, "save_figure",
                        lambda fig, path: titles.append(fig._suptitle.get_text()) or sweep_module.pyplot().close(fig)
                        or Path(path))
    scene = load_scene(SCENE).with_internal("map", via="direct", t_end_s=0.02)
    info = {"cluster": "local cluster", "workers": 1, "wall_s": 1.0, "run_s": 1.0}

    def row(speed, mass=None):
        return {"speed_hz": speed, "unbalance_g": mass, "status": "ok", "message": "", "wall_s": 0.1,
                "integration_s": 0.1, "static_eccentricity": [0.2, 0.2],
                "bearings": [{"node": 3, "ecc_max": 0.3, "ecc_min": 0.1, "once_per_rev": [0.2]}], "disks": []}

    files = write_summary(tmp_path / "speed", scene, [row(12.5), row(36.25), row(60.0)], settle_s=0.01,
                          bearing_nodes=[3], disk_nodes=[], unbalance=False, info=info)
    head = "Sweep of paper_22hz: shaft speed 12.5-60 Hz (3 runs), unbalance 8.5 g on node 6 at 37 mm"
    assert files[0].read_text().splitlines()[0] == f"# {head}"
    assert titles[-1].splitlines()[0] == head and "22 Hz" not in titles[-1]
    files = write_summary(tmp_path / "mass", scene, [row(22.0, 0.0), row(22.0, 20.0)], settle_s=0.01,
                          bearing_nodes=[3], disk_nodes=[], unbalance=True, info=info)
    head = "Sweep of paper_22hz: unbalance 0-20 g on node 6 at 37 mm (2 runs) at 22 Hz"
    assert files[0].read_text().splitlines()[0] == f"# {head}" and titles[-1].splitlines()[0] == head


def test_a_run_written_before_the_client_received_it_is_kept_from_its_files(tmp_path, paper_scene):
    # an interrupt can land after a worker wrote a run's files but before the client received
    # its row: the summary rebuilds that row from the files, the same row the worker returns
    from rotor_host.analyses.sweep import finished_on_disk, point_scene, points, run_point
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(paper_scene(internal="map", via="direct", t_end=0.02, map={"map": MODELS / "maps" /
                                                                                      "paper_bearing.json"}))
    (pt,) = points(scene, [22.0])
    want = run_point(point_scene(scene, pt, [6]), pt, str(tmp_path), 0.01, [6])
    got = finished_on_disk(tmp_path, pt, 0.01, [6])
    for key in ("pid", "rescued", "files"):
        want.pop(key), got.pop(key)
    assert got == want and want["status"] == "ok"
    (tmp_path / f"{pt.stem}.json").write_text('{"status": "running"}')  # a checkpoint is not a finished run
    assert finished_on_disk(tmp_path, pt, 0.01, [6]) is None
