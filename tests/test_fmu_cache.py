"""The FMUs that scenes need are built once per content and shared by every command and output
folder (bearing_fmu.io.cache): a second run into another folder finds the first run's build, and a
changed source gives a new name (never an old build reused wrongly)."""

import shutil

import pytest

from bearing_fmu.io import cache
from rotor_host.scenes import bearings as scene_bearings
from rotor_host.scenes.scene import load_scene


def test_the_cache_folder_follows_its_variable_and_the_platform_rule(tmp_path, monkeypatch):
    monkeypatch.setenv(cache.ENV, str(tmp_path / "here"))
    assert cache.build_cache() == tmp_path / "here"
    assert cache.cache_dir().is_dir()
    monkeypatch.delenv(cache.ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setattr(cache.sys, "platform", "linux")
    assert cache.build_cache() == tmp_path / "xdg" / "bearing_fmu" / "fmus"


def test_an_unwritable_cache_is_named_with_the_variable_to_set(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(cache.ENV, str(blocker / "fmus"))
    with pytest.raises(OSError, match=f"{blocker / 'fmus'}.*set {cache.ENV}"):
        cache.cache_dir()


def test_the_source_digest_changes_with_any_source_and_only_with_sources(tmp_path, monkeypatch):
    copy = tmp_path / "bearing_fmu"
    shutil.copytree(cache.PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(cache, "PACKAGE", copy)
    digest = cache.source_digest.__wrapped__
    before = digest()
    (copy / "notes.txt").write_text("not a source")  # not read by a build
    assert digest() == before
    c_file = next(copy.rglob("*.c"))
    c_file.write_text(c_file.read_text() + "\n/* one comment */\n")
    assert digest() != before


def test_two_output_folders_share_one_build(tmp_path, monkeypatch, paper_scene, code_cache):
    """The Python FMU of a scene, asked for by two runs with different output folders: one build."""
    monkeypatch.setenv(cache.ENV, str(tmp_path / "fmus"))
    builds = []
    from bearing_fmu.fmu import build as fmu_build

    original = fmu_build.build_fmu

    def counting(*args, **kwargs):
        builds.append(args[0])
        return original(*args, **kwargs)

    monkeypatch.setattr(fmu_build, "build_fmu", counting)
    scene = load_scene(paper_scene(via="fmu"))
    first = scene_bearings.scene_fmu(scene, None)
    second = scene_bearings.scene_fmu(scene, None)
    assert first == second and first.parent == tmp_path / "fmus" and first.is_file()
    assert len(builds) == 1
