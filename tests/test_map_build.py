"""``bearing-fmu map`` as row tasks (issue 35): an interrupted build, or one whose worker died,
resumes from its partial file to the very table an uninterrupted build makes (the reference: the
same table from ``tabulate`` in one go, compared bit for bit); the map store's key and its hits and
misses; ``--scheduler`` with a running Dask cluster and with an address where none answers."""

from __future__ import annotations

import json
import multiprocessing
import os
import shutil
import signal
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.map import store
from bearing_fmu.internals.map.build import build_map
from bearing_fmu.internals.map.groovemap import tabulate_grooved
from bearing_fmu.internals.map.store import map_key, settings_for, store_path, stored_file
from bearing_fmu.internals.map.tables import tabulate
from bearing_fmu.physics.params import PAPER_BEARING as P
from bearing_fmu.physics.params import BearingParams
from conftest import run_cli

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "rotor_host" / "bundled"
GROOVED = BearingParams.from_toml(MODELS / "bearing_paper_2groove.toml")
TINY = dict(resolution=(6, 8), grid=(16, 4), phases=1)
TINY_CLI = ["--resolution", "6x8", "--grid", "16x4", "--phases", "1", "--quiet"]


def stop_at(rows: int, action=None):
    """A ``build_map`` progress that interrupts the build once ``rows`` rows are in (or does ``action``)."""
    def progress(resumed):
        def on(n):
            if n == rows:
                if action is None:
                    raise KeyboardInterrupt
                action()
        return on
    return progress


def whole(params, settings):
    """The same table built in one go, without a partial file."""
    kw = dict(n_eps=settings.n_eps, n_beta=settings.n_beta, n_theta=settings.n_theta, n_x=settings.n_x,
              n_phase=settings.n_phase)
    if settings.n_phi is None:
        return tabulate(params, **kw)
    return tabulate_grooved(params, n_phi=settings.n_phi, **kw)


@pytest.mark.parametrize("params, workers", [(P, 1), (GROOVED, 2)], ids=["full bore, here", "grooved, 2 processes"])
def test_an_interrupted_build_resumes_to_the_same_table(tmp_path, params, workers):
    settings = settings_for(params, n_phi=None if params is P else 4, **TINY)
    partial = tmp_path / "m.json.partial"
    with pytest.raises(KeyboardInterrupt) as exc:
        build_map(params, settings, partial, workers=workers, progress=stop_at(3))
    assert exc.value.map_rows_done == 3
    assert len(partial.read_text().splitlines()) == 1 + 3  # the header and the rows solved
    said = []
    table = build_map(params, settings, partial, workers=workers, log=said.append)
    assert said == [f"resuming: 3 of 6 rows already solved in {partial}"]
    assert table.provenance["resumed_rows"] == 3 and not partial.exists()
    ref = whole(params, settings)
    assert np.array_equal(table.H, ref.H) and np.array_equal(table.Q, ref.Q)


def test_a_worker_that_dies_ends_the_build_and_its_rows_resume(tmp_path):
    settings = settings_for(P, resolution=(12, 16), grid=(32, 4), phases=1)
    partial = tmp_path / "m.json.partial"

    def kill_a_worker():
        os.kill(multiprocessing.active_children()[0].pid, signal.SIGKILL)

    with pytest.raises(RuntimeError, match="a worker process of the build died") as exc:
        build_map(P, settings, partial, workers=2, progress=stop_at(1, kill_a_worker))
    kept = exc.value.map_rows_done
    assert 1 <= kept < 12 and len(partial.read_text().splitlines()) == 1 + kept
    said = []
    table = build_map(P, settings, partial, workers=2, log=said.append)
    assert said == [f"resuming: {kept} of 12 rows already solved in {partial}"]
    ref = whole(P, settings)
    assert np.array_equal(table.H, ref.H) and np.array_equal(table.Q, ref.Q)


def test_the_partial_file_of_another_build_is_not_resumed(tmp_path):
    partial = tmp_path / "m.json.partial"
    with pytest.raises(KeyboardInterrupt):
        build_map(P, settings_for(P, **TINY), partial, progress=stop_at(2))
    other = settings_for(P, **{**TINY, "grid": (32, 4)})
    said = []
    table = build_map(P, other, partial, log=said.append)
    assert said == [] and table.provenance["resumed_rows"] == 0
    assert np.array_equal(table.H, whole(P, other).H)


# ------------------------------------------------------------------ the map store


def test_the_store_key_changes_with_what_determines_the_map(monkeypatch):
    base = settings_for(P, **TINY)
    key = map_key(P, base)
    # the map serves every bearing of its L/D: D, CR and mu do not enter (F = S r G, docs/forcemap.md)
    assert map_key(replace(P, D=2 * P.D, L=2 * P.L, CR=2 * P.CR, mu=3 * P.mu), base) == key
    changed = [map_key(replace(P, L=1.1 * P.L), base),  # L/D
               map_key(GROOVED, settings_for(GROOVED, n_phi=4, **TINY))]  # the bore
    changed += [map_key(P, replace(base, **kw)) for kw in (
        {"n_eps": 7}, {"n_beta": 10}, {"eps_max": 0.98}, {"n_theta": 32}, {"n_x": 8}, {"cavitation": "gumbel"},
        {"n_phase": 2}, {"flows": False})]
    monkeypatch.setattr(store, "source_digest", lambda *parts: "another solver")
    changed.append(map_key(P, base))
    assert len({key, *changed}) == 1 + len(changed)


def test_map_writes_into_the_store_and_finds_it_there(tmp_path, capsys):
    code, text, err = run_cli("bearing-fmu", ["map", *TINY_CLI, "-o", str(tmp_path / "a.json")], capsys)
    assert code == 0, err
    stored = store_path(P, settings_for(P, **TINY))
    assert f"and the map store's {stored}" in text and stored.read_bytes() == (tmp_path / "a.json").read_bytes()
    code, text, err = run_cli("bearing-fmu", ["map", *TINY_CLI, "-o", str(tmp_path / "b.json")], capsys)
    assert code == 0, err
    assert f"found in the map store, {stored}" in text and "copied to" in text
    assert (tmp_path / "b.json").read_bytes() == stored.read_bytes()
    code, text, err = run_cli("bearing-fmu", ["map", *TINY_CLI, "--rebuild", "-o", str(tmp_path / "c.json")], capsys)
    assert code == 0 and "solves in" in text, err
    assert json.loads((tmp_path / "c.json").read_text())["H"] == json.loads(stored.read_text())["H"]


def _scene_without_a_map(tmp_path) -> Path:
    text = (MODELS / "scenes" / "paper_22hz.toml").read_text()
    text = text.replace('map = "../maps/paper_bearing.json"', "")
    text = text.replace('rotor = "', f'rotor = "{MODELS / "scenes"}/')
    scene = tmp_path / "nomap.toml"
    scene.write_text(text)
    return scene


def test_a_scene_that_names_no_map_takes_the_stores(tmp_path, capsys):
    scene = _scene_without_a_map(tmp_path)
    run = ["run", str(scene), "--internal", "map", "--via", "direct", "--t-end", "0.002", "--out", str(tmp_path),
           "--no-plots", "--quiet"]
    path = store_path(P, settings_for(P))  # the default settings' map, as `bearing-fmu map` would store it
    path.unlink(missing_ok=True)
    code, _, err = run_cli("rotor-host", run, capsys)
    assert code == 2 and "the map store" in err and "has no map for L/D 0.6452" in err
    assert "build it once with `bearing-fmu map --bearing FILE`" in err
    # the finding, not the building, is tested here: the bundled map of the paper bearing stands in for a build
    path.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(MODELS / "maps" / "paper_bearing.json", path)
    try:
        assert stored_file("bearing-fmu-force-map", [P, replace(P, D=2 * P.D, L=2 * P.L)])[0] == path
        assert stored_file("bearing-fmu-force-map", [P, GROOVED])[0] is None  # one map serves one bore
        code, _, err = run_cli("rotor-host", run, capsys)
        assert code == 0, err
        assert f"[map] map not given: the map store's map for L/D 0.6452, full 360 deg circular bore: {path}" in err
    finally:
        path.unlink()


@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
@pytest.mark.native
def test_a_native_map_fmu_without_map_takes_the_stores(tmp_path, capsys):
    """`bearing-fmu build --native --internal map --bearing FILE` with no --map: the store's map of that
    bearing (as run and stability take it), said in one line; none there: the error says how to build it."""
    out = tmp_path / "m.fmu"
    cmd = ["build", "--native", "--internal", "map", "--bearing", str(MODELS / "bearing_paper.toml"), "-o", str(out),
           "--compiler", "cc"]
    path = store_path(P, settings_for(P))
    path.unlink(missing_ok=True)
    code, _, err = run_cli("bearing-fmu", cmd, capsys)
    assert code == 2 and "--native --internal map needs --map FILE: the map store" in err
    assert "build it once with `bearing-fmu map --bearing FILE`" in err and not out.exists()
    # the finding, not the building: the bundled map of the paper bearing stands in for a build
    path.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(MODELS / "maps" / "paper_bearing.json", path)
    try:
        code, text, err = run_cli("bearing-fmu", cmd, capsys)
        assert code == 0, err
        assert f"--map not given: the map store's map for L/D 0.6452, full 360 deg circular bore: {path}" in text
        import zipfile

        names = zipfile.ZipFile(out).namelist()
        assert any(n.startswith("binaries/linux64/") for n in names)
    finally:
        path.unlink()


# ------------------------------------------------------------------ --scheduler


def test_map_on_a_running_dask_scheduler(tmp_path, capsys):
    import logging

    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None,
                      silence_logs=logging.CRITICAL) as cluster:
        code, text, err = run_cli("bearing-fmu", ["map", *TINY_CLI, "--grid", "24x4", "--scheduler",
                                                  cluster.scheduler_address, "-o", str(tmp_path / "m.json")], capsys)
    assert code == 0, err
    assert f"on Dask ({cluster.scheduler_address})" in text
    got = json.loads((tmp_path / "m.json").read_text())
    ref = whole(P, settings_for(P, **{**TINY, "grid": (24, 4)}))
    assert np.array_equal(np.array(got["H"]), np.round(ref.H, 12))


def test_a_scheduler_address_where_none_answers_is_refused(tmp_path, capsys, monkeypatch):
    from bearing_fmu.internals.map import build

    monkeypatch.setattr(build, "CONNECT_TIMEOUT_S", 0.5)
    out = tmp_path / "m.json"
    code, _, err = run_cli("bearing-fmu", ["map", *TINY_CLI, "--scheduler", "tcp://127.0.0.1:1", "-o", str(out),
                                           "--rebuild"], capsys)
    assert code == 2
    assert err.startswith("bearing-fmu map: error: --scheduler tcp://127.0.0.1:1: no Dask scheduler answered there")
    assert not out.exists() and not Path(f"{out}.partial").exists()
    code, _, err = run_cli("bearing-fmu", ["map", *TINY_CLI, "--scheduler", "no address", "-o", str(out)], capsys)
    assert code == 2 and "expected local or a Dask scheduler address such as tcp://10.0.0.5:8786" in err


def test_map_help_shows_scheduler(capsys):
    code, text, _ = run_cli("bearing-fmu", ["map", "--help"], capsys)
    assert code == 0 and "--scheduler ADDRESS" in text
