"""Results survive a failed write (bearing_fmu.io.outputs: the rescue; bearing_fmu.io.exits: exit 1).

A full file system is a small tmpfs filled up, a read-only folder a tmpfs remounted read-only
(chmod does not stop root), a taken name a folder where the result file goes. The writers are
tested in this process; the commands (exit codes, what lands where) as subprocesses.
"""

import argparse
import errno
import json
import tempfile

import numpy as np
import pytest
from conftest import MODELS, fill, read_only, start_command, wait_for, write_scene

from bearing_fmu.io import outputs
from bearing_fmu.io.exits import run_command


@pytest.fixture(autouse=True)
def _fresh_ledger():
    outputs.take_rescued(), outputs.take_written()
    yield
    outputs.take_rescued(), outputs.take_written()


# ------------------------------------------------------------------------------ the writers

def test_a_full_disk_puts_the_result_beside_its_folder(tmp_path, tmpfs, capsys):
    out = tmpfs(tmp_path / "out")
    fill(out)
    path = outputs.write_json(out / "r.json", {"x": list(range(2000))})
    assert path == tmp_path / "out.rescued" / "r.json" and json.loads(path.read_text())["x"][-1] == 1999
    err = capsys.readouterr().err
    assert f"cannot write {out / 'r.json'} (No space left on device); written to {path} instead" in err
    # the folder refused once: the command's next result for it joins the first in the rescue
    assert outputs.write_text(out / "r.md", "x") == tmp_path / "out.rescued" / "r.md"
    assert [(r.path, r.reason) for r in outputs.take_rescued()] == [
        (str(out / "r.json"), "No space left on device"), (str(out / "r.md"), "No space left on device")]
    assert sorted(p.name for p in out.iterdir()) == ["filler"]  # no temporary left


def test_a_read_only_folder_and_parent_send_it_to_the_temp_folder(tmp_path, tmpfs, monkeypatch):
    d = tmpfs(tmp_path / "d")
    (d / "out").mkdir()
    read_only(d)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    path = outputs.savez(d / "out" / "r.npz", t=np.arange(3.0))
    assert path == tmp_path / "tmp" / "out.rescued" / "r.npz"
    assert np.load(path)["t"].tolist() == [0.0, 1.0, 2.0]
    assert outputs.take_rescued()[0].reason == "Read-only file system"


def test_a_folder_at_the_result_name_moves_that_file_only(tmp_path):
    out = tmp_path / "out"
    (out / "r.json").mkdir(parents=True)
    assert outputs.write_json(out / "r.json", {}) == tmp_path / "out.rescued" / "r.json"
    assert outputs.write_json(out / "s.json", {}) == out / "s.json"  # the folder itself takes files
    assert [r.reason for r in outputs.take_rescued()] == ["Is a directory"]


def test_a_stale_file_at_the_name_does_not_pass_for_the_result(tmp_path, tmpfs):
    out = tmpfs(tmp_path / "out")
    (out / "r.json").write_text('{"status": "running"}')  # an earlier checkpoint
    fill(out)
    outputs.write_json(out / "r.json", {"status": "ok", "pad": "x" * 8000})
    assert not (out / "r.json").exists()
    assert json.loads((tmp_path / "out.rescued" / "r.json").read_text())["status"] == "ok"


def test_nowhere_to_write_fails_naming_the_path(tmp_path, tmpfs, monkeypatch):
    d = tmpfs(tmp_path / "d")
    (d / "out").mkdir()
    (d / "tmp").mkdir()
    read_only(d)
    monkeypatch.setattr(tempfile, "tempdir", str(d / "tmp"))
    with pytest.raises(outputs.ResultNotWritten, match=rf"cannot write {d / 'out' / 'r.json'} \(Read-only file "
                                                       r"system\), nor in a rescue folder .*out.rescued"):
        outputs.write_json(d / "out" / "r.json", {})


def test_a_checkpoint_raises_naming_its_path_and_is_not_rescued(tmp_path, tmpfs):
    out = tmpfs(tmp_path / "out")
    fill(out)
    with pytest.raises(OSError) as info:
        outputs.write_json(out / "c.json", {"pad": "x" * 8000}, rescue=False)
    assert (info.value.errno, info.value.filename) == (errno.ENOSPC, str(out / "c.json"))
    assert not (tmp_path / "out.rescued").exists() and outputs.take_rescued() == []


@pytest.mark.parametrize("case, code", [("rescued", 1), ("full disk", 1), ("missing input", 2)])
def test_exit_codes_of_a_write_the_machine_refused(tmp_path, tmpfs, capsys, case, code):
    out = tmpfs(tmp_path / "out")
    fill(out)

    def func(args):
        if case == "rescued":
            outputs.write_json(out / "r.json", {"pad": "x" * 8000})
            return 0
        if case == "full disk":  # a write outside the writers (a library's own)
            raise OSError(errno.ENOSPC, "No space left on device", str(out / "cache.bin"))
        raise FileNotFoundError(errno.ENOENT, "No such file or directory", "scene.toml")

    assert run_command("rotor-host", argparse.Namespace(func=func, command="run")) == code
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert last == {
        "rescued": f"rotor-host run: error: 1 result file(s) could not be written where asked ({out / 'r.json'}: "
                   f"No space left on device); they are in {tmp_path / 'out.rescued'}",
        "full disk": f"rotor-host run: error: {out / 'cache.bin'}: No space left on device",
        "missing input": "rotor-host run: error: scene.toml: No such file or directory"}[case]


# ------------------------------------------------------------------------------ the commands

SCENE = """
    internal = "reynolds"
    via = "direct"
    speed_hz = 22.0
    [reynolds]
    n_theta = 32
    n_x = 4
    [time]
    t_end_s = 0.01
    dt_s = 1e-4
    [record]
    checkpoint_s = {checkpoint}
"""


@pytest.mark.slow
def test_a_run_into_a_full_disk_keeps_running_and_rescues_its_result(tmp_path, tmpfs, code_cache):
    """Full but for one page (the run's name lock): every checkpoint fails (one warning), the
    run goes on, its result lands beside the folder; exit 1, not 2."""
    scene = write_scene(tmp_path, SCENE.format(checkpoint=0.001))
    out = tmpfs(tmp_path / "out")
    fill(out, leave_bytes=4096)
    proc = start_command("rotor-host", "run", scene, "--out", out, "--quiet", "--no-plots", code_cache=code_cache)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 1, stderr
    assert "Traceback" not in stderr
    warnings = [line for line in stderr.splitlines() if line.startswith("warning: checkpoint not written")]
    assert warnings == [f"warning: checkpoint not written: {out / 's_reynolds.npz'}: No space left on device "
                        "(the run goes on)"]
    rescue = tmp_path / "out.rescued"
    assert f"cannot write {out / 's_reynolds.npz'} (No space left on device); written to " \
           f"{rescue / 's_reynolds.npz'} instead" in stderr
    assert stderr.strip().splitlines()[-1] == (
        f"rotor-host run: error: 2 result file(s) could not be written where asked ({out / 's_reynolds.npz'}: "
        f"No space left on device); they are in {rescue}")
    meta = json.loads((rescue / "s_reynolds.json").read_text())
    assert meta["status"] == "ok" and meta["t_reached_s"] == pytest.approx(0.01)
    assert np.load(rescue / "s_reynolds.npz")["t"][-1] == pytest.approx(0.01)
    assert f"wrote {rescue / 's_reynolds.npz'}, {rescue / 's_reynolds.json'}" in stdout
    assert sorted(p.name for p in out.iterdir()) == ["filler"]  # no half file, no lock, no stale checkpoint


@pytest.mark.slow  # a command in a subprocess; the full-disk run stays in the quick loop
def test_a_folder_made_read_only_mid_run_rescues_the_result(tmp_path, tmpfs, code_cache):
    """The run is held just before it writes its result (tests/pause_at.py), the folder is
    remounted read-only, the run goes on: exit 1, the result beside the folder, named."""
    scene = write_scene(tmp_path, SCENE.format(checkpoint=60))
    out = tmpfs(tmp_path / "out", size="1m")
    marker, go = tmp_path / "paused", tmp_path / "go"
    proc = start_command("rotor-host", "run", scene, "--out", out, "--quiet", "--no-plots",
                    pause="rotor_host.scenes.run:savez", code_cache=code_cache,
                    env={"PAUSE_MARKER": str(marker), "PAUSE_GO": str(go), "PAUSE_KWARGS": '{"rescue": true}'})
    wait_for(marker, proc)
    read_only(out)
    go.touch()
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 1, stderr
    rescue = tmp_path / "out.rescued"
    assert f"({out / 's_reynolds.npz'}: Read-only file system); they are in {rescue}" in stderr.splitlines()[-1]
    assert json.loads((rescue / "s_reynolds.json").read_text())["status"] == "ok"


@pytest.mark.slow  # a command in a subprocess; the full-disk run stays in the quick loop
def test_stability_json_at_a_name_taken_by_a_folder(tmp_path):
    out = tmp_path / "out"
    (out / "stability_rotor_paper_map.json").mkdir(parents=True)
    proc = start_command("rotor-host", "stability", MODELS / "rotor_paper.toml", "--speeds-hz", "20:24:2",
                    "--internal", "map", "--out", out, "--no-plots")
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 1, stderr
    rescued = tmp_path / "out.rescued" / "stability_rotor_paper_map.json"
    assert json.loads(rescued.read_text())["internal"] == "map"
    assert (out / "stability_rotor_paper_map.md").is_file()  # the folder takes the others
    assert f"wrote {out / 'stability_rotor_paper_map.md'}, {rescued}" in stdout
    assert stderr.strip().splitlines()[-1] == (
        f"rotor-host stability: error: 1 result file(s) could not be written where asked "
        f"({out / 'stability_rotor_paper_map.json'}: Is a directory); they are in {rescued.parent}")


@pytest.mark.slow  # a command in a subprocess; the full-disk run stays in the quick loop
def test_a_map_into_a_full_disk_is_rescued(tmp_path, tmpfs):
    out = tmpfs(tmp_path / "maps")
    fill(out, leave_bytes=4096)  # the probe before any work passes; the map does not fit
    proc = start_command("bearing-fmu", "map", "--resolution", "8x16", "--grid", "16x4", "--phases", "1", "--quiet",
                    "-o", out / "m.json")
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 1, stderr
    rescued = tmp_path / "maps.rescued" / "m.json"
    assert json.loads(rescued.read_text())["n_eps"] == 8 and f"wrote {rescued}" in stdout
    assert f"({out / 'm.json'}: No space left on device); they are in {rescued.parent}" in stderr


def test_a_full_disk_is_refused_before_any_work(tmp_path, tmpfs, capsys):
    out = tmpfs(tmp_path / "out")
    fill(out)
    with pytest.raises(ValueError, match=r"--out .*out: cannot write there \(No space left on device\)"):
        outputs.ensure_writable(out, "--out")


def test_an_fmu_built_into_a_full_disk_is_where_the_build_says(tmp_path, tmpfs):
    """The FMU the folder refuses is rescued beside it and the build returns that path (a run then
    loads it from there, instead of reporting an FMU 'not found' before the real cause)."""
    import zipfile

    from bearing_fmu.fmu.build import build_fmu

    out = tmpfs(tmp_path / "fmus")
    fill(out, leave_bytes=4096)
    path = build_fmu(out / "b.fmu")
    assert path == tmp_path / "fmus.rescued" / "b.fmu" and zipfile.is_zipfile(path)
    assert [r.path for r in outputs.take_rescued()] == [str(out / "b.fmu")]
