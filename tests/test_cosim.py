"""The fmpy co-simulation host: FMU bearings give the same rotor run as the same internal
called in-process (the reference is the direct run: equal to round-off, since the FMU
evaluates the very same code), discarded steps become step cuts, instances are freed."""

import numpy as np
import pytest

from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene



def scene(paper_scene, internal, t_end=0.01):
    """The paper's 22 Hz scene through the bearing FMUs (tests/conftest.py ``paper_scene``),
    Reynolds on 48 x 8, recording nodes 3, 6 and 9."""
    return load_scene(paper_scene(file=f"{internal}.toml", internal=internal, via="fmu", t_end=t_end, grid=(48, 8),
                                  record={"nodes": [3, 6, 9]}))


@pytest.mark.slow
@pytest.mark.parametrize("internal", ["reynolds", "linear"])
def test_fmu_run_equals_direct_run(paper_scene, fmu, internal):
    s = scene(paper_scene, internal)
    s.fmu = fmu
    direct = run_scene(s.with_internal(internal, via="direct"))
    cosim = run_scene(s.with_internal(internal, via="fmu"))
    assert direct.ok and cosim.ok
    for key in ("y", "z", "vy", "vz", "Fy", "Fz"):
        a, b = direct.arrays[key], cosim.arrays[key]
        scale = np.abs(a).max()
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * scale, err_msg=key)
    # the same Newton path: the FMU tangent outputs are the internal's Jacobian
    assert cosim.meta["force_evaluations"] == direct.meta["force_evaluations"]


def test_discarded_fmu_step_becomes_a_diagnosed_stop(tmp_path, paper_scene, fmu):
    # a huge unbalance at the bearing node drives the Reynolds journal into the wall: the FMU
    # discards the step (eccentricity >= 1), the integrator halves it, then stops naming the
    # bearing; everything up to there is kept and every instance is freed. 3 kg (of the rotor's
    # 3.4 kg: a heavier unbalance is refused by its key) at 100 mm and 66 Hz, 52 kN, reaches the
    # wall at t = 0.0076 s, after 38 steps; the direct run fails at the same t
    # (tests/test_scene.py::test_failed_run_keeps_what_it_computed)
    s = scene(paper_scene, "reynolds", t_end=0.2)
    s.fmu = fmu
    s.speed_hz = 66.0
    s.unbalances[0].node, s.unbalances[0].mass_kg, s.unbalances[0].radius_m = 2, 3.0, 0.1
    s = s.with_internal("reynolds", options={"reynolds": {"n_theta": 32, "n_x": 4}}, dt_s=2e-4)
    run = run_scene(s, tmp_path / "out")
    assert run.meta["status"] == "failed"
    assert "bearing 1" in run.meta["message"] and "eccentricity ratio" in run.meta["message"]
    assert "halvings" in run.meta["message"]  # the step was cut before the run stopped
    assert run.meta["t_reached_s"] > 0.005 and np.load(run.npz)["t"][-1] == run.meta["t_reached_s"]


def test_bad_fmu_parameter_names_the_parameter(tmp_path, fmu):
    from rotor_host.coupling.cosim import FMUBearings, FMUError

    with pytest.raises(FMUError, match="'viscosity' is not a parameter"):
        FMUBearings(fmu, [(0, 1)], 100.0, [{"viscosity": 0.05}])
    with pytest.raises(FMUError, match="initialisation failed.*unknown internal"):
        FMUBearings(fmu, [(0, 1)], 100.0, [{"internal": "magic"}])


def test_fmu_without_tangent_gives_the_force_alone(fmu):
    # newton_tangent 'fd' / 'linear': the host reads no K, C, so the FMUs are told not to
    # compute them (compute_tangent = false) and evaluate hands back the force alone, equal
    # to the force of an instance that does compute its tangent
    from rotor_host.coupling.cosim import FMUBearings

    params = [{"internal": "reynolds", "n_theta": 32, "n_x": 4}]
    q, v = np.array([2e-5, -3e-5]), np.array([1e-3, 2e-3])
    out = {}
    for mode in ("bearing", "fd"):
        with FMUBearings(fmu, [(0, 1)], 2 * np.pi * 22, params, tangent=mode) as b:
            b.begin_step(0.0, 1e-4)
            f, dq, dv = b.evaluate(q, v)
            out[mode] = (f.copy(), dq, dv, b._out[2:10].copy())  # the K, C outputs as read
            b.accept_step()
    assert not out["fd"][3].any()  # compute_tangent reached the FMU: K, C stay 0
    assert out["fd"][1] is None and out["fd"][2] is None
    assert np.abs(out["bearing"][1]).max() > 1e4  # a real film stiffness [N/m]
    np.testing.assert_array_equal(out["fd"][0], out["bearing"][0])


class _StatusDll:
    """The FMU's library with fmi2DoStep answering a fixed status (the rest passes through)."""

    def __init__(self, dll, status):
        self._dll, self._status = dll, status

    def fmi2DoStep(self, *args):
        return self._status

    def __getattr__(self, name):
        return getattr(self._dll, name)


@pytest.mark.parametrize("status, error", [(2, "StepRejected"), (3, "FMUError"), (4, "FMUError")])
def test_only_a_discard_cuts_the_step(fmu, status, error):
    # FMI 2.0: fmi2Discard = this step is refused, try another; fmi2Error / fmi2Fatal = the
    # instance failed. Before, every status > OK became a step cut and the integrator halved
    # the step on a real error (a Ctrl-C inside the slave came back as one) and carried on.
    from rotor_host.coupling import cosim
    from rotor_host.integrate.forces import StepRejected

    expected = {"StepRejected": StepRejected, "FMUError": cosim.FMUError}[error]
    with cosim.FMUBearings(fmu, [(0, 1)], 2 * np.pi * 22, [{"n_theta": 32, "n_x": 4}]) as b:
        real = b.instances[0].dll
        b.begin_step(0.0, 1e-4)
        b.instances[0].dll = _StatusDll(real, status)
        try:
            with pytest.raises(expected, match="bearing 1|doStep"):
                b.evaluate(np.array([1e-5, -2e-5]), np.zeros(2))
        finally:
            b.instances[0].dll = real
        assert issubclass(cosim.FMUError, RuntimeError) and not issubclass(cosim.FMUError, StepRejected)
