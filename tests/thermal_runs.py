"""A scene with a supply temperature on one internal, in-process and through the Python FMU's
thermal ports, beside the same scene on the Reynolds solver (tests/test_forcemap_flows.py,
tests/test_taylor_flows.py)."""

import dataclasses

import numpy as np


def three_runs(scene, internal: str, options: dict, t_end_s: float, tmp_path) -> dict:
    """{"rey", "direct", "fmu"}: the recorded series (npz) of ``scene`` (its ``t_end_s`` replaced) on
    Reynolds in-process, on ``internal`` with ``options`` ({internal: {option: value}}) in-process,
    and the same through the Python FMU."""
    from rotor_host.scenes.run import run_scene

    out = {}
    for name, which, via in (("rey", "reynolds", "direct"), ("direct", internal, "direct"), ("fmu", internal, "fmu")):
        run = run_scene(dataclasses.replace(scene.with_internal(which, options=options if which == internal else {},
                                                                t_end_s=t_end_s), via=via), tmp_path / name)
        assert run.ok, run
        out[name] = np.load(run.npz)
    return out


def check_three_runs(out: dict, reynolds_rtol: float, fmu_rtol: float = 1e-9) -> None:
    """The FMU run equals the in-process one to ``fmu_rtol`` and the Reynolds run is within
    ``reynolds_rtol`` of it, each of the largest value of y, z, Fy, Fz."""
    for key in ("y", "z", "Fy", "Fz"):
        scale = np.max(np.abs(out["direct"][key]))
        assert np.max(np.abs(out["fmu"][key] - out["direct"][key])) <= fmu_rtol * scale, key
        assert np.max(np.abs(out["rey"][key] - out["direct"][key])) <= reynolds_rtol * scale, key
