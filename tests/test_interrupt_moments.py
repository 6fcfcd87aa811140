"""Interrupts at every moment keep what finished, and the last line says what that is.

Each command runs in a subprocess held at one moment by tests/pause_at.py (closing the Dask
cluster after the last run, drawing compare's plots, a map's third row or its saving), so
the signal lands there every time, not by timing luck.
"""

import argparse
import json
import signal
import time

import pytest
from conftest import MODELS, start_command, wait_for

from bearing_fmu.io import outputs
from bearing_fmu.io.exits import run_command

SCENE = MODELS / "scenes" / "paper_22hz.toml"


def _interrupt(proc, marker, sig, group=False, timeout=60):
    """Send ``sig`` (to the process group, as Ctrl-C does, with ``group``) once the command is
    held at its pause; (seconds until it ended, stdout, stderr)."""
    import os

    wait_for(marker, proc)
    t0 = time.monotonic()
    os.killpg(proc.pid, sig) if group else proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=timeout)
    return time.monotonic() - t0, stdout, stderr


@pytest.mark.slow
@pytest.mark.parametrize("pause, sig", [("distributed:LocalCluster.close", signal.SIGINT),
                                        ("distributed:Client.close", signal.SIGTERM)])
def test_sweep_interrupted_while_closing_its_cluster_keeps_every_run(tmp_path, pause, sig):
    out = tmp_path / "out"
    marker = tmp_path / "paused"
    proc = start_command("rotor-host", "sweep", SCENE, "--speeds-hz", "20", "22", "--internal", "map", "--via",
                         "direct", "--t-end", "0.02", "--workers", "1", "--execution", "cluster", "--out", out, "--quiet", pause=pause,
                         env={"PAUSE_MARKER": str(marker)}, new_session=True)
    took, _, err = _interrupt(proc, marker, sig, group=sig == signal.SIGINT)
    assert proc.returncode == 128 + sig, err
    assert took < 5.0, f"{took:.1f} s after the signal"  # ~1.5 s, most of it drawing the diagram
    assert "Traceback" not in err
    stem = out / "sweep_paper_22hz_map"
    name = signal.Signals(sig).name
    assert err.strip().splitlines()[-1] == (
        f"rotor-host sweep: interrupted by {name}; kept: {stem}.md, {stem}.json, {stem}.png "
        "(2 of 2 runs finished, each with its .npz/.json)")
    summary = json.loads(stem.with_suffix(".json").read_text())
    assert summary["status"] == "interrupted" and summary["note"] == f"interrupted by {name}: all 2 runs had finished"
    assert [r["status"] for r in summary["rows"]] == ["ok", "ok"]
    assert not list(out.glob("*.lock"))


@pytest.mark.slow
def test_sweep_interrupted_while_drawing_its_diagram_keeps_the_table(tmp_path):
    out = tmp_path / "out"
    marker = tmp_path / "paused"
    proc = start_command("rotor-host", "sweep", SCENE, "--speeds-hz", "22", "--internal", "map", "--via", "direct",
                         "--t-end", "0.02", "--workers", "1", "--out", out, "--quiet",
                         pause="rotor_host.analyses.sweep.summary:plot_bifurcation", env={"PAUSE_MARKER": str(marker)})
    took, _, err = _interrupt(proc, marker, signal.SIGTERM)
    assert proc.returncode == 143 and took < 5.0, err
    stem = out / "sweep_paper_22hz_map"
    assert err.strip().splitlines()[-1].endswith(f"kept: {stem}.md, {stem}.json (1 of 1 runs finished, each with its "
                                                  ".npz/.json)")
    assert json.loads(stem.with_suffix(".json").read_text())["note"] == (
        "interrupted by SIGTERM while drawing the diagram: all 1 runs had finished")
    assert not stem.with_suffix(".png").exists()


@pytest.mark.slow
def test_compare_interrupted_while_plotting_keeps_its_table(tmp_path):
    out = tmp_path / "out"
    marker = tmp_path / "paused"
    proc = start_command("rotor-host", "compare", SCENE, "--via", "direct", "--internals", "linear", "--ref-grid",
                         "32x4", "--t-end", "0.005", "--out", out, "--quiet",
                         pause="rotor_host.analyses.compare:plot_error_vs_time", env={"PAUSE_MARKER": str(marker)})
    took, _, err = _interrupt(proc, marker, signal.SIGINT)
    assert proc.returncode == 130 and took < 2.0, err
    stem = out / "compare_paper_22hz"
    assert err.strip().splitlines()[-1] == (
        f"rotor-host compare: interrupted by SIGINT; kept: {stem}.md, {stem}.json (2 of 2 variant(s) finished, each "
        "with its run's .npz/.json)")
    table = json.loads(stem.with_suffix(".json").read_text())
    assert table["status"] == "interrupted" and [r["label"] for r in table["rows"]] == ["Reynolds 32x4", "linear"]
    assert table["note"] == "interrupted by SIGINT while drawing the plots: every variant had finished"
    assert not list(out.glob("*.png"))


MAP = ["map", "--resolution", "4x8", "--grid", "16x4", "--phases", "1", "--quiet"]


@pytest.mark.slow  # a command in a subprocess held at a moment; the compare case stays in the quick loop
def test_map_interrupted_while_saving_keeps_the_whole_map(tmp_path):
    from bearing_fmu.internals.map.tablefile import load_map

    marker = tmp_path / "paused"
    proc = start_command("bearing-fmu", *MAP, "-o", tmp_path / "m.json",
                         pause="bearing_fmu.internals.map.tablefile:save_map", env={"PAUSE_MARKER": str(marker)})
    took, _, err = _interrupt(proc, marker, signal.SIGINT)
    assert proc.returncode == 130 and took < 2.0, err
    assert err.strip().splitlines()[-1] == (
        f"bearing-fmu map: interrupted by SIGINT; kept: {tmp_path / 'm.json'} (the map was complete)")
    assert load_map(tmp_path / "m.json").n_eps == 4


@pytest.mark.slow  # a command in a subprocess held at a moment; the compare case stays in the quick loop
@pytest.mark.parametrize("workers", [1, 2])
def test_map_interrupted_mid_table_says_how_far_it_got(tmp_path, workers):
    """Held in the Reynolds solve of the third row (8 solves a row): alone, two rows are done and
    kept in the partial file, from which the same command resumes (tests/test_map_build.py); with
    two worker processes (each holding in its own first call) the parent does not wait for them:
    it ends them at once, and no row had come."""
    marker = tmp_path / "paused"
    proc = start_command("bearing-fmu", *MAP, "--workers", workers, "-o", tmp_path / "m.json",
                         pause="bearing_fmu.physics.solver.reynolds:Reynolds.force",
                         env={"PAUSE_MARKER": str(marker), "PAUSE_CALL": "17" if workers == 1 else "1"})
    took, _, err = _interrupt(proc, marker, signal.SIGTERM)
    assert proc.returncode == 143 and took < 2.0, err
    assert "Traceback" not in err
    partial = tmp_path / "m.json.partial"
    assert err.strip().splitlines()[-1] == (
        f"bearing-fmu map: interrupted by SIGTERM; kept: 2 of 4 rows of the map in {partial} (run the same command "
        "again to resume)" if workers == 1 else
        "bearing-fmu map: interrupted by SIGTERM; nothing kept: 0 of 4 rows of the map had been computed")
    assert not (tmp_path / "m.json").exists() and partial.exists() == (workers == 1)


def test_an_interrupt_after_the_results_were_written_names_them(tmp_path, capsys):
    def func(args):
        outputs.write_json(tmp_path / "a.json", {})
        raise KeyboardInterrupt  # e.g. while printing what it wrote

    assert run_command("rotor-host", argparse.Namespace(func=func, command="stability")) == 130
    assert capsys.readouterr().err.strip() == (
        f"rotor-host stability: interrupted by SIGINT; kept: the 1 file(s) written before it: {tmp_path / 'a.json'}")
