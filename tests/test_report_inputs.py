"""What a report names as its inputs, and the command-line changes it names: the inputs line
(analyses/computed_for.py) tells a plain bore from a grooved one and names the oil, supply and data
file; `run --bearing` swaps a rotor's bearing files (all, or one by node) in a copy of the rotor
file; `run --supply-c` is checked as the scene key is (exit 2, the option named); the bundled
names resolve on the bearing side without importing the host; a thermal run's figure has its
temperature and power panels. No scene is integrated here."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from rotor_host.analyses.computed_for import scene_line, title_line
from rotor_host.bundled import find
from rotor_host.model.rotor import Rotor
from rotor_host.scenes.overrides import ALL_BEARINGS, SceneOverrides, swapped_rotor
from rotor_host.scenes.scene import SceneError, load_scene


def test_the_inputs_line_tells_the_bores_and_oils_apart():
    plain, grooved = find("rotor_paper", "rotor"), find("rotor_paper_2groove", "rotor")
    a = title_line(Rotor.from_toml(plain), plain, "map", {"map": str(find("paper_bearing", "map"))})
    b = title_line(Rotor.from_toml(grooved), grooved, "reynolds", None)
    assert a != b
    assert "bearing_paper.toml" in a and "full 360 deg circular bore" in a and "paper_bearing.json" in a
    assert "bearing_paper_2groove.toml" in b and "2 axial grooves" in b and "internal reynolds" in b
    assert "isoviscous mu 0.05 Pa s" in a  # the paper bearing has no [oil]: its own viscosity
    vg46 = load_scene(find("paper_vg46_44hz", "scene"))
    line = scene_line(vg46)
    assert "ISO VG 46" in line or "VG 46" in line


def test_bearing_swap_writes_a_rotor_with_the_new_bearing_files(tmp_path):
    rotor = find("rotor_paper", "rotor")
    grooved = find("bearing_paper_2groove", "bearing")
    every = Rotor.from_toml(swapped_rotor(rotor, {ALL_BEARINGS: grooved}, tmp_path))
    assert [p.geometry.describe() for p in every.bearings] == [Rotor.from_toml(find("rotor_paper_2groove", "rotor"))
                                                               .bearings[0].geometry.describe()] * 2
    one = Rotor.from_toml(swapped_rotor(rotor, {"9": grooved}, tmp_path))  # by 1-based node
    assert one.bearings[0].geometry.is_full_bore and not one.bearings[1].geometry.is_full_bore
    with pytest.raises(SceneError, match=r"no bearing named 'front'.*3, 9"):
        swapped_rotor(rotor, {"front": grooved}, tmp_path)


def test_overrides_swap_the_scene_rotor_and_set_the_supply(tmp_path):
    scene = load_scene(find("paper_vg46_44hz", "scene"))
    out = SceneOverrides(bearings={ALL_BEARINGS: find("bearing_paper_vg46", "bearing")}, supply_c=55.0,
                         folder=tmp_path).apply(scene)
    assert out.rotor_path.parent == tmp_path and out.supply_temperature_K == pytest.approx(328.15)
    assert "supply 55 C" in scene_line(out)


def test_supply_override_is_refused_by_the_option(tmp_path, capsys):
    from rotor_host.cli import main

    # the oil's law covers range_C of the bearing file; 500 C is far beyond any
    code = main(["run", "paper_vg46_44hz", "--supply-c", "500", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and "--supply-c 500" in err and "range" in err
    # an isoviscous bearing has no oil to heat: named with its bearing
    code = main(["run", "paper_22hz", "--via", "direct", "--supply-c", "40", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and "--supply-c 40" in err and "no [oil] table" in err


def test_bundled_names_resolve_on_the_bearing_side_without_the_host():
    code = ("import sys; from bearing_fmu.io import bundled as b; p = b.find('bearing_paper', 'bearing'); "
            "assert p is not None and p.name == 'bearing_paper.toml', p; assert 'paper_bearing' in b.names('map'); "
            "assert not [m for m in sys.modules if m.startswith('rotor_host')], 'the host was imported'")
    subprocess.run([sys.executable, "-c", code], check=True)
    from bearing_fmu.io.bundled import find as bearing_find

    assert bearing_find("paper_22hz", "scene") == find("paper_22hz", "scene")


@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
def test_a_thermal_runs_figure_has_temperature_and_power_panels(tmp_path):
    from rotor_host.analyses.plotting import pyplot
    from rotor_host.analyses.report import plot_runs

    t = np.linspace(0.0, 0.1, 21)
    arrays = {"t": t, "nodes": np.array([3, 6, 9]), "bearing_nodes": np.array([3, 9]), "disk_nodes": np.array([6]),
              "CR": np.array([90e-6, 90e-6]), "y": 1e-5 * np.sin(40 * t)[:, None] * np.ones(3),
              "z": 1e-5 * np.cos(40 * t)[:, None] * np.ones(3), "Fy": np.ones((21, 2)), "Fz": np.ones((21, 2)),
              "T_eff": 320.0 + np.zeros((21, 2)), "P_loss": 3.0 + np.zeros((21, 2))}
    seen = {}
    plt = pyplot()
    close = plt.close
    plt.close = lambda fig: seen.setdefault("titles", [a.get_title() for a in fig.axes]) and close(fig)
    try:
        plot_runs({"map": arrays}, tmp_path / "run.png", history=True, bearing=1)
    finally:
        plt.close = close
    titles = seen["titles"]
    assert len(titles) == 8 and "(g) effective film temperature" in titles and "(h) friction power of the film" in titles
    assert "(c) orbit of bearing 2 (node 9) of 2" in titles[2]


def test_the_inputs_line_names_each_bearing_when_they_differ(tmp_path):
    rotor = swapped_rotor(find("rotor_paper", "rotor"), {"9": find("bearing_paper_2groove", "bearing")}, tmp_path)
    line = title_line(Rotor.from_toml(rotor), rotor, "reynolds", None)
    assert "at node 3 bearing_paper.toml (full 360 deg circular bore)" in line
    assert "at node 9 bearing_paper_2groove.toml (2 axial grooves" in line


def test_a_comparison_names_its_rotor_bearings_and_oil():
    """`rotor-host compare` and the main job: the scene's rotor, bearing and oil, each row its internal."""
    from rotor_host.analyses.compare import compare_inputs
    from rotor_host.bundled import find
    from rotor_host.scenes.scene import load_scene

    line = compare_inputs(load_scene(find("scenes/paper_22hz.toml")))
    assert line.startswith("rotor paper rotor (Table 1) (rotor_paper.toml); bearing bearing_paper.toml (full 360 deg")
    assert line.endswith("; internal: each row's")
