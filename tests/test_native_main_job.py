"""The main job's rows (`rotor-host paper`: each variant through its native FMU, iterated by the
integrator's compiled loop) cost about what the same internal called in-process costs
(`rotor-host run <scene> --via direct`), per step.

The measure is the marginal CPU time per step (this thread's: a busy machine's other processes do
not enter, as wall time let them: 1.30x for Reynolds at a load of 9): a long run's less a short
one's, over the steps between them (what a run's own fixed costs do not enter),
each the minimum of a few repeats, the two routes run alternately in this one process, so a busy
machine slows both alike; the ratio is checked, never a time. Limits (issue 37): the force map
and the Taylor surrogate 1.5x the direct call, the Reynolds solver 1.2x. Measured 2026-12-06 on
a 2-vCPU AMD EPYC VM at a load of 5-8: about 0.6-1.4x for map and Taylor, 0.7-1.05x for Reynolds.
"""

import time
from pathlib import Path

import pytest

from bearing_fmu.surrogates.surrogate import load_surrogate
from rotor_host.analyses.compare import PYTHON_FMU, paper_variants
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene, required_file

SCENE = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml"
LIMIT = {"map": 1.5, "taylor": 1.5, "reynolds": 1.2, "linear": 1.5}
# (short, long) runs [s] and repeats: the Reynolds steps cost ~50x the others'
LENGTHS = {"reynolds": ((0.01, 0.04), 3)}
DEFAULT_LENGTHS = ((0.02, 0.2), 7)  # min of 7: another test on the other core in CI


def _marginal(scenes: dict, lengths, repeats: int, work: Path) -> dict:
    """{route: marginal integration time per step [s]} of each route's scene, runs alternated."""
    (short, long), n = lengths, {}
    best = {(r, t): float("inf") for r in scenes for t in (short, long)}
    for r, s in scenes.items():  # each route's FMU built and loaded, its kernels compiled, off the clock
        run_scene(s.with_internal(s.internal, t_end_s=10 * s.dt_s), None, work_dir=work)
    for _ in range(repeats):
        for t in (short, long):
            for r, s in scenes.items():
                cpu = time.thread_time()
                meta = run_scene(s.with_internal(s.internal, t_end_s=t), None, work_dir=work).meta
                cpu = time.thread_time() - cpu  # this thread's CPU: what other processes take does not enter
                assert meta["status"] == "ok", meta["message"]
                best[r, t] = min(best[r, t], cpu)
                n[t] = meta["steps"]
    return {r: (best[r, long] - best[r, short]) / (n[long] - n[short]) for r in scenes}


@pytest.mark.slow
@pytest.mark.native
def test_main_job_rows_cost_per_step_about_the_direct_call(tmp_path):
    scene = load_scene(SCENE)
    ref, variants = paper_variants(scene, load_surrogate(required_file(scene, "taylor", "surrogate")))
    ratios = {}
    for v in [ref, *variants]:
        if v.label.endswith(PYTHON_FMU):
            continue
        native = v.scene(scene)
        assert native.via == "fmu" and native.fmu_kind == "native"
        lengths, repeats = LENGTHS.get(v.internal, DEFAULT_LENGTHS)
        per_step = _marginal({"native": native, "direct": native.with_internal(v.internal, via="direct")},
                             lengths, repeats, tmp_path)
        ratios[v.internal] = per_step["native"] / per_step["direct"]
    print(f"native / direct per step: {ratios}")  # shown with -s
    assert set(ratios) == {"reynolds", "map", "taylor", "linear"}
    for internal, ratio in ratios.items():
        assert ratio <= LIMIT[internal], f"{internal}: the main job's row {ratio:.2f}x the direct call per step {ratios}"
