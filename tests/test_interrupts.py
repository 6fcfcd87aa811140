"""Nothing lost: interrupts, kills, checkpoints and parallel runs through the real command line.

Each test starts ``rotor-host run`` in a subprocess (the exit code and stderr are the point),
on the paper rotor at 22 Hz with the Reynolds internal on a coarse grid so a run takes a few
seconds, and reads back what it left on disk.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT


def _scene(paper_scene, via, t_end, checkpoint, fmu=None):
    """The paper's 22 Hz scene (tests/conftest.py ``paper_scene``) on Reynolds 32 x 4, checkpoints
    every ``checkpoint`` s of wall time; its results are s_reynolds.*."""
    return paper_scene(file="s.toml", name="interrupt", via=via, fmu=fmu, t_end=t_end, grid=(32, 4),
                       record={"checkpoint_s": checkpoint})


def _env(tmp_path, code_cache):
    """The subprocess imports this checkout, shares the session's numba cache and has its own
    temp folder (to see that it leaves nothing there)."""
    tmp = tmp_path / "tmp"
    tmp.mkdir(exist_ok=True)
    return {**os.environ, "PYTHONPATH": str(ROOT), "BEARING_FMU_CACHE_DIR": str(code_cache), "TMPDIR": str(tmp),
            "MPLBACKEND": "Agg", "BEARING_FMU_BUILD_CACHE": str(tmp_path / "fmus")}


def _start(scene, out, env, *extra):
    return subprocess.Popen([sys.executable, "-m", "rotor_host.cli", "run", str(scene), "--out", str(out),
                             "--quiet", "--no-plots", *extra],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for_checkpoint(proc, path: Path, timeout: float = 120.0) -> dict:
    """The run's json once a checkpoint (status "running") with some steps is on disk."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if proc.poll() is not None:
            pytest.fail(f"the run ended before its first checkpoint: {proc.communicate()}")
        if path.is_file():
            try:
                meta = json.loads(path.read_text())
            except json.JSONDecodeError:  # cannot happen with the atomic rename: fail loudly
                pytest.fail(f"{path} was read half-written")
            if meta["status"] == "running" and meta["steps"] > 0:
                return meta
        time.sleep(0.05)
    proc.kill()
    pytest.fail("no checkpoint within the timeout")


@pytest.mark.slow
@pytest.mark.parametrize("via, sig", [("fmu", signal.SIGINT), ("direct", signal.SIGTERM), ("direct", signal.SIGKILL)])
def test_a_signal_keeps_what_was_computed(tmp_path, paper_scene, code_cache, fmu, via, sig):
    scene = _scene(paper_scene, via, t_end=5.0, checkpoint=0.3, fmu=Path(fmu) if via == "fmu" else None)
    out = tmp_path / "out"
    env = _env(tmp_path, code_cache)
    proc = _start(scene, out, env)
    json_path = out / "s_reynolds.json"
    first = _wait_for_checkpoint(proc, json_path)
    time.sleep(0.5)  # well inside the integration
    t_sig = time.monotonic()
    proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=30)
    stopped_after = time.monotonic() - t_sig
    meta = json.loads(json_path.read_text())
    arrays = np.load(out / "s_reynolds.npz")
    assert arrays["t"].size > 1 and arrays["t"][-1] == pytest.approx(meta["t_reached_s"])
    assert np.all(np.isfinite(arrays["Fy"]))
    if sig == signal.SIGKILL:  # nothing runs after kill -9: the last checkpoint is what is left
        assert proc.returncode == -signal.SIGKILL
        assert meta["status"] == "running" and meta["t_reached_s"] >= first["t_reached_s"]
        return
    assert proc.returncode == 128 + sig, stderr
    assert stopped_after < 5.0  # "within about a second", with room for a loaded CI machine
    assert "Traceback" not in stderr
    assert f"interrupted by {signal.Signals(sig).name}" in stderr
    assert meta["status"] == "interrupted" and meta["signal"] == signal.Signals(sig).name
    assert 0.0 < meta["t_reached_s"] < 5.0 and meta["t_reached_s"] > first["t_reached_s"]
    # every FMU instance freed and its extraction removed; no result lock left behind
    assert not list((tmp_path / "tmp").glob("bearing_fmu_*"))
    assert not list(out.glob("*.lock"))


@pytest.mark.slow
def test_parallel_runs_into_one_folder_all_land(tmp_path, paper_scene, code_cache):
    """Three runs of one FMU scene into one folder at once: each builds (or reuses) the FMU
    without breaking another's, and each result is complete under its own name."""
    scene = _scene(paper_scene, "fmu", t_end=0.005, checkpoint=60)
    out = tmp_path / "out"
    env = _env(tmp_path, code_cache)
    procs = [_start(scene, out, env) for _ in range(3)]
    results = [p.communicate(timeout=300) for p in procs]
    for p, (stdout, stderr) in zip(procs, results):
        assert p.returncode == 0, stderr
        assert "Traceback" not in stderr
    # the runs overlap (each holds its name from before its FMU build to its end): three names
    stems = sorted(p.stem for p in out.glob("*.json"))
    assert stems == ["s_reynolds", "s_reynolds-2", "s_reynolds-3"], stems
    for stem in stems:
        meta = json.loads((out / f"{stem}.json").read_text())
        assert meta["status"] == "ok"
        t = np.load(out / f"{stem}.npz")["t"]
        assert t[-1] == pytest.approx(0.005)
    # each run printed the names it wrote, and no two printed the same
    written = [next(line for line in stdout.splitlines() if line.startswith("wrote")) for stdout, _ in results]
    assert len(set(written)) == 3
    builds = Path(env["BEARING_FMU_BUILD_CACHE"])
    assert len(list(builds.glob("*.fmu"))) == 1  # content-addressed: one FMU for one content
    assert not list(out.glob("*.lock")) and not list(builds.glob("*.tmp"))
