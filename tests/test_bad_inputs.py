"""Bad input, refused in one line that names it: files (scene, rotor, bearing) and command lines.

Each case is (input, the words the message must hold). The words are the key with its table
path, or the option, taken from the input itself (the key or option the case breaks), plus
the expected value in words where the schema or the option's type states it. A representative
case per class of fault exits 2 without a traceback from ``main(argv)``, and one per way a
command exits 2 (argparse, run_command) runs the real command in a subprocess; the rest run
in-process through ``load_scene``, ``Rotor.from_toml``, ``BearingParams.from_toml`` and the real
argument parsers (``main(argv)``), which is fast.
"""

import argparse
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import pytest

from bearing_fmu.physics.params import BearingParams
from rotor_host.model.rotor import Rotor
from rotor_host.model.parts import RotorFileError
from rotor_host.scenes.scene import SceneError, load_scene
from conftest import run_cli

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "rotor_host" / "bundled"
SCENE = MODELS / "scenes" / "paper_22hz.toml"
ROTOR = MODELS / "rotor_paper.toml"  # 10 elements: nodes 1..11, bearings at nodes 3 and 9

# the smallest valid scene (rotor given as an absolute path, so the file may sit anywhere)
HEAD = f'rotor = "{ROTOR.as_posix()}"\ninternal = "reynolds"\nspeed_hz = 22\n'
TIME = "[time]\nt_end_s = 2e-4\ndt_s = 1e-4\n"


def _scene(tmp_path: Path, body: str, name: str = "s.toml") -> Path:
    p = tmp_path / name
    p.write_text(textwrap.dedent(body))
    return p


def _rotor(tmp_path: Path, text: str) -> Path:
    (tmp_path / "bearing_paper.toml").write_text((MODELS / "bearing_paper.toml").read_text())
    p = tmp_path / "r.toml"
    p.write_text(text)
    return p


def _not_an_fmu(tmp_path: Path) -> None:
    """plain.fmu: text, not a zip; empty.fmu: a zip without modelDescription.xml."""
    (tmp_path / "plain.fmu").write_text("not an archive\n")
    with zipfile.ZipFile(tmp_path / "empty.fmu", "w") as z:
        z.writestr("resources/x.txt", "x")


# ----------------------------------------------------------------------------- scene files

SCENE_CASES = [
    # wrong type or shape where a table, array of tables or array is expected (from the issue)
    (HEAD + "time = 0.002\n", ["time = 0.002", "must be a table", "[time]"]),
    (HEAD + "[time]\nt_end_s = 2e-4\ndt_s = 1e-4\n[record]\nnodes = 3\n", ["[record] nodes = 3", "array"]),
    (HEAD + "unbalance = 5\n" + TIME, ["unbalance = 5", "array of tables"]),
    (HEAD + TIME + "[unbalance]\nnode = 3\nmass_kg = 0.01\nradius_mm = 3\n",
     ["unbalance = {node = 3", "write [[unbalance]]"]),
    (HEAD + "initial = \"centred\"\n" + TIME, ["initial = 'centred'", "must be a table"]),
    (HEAD + "reynolds = 4\n" + TIME, ["reynolds = 4", "must be a table"]),
    # file names that are not text
    ('rotor = 5\ninternal = "reynolds"\nspeed_hz = 22\n' + TIME, ["rotor = 5", "file name"]),
    (HEAD + "fmu = true\n" + TIME, ["fmu = true", "file name"]),
    # bools are not numbers; inf and nan are refused; integers where integers belong
    (HEAD.replace("speed_hz = 22", "speed_hz = true") + TIME, ["speed_hz = true", "finite number > 0"]),
    (HEAD + "[time]\nt_end_s = inf\ndt_s = 1e-4\n", ["[time] t_end_s = inf", "finite number > 0"]),
    (HEAD + TIME + "[[unbalance]]\nnode = 3\nmass_kg = nan\nradius_mm = 3\n", ["[[unbalance]] 1 mass_kg = nan"]),
    (HEAD + TIME + "[[static_loads]]\nnode = 3\n[[static_loads]]\nnode = 9\nFz_N = -inf\n",
     ["[[static_loads]] 2 Fz_N = -inf", "finite"]),
    (HEAD + TIME + "[record]\nevery = 2.0\n", ["[record] every = 2.0", "integer"]),
    (HEAD + TIME + "[[unbalance]]\nnode = 3.5\nmass_kg = 0.01\nradius_mm = 3\n", ["[[unbalance]] 1 node = 3.5"]),
    # 0 and negative values are values, refused by their range
    (HEAD + "[time]\nt_end_s = 2e-4\ndt_s = 0\n", ["[time] dt_s = 0", "> 0"]),
    (HEAD + "[time]\nt_end_s = 2e-4\ndt_s = 1e-4\nhht_alpha = 0.1\n", ["[time] hht_alpha = 0.1", "[-1/3, 0]"]),
    # choices
    (HEAD + 'via = "tcp"\n' + TIME, ["via = 'tcp'", "fmu, direct"]),
    (HEAD + TIME + '[initial]\nstate = "rest"\n', ["[initial] state = 'rest'", "static_equilibrium, centred"]),
    # node numbers against the rotor's 11 nodes
    (HEAD + TIME + "[record]\nnodes = [3, 12]\n", ["[record] nodes entry 2 = 12", "1..11"]),
    (HEAD + TIME + "[[static_loads]]\nnode = 0\n", ["[[static_loads]] 1 node = 0", "1..11"]),
    # an entry of an array of tables that is not a table
    (HEAD + "unbalance = [5]\n" + TIME, ["unbalance", "entry 1 = 5", "must be a table"]),
    # keys: unknown, missing
    (HEAD + TIME + "[[unbalance]]\nnode = 3\nmass_g = 1\nradius_mm = 3\n",
     ["[[unbalance]] 1", "unknown key(s) mass_g (did you mean mass_kg?)", "missing key(s) mass_kg"]),
    (HEAD, ["missing key(s) time"]),
    # tables: unknown ones named as tables, with the allowed ones (tables in brackets)
    (HEAD + TIME + "[geometry]\ngrooves = 2\n", ["unknown table(s) [geometry]", "allowed: rotor, internal",
                                                "[speed_profile], [time]", "[[unbalance]]", "[reynolds]"]),
    (HEAD + TIME + "[reynold]\nn_theta = 64\n", ["unknown table(s) [reynold] (did you mean [reynolds]?)"]),
    # a TOML syntax error: the file and the line
    (HEAD + TIME + "x = = 3\n", ["not valid TOML", "line 7"]),
    # overrides of the time step go through the same checks (see test_overrides_are_checked)
]


@pytest.mark.parametrize("body, words", SCENE_CASES, ids=[f"scene{i}" for i in range(len(SCENE_CASES))])
def test_bad_scene_file_names_the_key(tmp_path, body, words):
    path = _scene(tmp_path, body)
    with pytest.raises(SceneError) as exc:
        load_scene(path)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith(str(path))  # one line, the file first
    for w in words:
        assert w in msg, (w, msg)


def test_paths_in_a_scene_that_are_not_what_they_say(tmp_path):
    _not_an_fmu(tmp_path)
    (tmp_path / "folder").mkdir()
    cases = [  # (what the scene names, the words)
        ('fmu = "plain.fmu"', ["fmu = 'plain.fmu'", "is not an FMU", "not a zip"]),
        ('fmu = "empty.fmu"', ["fmu = 'empty.fmu'", "is not an FMU", "modelDescription.xml"]),
        ('fmu = "folder"', ["fmu = 'folder'", "is a directory"]),
        ('fmu = "nope.fmu"', ["fmu = 'nope.fmu'", "not found"]),
    ]
    for line, words in cases:
        with pytest.raises(SceneError) as exc:
            load_scene(_scene(tmp_path, HEAD + line + "\n" + TIME))
        assert all(w in str(exc.value) for w in words), (words, str(exc.value))
    with pytest.raises(SceneError, match="rotor = 'folder'.*is a directory"):
        load_scene(_scene(tmp_path, 'rotor = "folder"\ninternal = "reynolds"\nspeed_hz = 22\n' + TIME))
    with pytest.raises(SceneError, match=r"scene file .*folder is a directory, not a file"):
        load_scene(tmp_path / "folder")
    with pytest.raises(SceneError, match=r"scene file .*empty\.fmu is not a text"):
        load_scene(tmp_path / "empty.fmu")  # a binary file given as the scene


def test_a_bad_rotor_is_named_from_the_scene(tmp_path):
    # the scene reads its rotor whole: a rotor without bearings (an IndexError before) and a
    # rotor whose elements are not tables (a node range 1..5 from len('none') + 1 before)
    material = "[material]\nE_GPa = 200\ndensity_kg_m3 = 7850\npoisson = 0.3\n"
    (tmp_path / "free.toml").write_text("elements = [{od_mm = 10, length_mm = 100}]\n" + material)
    (tmp_path / "none.toml").write_text('elements = "none"\n' + material)
    for rotor, words in (("free.toml", ["rotor = 'free.toml'", "no bearings", "[[bearings]]"]),
                         ("none.toml", ["rotor = 'none.toml'", "elements = 'none'", "array of tables"])):
        body = f'rotor = "{rotor}"\ninternal = "reynolds"\nspeed_hz = 22\n' + TIME
        with pytest.raises(SceneError) as exc:
            load_scene(_scene(tmp_path, body))
        assert all(w in str(exc.value) for w in words), (words, str(exc.value))


def test_overrides_are_checked_and_zero_is_a_value():
    # --dt 0 used to mean "the scene's dt" (a truth test); now 0 reaches the check and is refused
    from rotor_host.scenes.overrides import SceneOverrides, load_with_overrides

    with pytest.raises(SceneError, match=r"dt_s = 0\.0 must be a finite number > 0"):
        load_with_overrides(SCENE, SceneOverrides(dt_s=0.0))
    base = load_scene(SCENE)  # 0.5 s at dt = 1e-4 s (rotor_host/bundled/scenes/paper_22hz.toml)
    with pytest.raises(SceneError, match=r"t_end_s = 0\.00015 is not a whole number of steps dt_s = 0\.0001"):
        base.with_internal("reynolds", t_end_s=1.5e-4)
    assert base.with_internal("reynolds", t_end_s=2e-4).t_end_s == 2e-4


# ----------------------------------------------------------------------------- rotor and bearing files

ROTOR_TEXT = ROTOR.read_text()


@pytest.mark.parametrize("old, new, words", [
    ("[material]", "[[material]]", ["material = [{E_GPa = 200.0", "must be a table"]),
    ("od_mm = 12.0, length_mm = 40.0", "od_mm = true, length_mm = 40.0", ["[[elements]] 1 od_mm = true", "number"]),
    ("length_mm = 266.5 }", "length_mm = nan }", ["[[elements]] 4 length_mm = nan", "finite"]),
    ("nodes = [1, 2]", "nodes = 1", ["[[elements]] 1 nodes = 1", "array of 2 values"]),
    ("node = 6\n", 'node = "6"\n', ["[[disks]] 1 node = '6'", "integer"]),
    ('bearing = "bearing_paper.toml"', "bearing = 7", ["[[bearings]] 1 bearing = 7", "file name"]),
    ("[[disks]]", "[disks]", ["disks = {node = 6", "write [[disks]]"]),
    ("[material]", "[geometry]\ngrooves = 2\n\n[material]",
     ["unknown table(s) [geometry]", "allowed: [[elements]], [material], name"]),
    ("[[disks]]", "[[seals]]\nnode = 4\n\n[[disks]]", ["unknown table(s) [[seals]]", "[[disks]], [[bearings]]"]),
])
def test_bad_rotor_file_names_the_key(tmp_path, old, new, words):
    assert old in ROTOR_TEXT
    path = _rotor(tmp_path, ROTOR_TEXT.replace(old, new, 1))
    with pytest.raises(RotorFileError) as exc:
        Rotor.from_toml(path)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith(str(path))
    for w in words:
        assert w in msg, (w, msg)


@pytest.mark.parametrize("text, words", [
    ("[bearing]\nD_mm = true\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n", ["[bearing] D_mm = true", "number"]),
    ("[bearing]\nD_mm = 31\nL_mm = inf\nCR_um = 90\nmu_Pa_s = 0.05\n", ["[bearing] L_mm = inf"]),
    ("bearing = 3\n", ["bearing = 3", "expected a table"]),
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = -90\nmu_Pa_s = 0.05\n", ["[bearing]", "CR"]),  # range: BearingParams
    ("[bearing\n", ["not valid TOML", "line 1"]),
    # a table beside [bearing], [geometry] and [oil] would be ignored: the bearing computed without it
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[cooling]\nflow = 0.1\n",
     ["unknown table(s) [cooling]", "allowed: [bearing], [geometry], [oil]"]),
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[[oil]]\nmu_Pa_s = 0.1\n",
     ["[oil]: expected a table"]),
    ("D_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[cooling]\nflow = 0.1\n",
     ["unknown table(s) [cooling]", "allowed: D_mm, L_mm"]),
    # [oil]: one law, its keys by type and range, mu_Pa_s not beside it
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\n[oil]\nmu_Pa_s = 0.1\n",
     ["[oil]", "unknown key(s) mu_Pa_s"]),
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\n[oil]\ngrade = \"ISO VG 32\"\nrise_factor = 2\n",
     ["[oil] rise_factor = 2", "<= 1"]),
    # [geometry]: its keys by type and range, then together, each naming the file and key
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[geometry]\ngrooves = 2\n",
     ["[geometry]", "unknown key(s) grooves (did you mean grooves_deg?)"]),
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[geometry]\npreload = 1.2\nlobes = 2\n",
     ["[geometry] preload = 1.2", ">= 0 and < 1"]),
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[geometry]\nlobes = 2.0\n",
     ["[geometry] lobes = 2.0", "integer"]),
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[geometry]\narc_deg = [90]\n",
     ["[geometry] arc_deg = [90]", "array of 2 values"]),
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[geometry]\ngrooves_deg = [90, 100]\n",
     ["[geometry] grooves_deg: the grooves at 90 deg and 100 deg overlap", "groove_width_deg = 20"]),
    ("[bearing]\nD_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[geometry]\npreload = 0.3\n",
     ["[geometry] preload = 0.3 needs lobes >= 2"]),
    ("D_mm = 31\nL_mm = 20\nCR_um = 90\nmu_Pa_s = 0.05\n[geometry]\narc_deg = [270, 90]\n",
     ["[geometry] arc_deg = [270, 90]: end - start must be in (0, 360)"]),
])
def test_bad_bearing_file_names_the_key(tmp_path, text, words):
    p = tmp_path / "b.toml"
    p.write_text(text)
    with pytest.raises(ValueError) as exc:  # BearingFileError: a ValueError (and a KeyError)
        BearingParams.from_toml(p)
    msg = str(exc.value)
    assert "\n" not in msg and str(p) in msg and not msg.startswith("'")
    for w in words:
        assert w in msg, (w, msg)


# ----------------------------------------------------------------------------- command lines, in-process

def _cli(prog: str, argv: list[str], capsys) -> tuple[int, str]:
    """(exit status, stderr) of ``prog``'s main(argv) in this process."""
    code, _out, err = run_cli(prog, argv, capsys)
    return code, err


S = str(SCENE)
CLI_CASES = [  # (program, arguments, words): the option and what it expects
    ("rotor-host", ["run", S, "--dt", "0"], ["argument --dt", "> 0 s", "'0'"]),
    ("rotor-host", ["run", S, "--t-end", "0"], ["argument --t-end", "> 0 s", "'0'"]),
    ("rotor-host", ["run", S, "--t-end", "inf"], ["argument --t-end", "'inf'"]),
    ("rotor-host", ["run", S, "--dt", "1e-4s"], ["argument --dt", "'1e-4s'"]),
    ("rotor-host", ["run", S, "--via", "tcp"], ["argument --via", "fmu", "direct"]),
    ("rotor-host", ["run", S, "--surrogate", "nope.json"], ["argument --surrogate", "not found"]),
    ("rotor-host", ["run", str(MODELS)], ["argument scene", "a directory"]),
    ("rotor-host", ["run", S, "--t-end", "1.5e-4"], ["t_end_s = 0.00015", "whole number of steps"]),
    ("rotor-host", ["compare", S, "--grids", "axb"], ["argument --grids", "NxM", "'axb'"]),
    ("rotor-host", ["compare", S, "--grids", "64x7"], ["argument --grids", "even", "'64x7'"]),
    ("rotor-host", ["compare", S, "--ref-grid"], ["argument --ref-grid", "expected one argument"]),
    ("rotor-host", ["compare", S, "--ref-grid", "4x4"], ["argument --ref-grid", "8..100000", "'4x4'"]),
    ("rotor-host", ["compare", S, "--orders", "0"], ["argument --orders", "integer >= 1", "'0'"]),
    ("rotor-host", ["compare", S, "--orders", "-3"], ["argument --orders", "'-3'"]),
    ("rotor-host", ["paper", "--t-end", "nan"], ["argument --t-end", "'nan'"]),
    ("rotor-host", ["paper", "--scenes", "nowhere"], ["argument --scenes", "folder", "not found"]),
    ("rotor-host", ["fit", "--scene", S, "-o", "x.json", "--lambda", "foo"], ["argument --lambda", "'cv'", "'foo'"]),
    ("rotor-host", ["fit", "--scene", S, "-o", "x.json", "--k-folds", "1"], ["argument --k-folds", ">= 2", "'1'"]),
    ("rotor-host", ["fit", "--scene", S, "-o", "x.json", "--designed-ecc-max", "1"],
     ["argument --designed-ecc-max", "(0, 1)"]),
    ("rotor-host", ["fit", "--scene", "nope.toml", "-o", "x.json"], ["argument --scene", "not found"]),
    ("rotor-host", ["dt-study", S, "--halvings", "0"], ["argument --halvings", ">= 1"]),
    ("rotor-host", ["dt-study", S, "--tol", "-1"], ["argument --tol", "% CR"]),
    ("rotor-host", ["dt-study", S, "--dt", "0"], ["argument --dt", "> 0 s"]),
    ("rotor-host", ["limit-cycle", S, "--revs", "0"], ["argument --revs", ">= 1", "'0'"]),
    ("rotor-host", ["limit-cycle", S, "--hold", "-1"], ["argument --hold", ">= 0 s"]),
    ("rotor-host", ["limit-cycle", S, "--speed-hz", "0"], ["argument --speed-hz", "> 0 Hz"]),
    ("bearing-fmu", ["demo", "--speed-hz", "0"], ["argument --speed-hz", "> 0 Hz"]),
    ("bearing-fmu", ["demo", "--load", "nan"], ["argument --load", "'nan'"]),
    ("bearing-fmu", ["build", "-o", str(MODELS)], ["argument -o/--output", "a directory"]),
    ("bearing-fmu", ["build", "-o", "x.fmu", "--surrogate", "nope.json"], ["argument --surrogate", "not found"]),
    ("bearing-fmu", ["fit", "-o", "x.json", "--grid", "3", "4"], ["--grid 3 4", "n_theta", "8..100000"]),
    ("bearing-fmu", ["fit", "-o", "x.json", "--n-train", "0"], ["argument --n-train", ">= 1"]),
    ("bearing-fmu", ["fit", "-o", "x.json", "--speed-hz", "0"], ["argument --speed-hz", "nonzero"]),
    ("bearing-fmu", ["fit", "-o", "x.json", "--ecc-max", "1.5"], ["argument --ecc-max", "(0, 1)"]),
]


@pytest.mark.parametrize("prog, argv, words", CLI_CASES, ids=[" ".join(a[:1] + a[2:]) for _, a, _ in CLI_CASES])
def test_bad_option_is_refused_by_name(prog, argv, words, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # relative outputs (x.json) land here, and nothing is written anyway
    code, err = _cli(prog, argv, capsys)
    assert code == 2, err
    last = err.strip().splitlines()[-1]  # argparse prints the usage first, the error last
    assert last.startswith(f"{prog} {argv[0]}: error: ")
    for w in words:
        assert w in last, (w, last)
    assert not list(tmp_path.iterdir())  # refused before any work


def test_output_paths_in_the_way(tmp_path, capsys):
    blocker = tmp_path / "afile"
    blocker.write_text("x")
    for prog, argv, words in (
        ("rotor-host", ["run", S, "--out", str(blocker)], ["argument --out", "it is a file"]),
        ("rotor-host", ["dt-study", S, "--out", str(blocker / "sub")], ["argument --out", "is a file, not a folder"]),
        ("bearing-fmu", ["build", "-o", str(blocker / "b.fmu")], ["argument -o/--output", "is a file, not a folder"]),
        ("rotor-host", ["fit", "--scene", S, "-o", str(blocker / "s.json")], ["argument -o/--output", "afile"]),
    ):
        code, err = _cli(prog, argv, capsys)
        assert code == 2 and all(w in err for w in words), (words, err)


def test_limit_cycle_names_a_bad_saved_run(tmp_path, capsys):
    import numpy as np

    bad = tmp_path / "run.npz"
    np.savez(bad, t=np.arange(3.0))  # no eccentricity array
    code, err = _cli("rotor-host", ["limit-cycle", str(bad), "--speed-hz", "22", "--out", str(tmp_path)], capsys)
    assert code == 2 and "eccentricity" in err and str(bad) in err
    code, err = _cli("rotor-host", ["limit-cycle", str(bad), "--out", str(tmp_path)], capsys)
    assert code == 2 and "--speed-hz" in err


def _parsers():
    """Every (program subcommand, parser) of both command lines, taken from their main()."""
    from bearing_fmu.cli import main as bearing_fmu
    from rotor_host.cli import main as rotor_host

    class Got(Exception):
        pass

    def grab(self, *args, **kw):
        raise Got(self)

    out = {}
    original = argparse.ArgumentParser.parse_args
    argparse.ArgumentParser.parse_args = grab
    try:
        for prog, main in (("rotor-host", rotor_host), ("bearing-fmu", bearing_fmu)):
            try:
                main([])
            except Got as got:
                sub = next(a for a in got.args[0]._actions if isinstance(a, argparse._SubParsersAction))
                out.update({f"{prog} {name}": p for name, p in sub.choices.items()})
    finally:
        argparse.ArgumentParser.parse_args = original
    return out


FREE_TEXT = {"--note"}  # options whose value is any text


def test_every_option_that_takes_a_value_has_a_type_or_choices():
    parsers = _parsers()
    assert len(parsers) == 18  # run, compare, paper, fit, dt-study, waterfall, limit-cycle, stability, sweep, response,
    # ucs, level1, api-report, linear-vs-runup; demo, fit, build, map
    untyped = []
    for name, p in parsers.items():
        for a in p._actions:
            takes_value = a.nargs != 0 and not isinstance(a, argparse._HelpAction)
            hidden = a.help == argparse.SUPPRESS  # bearing-fmu fit's pointers to rotor-host fit
            if takes_value and not hidden and a.type is None and a.choices is None:
                flag = a.option_strings[-1] if a.option_strings else a.dest
                if flag not in FREE_TEXT:
                    untyped.append(f"{name} {flag}")
    assert not untyped, f"options without a type: {untyped}"


# ----------------------------------------------------------------------------- the real commands

SUBPROCESS_CASES = [  # one per class of fault: (program module, arguments or a scene body, words)
    ("rotor_host.cli", ["run", S, "--dt", "0"], ["--dt", "'0'"]),  # a number out of range
    ("rotor_host.cli", ["compare", S, "--grids", "axb"], ["--grids", "'axb'"]),  # a malformed value
    ("rotor_host.cli", ["fit", "--scene", S, "-o", "x.json", "--k-folds", "1"], ["--k-folds"]),  # a recipe option
    ("rotor_host.cli", ["run", str(MODELS)], ["scene", "a directory"]),  # a folder for a file
    ("rotor_host.cli", "time = 0.002\n", ["time = 0.002", "table"]),  # a file: wrong shape
    ("rotor_host.cli", TIME + "[unbalance]\nnode = 3\nmass_kg = 0.01\nradius_mm = 3\n", ["[[unbalance]]"]),
    ("rotor_host.cli", 'fmu = "plain.fmu"\n' + TIME, ["fmu = 'plain.fmu'", "not an FMU"]),  # not what it says
    ("rotor_host.cli", TIME + "x = = 1\n", ["not valid TOML", "line"]),  # syntax
    ("bearing_fmu.cli", ["demo", "--speed-hz", "-1"], ["--speed-hz", "'-1'"]),
    ("bearing_fmu.cli", ["build", "-o", str(MODELS)], ["-o/--output", "a directory"]),
]
# The cases that run the real command (``python -m``, its exit status, stderr without a
# traceback): one per way a command exits 2 -- argparse refusing an option (rotor-host,
# bearing-fmu) and run_command refusing a file (rotor-host; bearing-fmu's: tests/test_guard.py,
# a damaged surrogate). Every case, these too, also runs in-process through main(argv) below:
# the same exit status and message at a fraction of a Python start-up each.
REAL = (0, 4, 8)
_IDS = [f"{m.split('.')[0]}-{i}" for i, (m, _, _) in enumerate(SUBPROCESS_CASES)]


def _argv(tmp_path, given):
    if isinstance(given, str):  # a scene body: run it
        _not_an_fmu(tmp_path)
        return ["run", str(_scene(tmp_path, HEAD + given)), "--out", str(tmp_path / "out")]
    return given


@pytest.mark.parametrize("module, given, words", [SUBPROCESS_CASES[i] for i in REAL], ids=[_IDS[i] for i in REAL])
def test_real_command_exits_2_without_traceback(tmp_path, module, given, words):
    # cwd = the repository, so this worktree's code runs (not an installed copy)
    r = subprocess.run([sys.executable, "-m", module, *_argv(tmp_path, given)], cwd=ROOT, capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    assert "Traceback" not in r.stderr
    for w in words:
        assert w in r.stderr, (w, r.stderr)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("module, given, words", SUBPROCESS_CASES, ids=_IDS)
def test_every_class_of_fault_exits_2_from_main(tmp_path, module, given, words, capsys, monkeypatch):
    # the same checks through main(argv) in this process (an exception escaping main fails the test)
    monkeypatch.chdir(tmp_path)  # relative outputs (x.json) would land here; nothing is written
    code, err = _cli({"rotor_host.cli": "rotor-host", "bearing_fmu.cli": "bearing-fmu"}[module],
                     _argv(tmp_path, given), capsys)
    assert code == 2, err
    assert "Traceback" not in err
    for w in words:
        assert w in err, (w, err)
    assert not (tmp_path / "out").exists()


def test_good_options_still_parse():
    # the forms the README and the study records use (docs/studies/*: --ref-grid '' --grids --orders 3)
    compare = _parsers()["rotor-host compare"]
    a = compare.parse_args([S, "--ref-grid", "", "--grids", "--orders", "3"])
    assert a.ref_grid is None and a.grids == [] and a.orders == [3]
    a = compare.parse_args([S])  # defaults: reference 256x32, one coarser grid 64x8
    assert a.ref_grid == (256, 32) and a.grids == [(64, 8)] and a.orders == [1, 3, 5, 7]
    run = _parsers()["rotor-host run"].parse_args([S, "--dt", "2e-4", "--t-end", "1"])
    assert (run.dt, run.t_end) == (2e-4, 1.0)
