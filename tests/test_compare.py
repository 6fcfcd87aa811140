"""`rotor-host compare`: its error measures against hand computations, and a short real run."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from rotor_host.analyses.compare import Variant, compare, envelope_error, late_max_eccentricity
from rotor_host.analyses.report import errors_against
from rotor_host.scenes.scene import load_scene

SCENES = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "scenes"
CR = 90e-6


def _whirl(t, ecc, phase):
    # one bearing (node 3) on a circular forward whirl at 10 Hz, eccentricity ecc
    y = ecc * CR * np.cos(2 * np.pi * 10 * t + phase)
    z = ecc * CR * np.sin(2 * np.pi * 10 * t + phase)
    return {"t": t, "nodes": np.array([3]), "bearing_nodes": np.array([3]), "CR": np.array([CR]),
            "y": y[:, None], "z": z[:, None], "Fy": y[:, None], "Fz": z[:, None],
            "eccentricity": np.full((len(t), 1), ecc)}


def test_envelope_error_ignores_whirl_phase_and_sees_size():
    t = np.arange(0, 1.0, 1e-4)
    ref = _whirl(t, 0.5, 0.0)
    # the same whirl half a turn later: pointwise the journals are 2 x 0.5 CR apart ...
    shifted = _whirl(t, 0.5, np.pi)
    assert errors_against(ref, shifted)["orbit_max_pct_cr"] == pytest.approx(100.0)
    # ... but the orbit has the same size: envelope error 0
    assert envelope_error(ref, shifted, speed_hz=20.0) == pytest.approx(0.0, abs=1e-12)
    # a whirl 2 % CR larger: envelope error 2 % CR in every window
    assert envelope_error(ref, _whirl(t, 0.52, 0.0), speed_hz=20.0) == pytest.approx(2.0)
    assert late_max_eccentricity(_whirl(t, 0.52, 0.0)) == pytest.approx(0.52)


@pytest.mark.slow
def test_short_compare_run(tmp_path):
    # 10 ms of the 22 Hz scene (100 steps), called directly: Reynolds default grid as reference,
    # a coarse grid, the shipped order-5 surrogate and the linear model. Expected: the reference
    # row is 0 against itself with speed-up 1; each variant is a different model, so its error is
    # > 0, and small (< 5 % CR: measured 0.004-0.016 % CR at 10 ms, 0.02-0.05 % at 20 ms); no
    # envelope error (it needs 2 revolutions, 91 ms)
    base = load_scene(SCENES / "paper_22hz.toml").with_internal("reynolds", via="direct", t_end_s=0.01)
    ref = Variant("Reynolds default grid", "reynolds")
    variants = [Variant("Reynolds 32x8", "reynolds", {"reynolds": {"n_theta": 32, "n_x": 8}}),
                Variant("Taylor order 5", "taylor", order=5),
                Variant("linear", "linear")]
    rows = compare(base, ref, variants, tmp_path, default_label=ref.label, log=lambda *_: None)
    by = {r["label"]: r for r in rows}
    assert all(r["status"] == "ok" for r in rows)
    assert by[ref.label]["orbit_rms_pct_cr"] == 0.0 and by[ref.label]["speedup_vs_ref"] == pytest.approx(1.0)
    # every variant differs from the reference, by little at the start of the run
    for label in ("Reynolds 32x8", "Taylor order 5", "linear"):
        assert 0.0 < by[label]["orbit_rms_pct_cr"] < 5.0
        assert math.isfinite(by[label]["force_nrmse_pct"]) and by[label]["envelope_rms_pct_cr"] is None
        assert by[label]["speedup_vs_ref"] > 0
    stem = "compare_paper_22hz"
    data = json.loads((tmp_path / f"{stem}.json").read_text())
    assert [r["label"] for r in data["rows"]] == [r["label"] for r in rows]
    assert "| Taylor order 5 |" in (tmp_path / f"{stem}.md").read_text()
    assert (tmp_path / f"{stem}_error_vs_time.png").stat().st_size > 0


def test_compare_takes_any_registered_internal_that_can_be_a_variant(tmp_path):
    # `rotor-host compare --internals NAME...`: one variant per internal, the scene's options for
    # it; an internal whose capabilities say it cannot be a compare variant is refused by name
    from bearing_fmu.internals import registry
    from rotor_host.analyses.compare import reference_and_variants
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml")
    ref, variants = reference_and_variants(scene, tmp_path, ref_grid=None, internals=["map", "linear"])
    assert ref.internal == "reynolds" and [v.internal for v in variants] == ["map", "linear"]
    spec = registry.InternalSpec("no_compare", lambda p, o, c: None, "test only",
                                 can=registry.Capabilities(compare=False))
    registry.register(spec)
    try:
        with pytest.raises(ValueError, match="--internals no_compare: this internal cannot be a compare variant"):
            reference_and_variants(scene, tmp_path, internals=["no_compare"])
    finally:
        registry.unregister("no_compare")


def test_main_job_runs_every_variant_through_its_native_fmu_and_the_map_also_through_the_python_fmu():
    # issue 37: the main job's rows through the fastest FMU route (native, compiled loop), the
    # Python FMU kept as a row of its own so the table shows both routes
    from bearing_fmu.surrogates.surrogate import load_surrogate
    from rotor_host.analyses.compare import PAPER_REFERENCE, PYTHON_FMU, paper_variants, route
    from rotor_host.scenes.scene import required_file

    for name in ("paper_22hz.toml", "paper_44hz.toml"):
        scene = load_scene(SCENES / name)
        ref, variants = paper_variants(scene, load_surrogate(required_file(scene, "taylor", "surrogate")))
        assert ref.label == PAPER_REFERENCE and route(ref.scene(scene)) == "the native FMU"
        assert [v.internal for v in variants] == ["map", "map", "taylor", "linear"]
        python = [v for v in variants if route(v.scene(scene)) == "the Python FMU"]
        assert len(python) == 1 and python[0].label.endswith(PYTHON_FMU)
        assert python[0].options == variants[0].options  # the same map, the other route
        assert all(v.scene(scene).fmu_kind == "native" for v in variants if v is not python[0])
