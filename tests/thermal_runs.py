"""A scene with a supply temperature on one internal, in-process and through the Python FMU's
thermal ports, beside the same scene on the Reynolds solver (tests/test_forcemap_flows.py,
tests/test_taylor_flows.py), and the thermal records of such runs compared (the native FMU's too:
tests/test_thermal_host.py, tests/test_native_groove_thermal.py)."""

import dataclasses

import numpy as np

# what every route records of the film over time (docs/file-formats.md, "Run result: the thermal
# arrays"); the inflow Q_in only in-process (the FMUs have no inflow output)
THERMAL = ("T_eff", "mu_eff", "P_loss", "Q_side")


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
    ``reynolds_rtol`` of it, each of the largest value of y, z, Fy, Fz; with a supply temperature
    both record the same film history (``check_thermal_records``), and the Reynolds run's T_eff is
    within ``reynolds_rtol`` K of it (the film's rise over the supply is ~1 K)."""
    for key in ("y", "z", "Fy", "Fz"):
        scale = np.max(np.abs(out["direct"][key]))
        assert np.max(np.abs(out["fmu"][key] - out["direct"][key])) <= fmu_rtol * scale, key
        assert np.max(np.abs(out["rey"][key] - out["direct"][key])) <= reynolds_rtol * scale, key
    if "T_eff" in out["direct"].files:
        check_thermal_records(out, fmu_rtol)
        assert np.max(np.abs(out["rey"]["T_eff"] - out["direct"]["T_eff"])) <= reynolds_rtol


def check_thermal_records(out: dict, rtol: float = 1e-9, reference: str = "direct") -> None:
    """Every run of ``out`` but the Reynolds one ("rey") records T_eff, mu_eff, P_loss and Q_side at
    the same times as ``out[reference]``, equal to ``rtol`` of each array's largest value (T_eff: to
    ``rtol`` K, of the order of the film's rise of 1-2 K over the supply; a step's lag moves it by
    ~1e-6 K at the 44 Hz scene's); an in-process run records the inflow too, an FMU run not; none of
    them records anything not finite."""
    ref = out[reference]
    for name, run in out.items():
        if name == "rey":
            continue
        assert np.array_equal(run["t"], ref["t"]), name
        for key in THERMAL:
            assert run[key].shape == ref["Fy"].shape and np.all(np.isfinite(run[key])), (name, key)
            scale = 1.0 if key == "T_eff" else np.max(np.abs(ref[key]))  # T_eff [K]: its rise is ~1 K
            assert np.max(np.abs(run[key] - ref[key])) <= rtol * scale, (name, key, np.max(np.abs(run[key] - ref[key])))
        assert ("Q_in" in run.files) == (name in ("direct", "rey")), name


ROUTES = {"direct": {}, "python": {"via": "fmu", "fmu_kind": "python"}, "native": {"via": "fmu", "fmu_kind": "native"}}


def run_routes(scene, tmp_path, names=("direct", "python", "native")) -> dict:
    """{name: the recorded series (npz)} of ``scene`` in-process ("direct"), through the Python FMU
    ("python") and through the native FMU ("native")."""
    from rotor_host.scenes.run import run_scene

    out = {}
    for name in names:
        run = run_scene(dataclasses.replace(scene, **ROUTES[name]), tmp_path / name)
        assert run.ok, run
        out[name] = np.load(run.npz)
    return out


def check_native(out: dict, rtol: float, direct_rtol: float | None = None) -> None:
    """The native run of ``out`` equals the Python FMU's to ``rtol`` of the largest y, z, Fy, Fz
    (and the in-process run's to ``direct_rtol``, if given)."""
    for key in ("y", "z", "Fy", "Fz"):
        scale = np.max(np.abs(out["python"][key]))
        assert np.max(np.abs(out["native"][key] - out["python"][key])) <= rtol * scale, key
        if direct_rtol is not None:
            assert np.max(np.abs(out["native"][key] - out["direct"][key])) <= direct_rtol * scale, key


def native_equals_python(scene, tmp_path, rtol: float = 1e-12) -> dict:
    """{"python", "native"}: the recorded series of ``scene`` through the Python and the native FMU,
    checked equal to ``rtol`` of the largest y, z, Fy, Fz and in their thermal records."""
    out = run_routes(scene, tmp_path, ("python", "native"))
    check_native(out, rtol)
    check_thermal_records(out, rtol, reference="python")
    return out
