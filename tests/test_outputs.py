"""Result files that cannot collide or vanish (bearing_fmu.io.outputs) and what run_scene leaves
on disk when it cannot even start integrating."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from bearing_fmu.io import outputs


def test_claim_gives_a_running_name_to_one_process_only(tmp_path):
    a = outputs.claim(tmp_path, "run")
    b = outputs.claim(tmp_path, "run")  # held by this (live) process: the next free name
    assert (a.stem, b.stem) == ("run", "run-2")
    assert a.path(".npz") == tmp_path / "run.npz"
    a.release()
    with outputs.claim(tmp_path, "run") as c:  # released: the name is free again
        assert c.stem == "run"
    assert not (tmp_path / "run.lock").exists()
    b.release()


def test_a_dead_process_does_not_hold_its_name(tmp_path):
    # a run killed with -9 leaves its lock; the pid in it is gone, so the name is taken over
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    (tmp_path / "run.lock").write_text(dead.stdout.strip())
    with outputs.claim(tmp_path, "run") as c:
        assert c.stem == "run"
        assert (tmp_path / "run.lock").read_text() == str(os.getpid())


def test_a_command_ended_by_a_signal_frees_the_names_it_still_held(tmp_path):
    """A signal landing between a run's last write and its own release (the window a fresh-clone
    CI hit in the sweep's Ctrl-C test) left ``<stem>.lock``: the command's end frees it."""
    from types import SimpleNamespace

    from bearing_fmu.io.exits import run_command

    def interrupted_before_its_release(args):
        outputs.claim(tmp_path, "run")  # held, never released by the "run"
        raise KeyboardInterrupt

    code = run_command("test", SimpleNamespace(func=interrupted_before_its_release, command="run"))
    assert code == 130 and not list(tmp_path.glob("*.lock"))
    with outputs.claim(tmp_path, "run") as c:  # the name is free again
        assert c.stem == "run"



def test_a_signal_while_a_name_is_being_claimed_leaves_no_lock(tmp_path, monkeypatch):
    """The second window a fresh-clone CI hit (the sweep's Ctrl-C test, a run's lock left): a
    SIGINT landing after the lock file was created but before its Claim was registered. It is
    held until the Claim exists, then raised, and the name freed: no lock, whoever calls claim."""
    import signal

    from bearing_fmu.io.interrupts import Interrupted, handled

    real_fdopen = os.fdopen

    def fdopen_then_ctrl_c(fd, *a, **kw):  # the signal lands in the window (the lock exists, not yet its pid)
        os.kill(os.getpid(), signal.SIGINT)
        return real_fdopen(fd, *a, **kw)

    monkeypatch.setattr(outputs.os, "fdopen", fdopen_then_ctrl_c)
    with handled(), pytest.raises(Interrupted):
        outputs.claim(tmp_path, "run")
    monkeypatch.undo()
    assert not list(tmp_path.glob("*.lock")) and not outputs._HELD
    with outputs.claim(tmp_path, "run") as c:
        assert c.stem == "run"


def test_a_signal_while_a_temporary_is_made_leaves_no_temporary(tmp_path, monkeypatch):
    """A SIGINT landing inside mkstemp (the temporary made, its name not yet returned) is held
    until the name is known, then raised, and the temporary removed: the folder stays empty."""
    import signal
    import tempfile

    from bearing_fmu.io.interrupts import Interrupted, handled

    real_mkstemp = tempfile.mkstemp

    def mkstemp_then_ctrl_c(*a, **kw):
        made = real_mkstemp(*a, **kw)
        os.kill(os.getpid(), signal.SIGINT)
        return made

    monkeypatch.setattr(outputs.tempfile, "mkstemp", mkstemp_then_ctrl_c)
    with handled(), pytest.raises(Interrupted):
        outputs.write_json(tmp_path / "a.json", {"x": 1})
    assert not list(tmp_path.iterdir())


def test_atomic_writes_leave_the_old_file_or_the_new_one(tmp_path):
    path = tmp_path / "a.json"
    outputs.write_json(path, {"x": 1})
    assert json.loads(path.read_text()) == {"x": 1}

    class Boom(Exception):
        pass

    def fail(f):
        f.write(b"{half")
        raise Boom

    with pytest.raises(Boom):
        outputs._atomic(path, fail)
    assert json.loads(path.read_text()) == {"x": 1}  # untouched
    assert [p.name for p in tmp_path.iterdir()] == ["a.json"]  # no temporary left
    outputs.savez(tmp_path / "b.npz", t=np.arange(3.0))
    assert np.load(tmp_path / "b.npz")["t"].tolist() == [0.0, 1.0, 2.0]


@pytest.mark.parametrize("case", ["file", "under_file"])
def test_an_output_folder_that_cannot_be_one_is_named(tmp_path, case):
    f = tmp_path / "f"
    f.write_text("")
    target = f if case == "file" else f / "sub"
    with pytest.raises(ValueError, match=r"--out .*f.*(is a file|part of this path is a file)"):
        outputs.ensure_writable(target, "--out")
    with pytest.raises(ValueError, match="-o .* is a folder"):
        outputs.ensure_output_file(tmp_path, "-o")


def test_an_unwritable_folder_is_refused_before_any_work(tmp_path, tmpfs):
    # a read-only file system (root writes into a chmod 555 folder, so the test makes one that
    # nobody can write: a tmpfs remounted read-only, as CI runs as root too)
    from conftest import read_only

    ro = tmpfs(tmp_path / "ro")
    read_only(ro)
    with pytest.raises(ValueError, match=r"--out .*ro/x: cannot write there \(Read-only file system\)"):
        outputs.ensure_writable(ro / "x", "--out")


def test_a_run_without_static_equilibrium_still_writes_its_json(tmp_path, paper_scene):
    # a load far beyond what the bearings carry (1e9 N on the disk): no equilibrium; the run
    # says so in its json (status failed) instead of stopping without a file
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    s = load_scene(paper_scene(t_end=0.001, grid=(32, 4), unbalance_g=None, static_loads=[{"node": 6, "Fz_N": -1e9}]))
    run = run_scene(s, tmp_path / "out")
    meta = json.loads(run.json.read_text())
    assert meta["status"] == "failed" and "carries at most" in meta["message"]
    # the disk sits midway between the bearings: each carries half (plus half the weight)
    assert meta["equilibrium"]["load_N"] == pytest.approx(5e8, rel=1e-6) and meta["equilibrium"]["bearing"]
    assert meta["steps"] == 0 and meta["equilibrium_eccentricity"] is None
    assert np.load(run.npz)["t"].size == 0
