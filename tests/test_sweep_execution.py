"""Where a sweep runs (rotor_host/analyses/sweep/local.py): the choice by the work, and the same
rows whichever execution runs them (the runs are the same function on the same arguments, so
their results agree to the bit; only the timings, the process id and the file paths differ).

The figures (fixed costs of each execution against the work) are benchmarks/sweep_fixed_costs.py's.
"""

import json

import pytest
from conftest import MODELS

SCENE = MODELS / "scenes" / "paper_22hz.toml"
CHEAP = ["--internal", "map", "--via", "direct", "--t-end", "0.02", "--quiet"]
PER_PROCESS = {"pid", "wall_s", "integration_s", "setup_s", "files", "rescued"}


def _cli(*argv):
    from rotor_host.cli import main

    return main([str(a) for a in argv])


def _rows(out):
    summary = json.loads((out / "sweep_paper_22hz_map.json").read_text())
    return summary, [{k: v for k, v in r.items() if k not in PER_PROCESS} for r in summary["rows"]]


@pytest.fixture
def no_running_cluster(tmp_path, monkeypatch):
    """No cluster left running where the sweep looks for one (the user's own must not count)."""
    monkeypatch.delenv("DASK_SCHEDULER_ADDRESS", raising=False)
    monkeypatch.setenv("ROTOR_HOST_SCHEDULER_FILE", str(tmp_path / "none.json"))


def test_the_choice_follows_the_work(no_running_cluster, tmp_path, monkeypatch):
    from rotor_host.analyses.sweep import choose

    monkeypatch.setattr("os.cpu_count", lambda: 2)
    assert choose("auto", 11, workers=None, scheduler=None).kind == "pool"
    assert choose("auto", 11, workers=None, scheduler=None).workers == 2
    assert choose("auto", 1, workers=None, scheduler=None).kind == "inline"  # one run: nothing to share
    assert choose("auto", 11, workers=1, scheduler=None).kind == "inline"
    assert choose("auto", 3, workers=8, scheduler=None).workers == 3  # no idle worker started
    assert choose("cluster", 11, workers=None, scheduler=None).kind == "cluster"
    told = choose("auto", 11, workers=None, scheduler="tcp://10.0.0.5:8786")
    assert (told.kind, told.scheduler) == ("cluster", "tcp://10.0.0.5:8786")
    with pytest.raises(ValueError, match="^--execution pool: runs on this machine; --scheduler names a cluster"):
        choose("pool", 11, workers=None, scheduler="tcp://10.0.0.5:8786")
    # a stale scheduler file (nothing answers at its address) is said and passed over
    stale = tmp_path / "stale.json"
    stale.write_text(json.dumps({"address": "tcp://127.0.0.1:1"}))
    monkeypatch.setenv("ROTOR_HOST_SCHEDULER_FILE", str(stale))
    said = []
    assert choose("auto", 11, workers=None, scheduler=None, log=said.append).kind == "pool"
    assert said == [f"(the scheduler file {stale} names tcp://127.0.0.1:1, where no Dask scheduler answers now: "
                    "running on this machine)"]


def test_a_scheduler_file_that_is_not_one_is_named(tmp_path, capsys):
    bad = tmp_path / "sched.json"
    bad.write_text(json.dumps({"id": "x"}))
    assert _cli("sweep", SCENE, "--speeds-hz", "22", *CHEAP, "--scheduler", bad, "--out", tmp_path / "o") == 2
    assert capsys.readouterr().err.strip() == (
        f"rotor-host sweep: error: --scheduler {bad}: not a Dask scheduler file: no \"address\" such as "
        "tcp://HOST:PORT in it (found None)")


@pytest.mark.slow  # two sweeps of three runs with their diagrams: 4-8 s
def test_inline_and_pool_give_the_same_rows(no_running_cluster, tmp_path, capsys):
    rows = {}
    for how in ("inline", "pool"):
        out = tmp_path / how
        assert _cli("sweep", SCENE, "--speeds-hz", "20", "22", "44", *CHEAP, "--workers", "2", "--execution", how,
                    "--out", out) == 0
        summary, rows[how] = _rows(out)
        assert summary["execution"] == how and summary["fixed_costs_s"]["total"] >= 0
        text = capsys.readouterr().out
        assert "3 of 3 runs ok" in text and "\nfixed costs " in text and "; work " in text
        if how == "pool":
            assert "pool start (2 workers" in text
            assert len({r["pid"] for r in summary["rows"]}) >= 2  # the first in this process, the rest in the pool
    assert rows["inline"] == rows["pool"] and rows["pool"][0]["status"] == "ok"


@pytest.mark.slow
def test_a_local_cluster_gives_the_same_rows_as_this_process(no_running_cluster, tmp_path, capsys):
    rows = {}
    for how in ("inline", "cluster"):
        out = tmp_path / how
        assert _cli("sweep", SCENE, "--speeds-hz", "20", "44", *CHEAP, "--workers", "2", "--execution", how,
                    "--out", out) == 0
        rows[how] = _rows(out)[1]
    assert rows["inline"] == rows["cluster"]
    assert "cluster start (2 workers)" in capsys.readouterr().out


@pytest.mark.slow
def test_a_cluster_left_running_is_reused(no_running_cluster, tmp_path, monkeypatch, capsys):
    import logging

    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.CRITICAL) as cluster:
        f = tmp_path / "scheduler.json"
        f.write_text(json.dumps({"address": cluster.scheduler_address}))
        monkeypatch.setenv("ROTOR_HOST_SCHEDULER_FILE", str(f))
        out = tmp_path / "o"
        assert _cli("sweep", SCENE, "--speeds-hz", "20", "22", *CHEAP, "--out", out) == 0
    summary, _ = _rows(out)
    assert summary["execution"] == "cluster" and summary["cluster"] == cluster.scheduler_address
    assert "a cluster left running" in capsys.readouterr().out
