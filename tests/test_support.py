"""Physical sanity of every answer (issue: nothing wrong said as right): the static equilibrium
accepts only a rotor its bearings hold (rotor_host.integrate.equilibrium: bearings at two places,
journals inside their clearances, bearing forces balancing the loads), and a scene's time step,
speed and unbalance are checked against the shaft period, the material and the rotor's mass
before any solve (rotor_host.scenes.sanity). The expected numbers come from statics by hand
(the paper rotor's weight from its Table 1 geometry, its centre of mass by its symmetry), from
the shaft period 1 / f and from the speed of sound sqrt(E / rho) of steel, not from the code.
"""

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.physics.statics import format_newtons
from rotor_host.integrate.equilibrium import BALANCE_RTOL, RotorNotSupported, static_equilibrium, support_check
from rotor_host.integrate.forces import LinearForce
from rotor_host.model.rotor import Rotor
from rotor_host.scenes.sanity import CoarseStepWarning, check_scene_physics
from rotor_host.scenes.scene import SceneError, load_scene

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
G = 9.81


def _paper_weight_by_hand() -> float:
    """The paper rotor's weight [N] from Table 1: steel 7850 kg/m^3, ten solid elements
    (od, length in mm) and the disk (95 mm outside, 23.5 mm bore, 47 mm wide)."""
    elements = [(12.0, 40.0), (31.0, 10.0), (31.0, 10.0), (12.0, 266.5), (23.5, 23.5), (23.5, 23.5),
                (12.0, 266.5), (31.0, 10.0), (31.0, 10.0), (12.0, 40.0)]
    volume = sum(math.pi / 4 * d ** 2 * length for d, length in elements)
    volume += math.pi / 4 * (95.0 ** 2 - 23.5 ** 2) * 47.0
    return 7850.0 * volume * 1e-9 * G


def _one_bearing_rotor(tmp_path) -> Path:
    """The paper rotor with its bearing at node 9 taken away: it rests on node 3 alone."""
    text = (MODELS / "rotor_paper.toml").read_text()
    text = text[:text.rindex("[[bearings]]")].replace('"bearing_paper.toml"', f'"{MODELS / "bearing_paper.toml"}"')
    path = tmp_path / "rotor_one.toml"
    path.write_text(text)
    return path


def _scene(tmp_path, rotor: Path, *, speed_hz=22.0, dt_s=1e-4, t_end_s=0.01, mass_kg=8.5e-3) -> Path:
    path = tmp_path / "s.toml"
    path.write_text(f'name = "s"\nrotor = "{rotor}"\ninternal = "map"\nvia = "direct"\nspeed_hz = {speed_hz!r}\n'
                    f'[map]\nmap = "{MODELS / "maps" / "paper_bearing.json"}"\n'
                    f"[time]\nt_end_s = {t_end_s!r}\ndt_s = {dt_s!r}\n"
                    f"[[unbalance]]\nnode = 6\nmass_kg = {mass_kg!r}\nradius_mm = 37.0\n")
    return path


def test_rigid_modes_are_the_null_space_of_the_free_shaft():
    # a free beam's K does no work on a rigid motion (K phi = 0), and the weight's resultant is
    # the rotor's weight by hand, acting at mid-length (the rotor is symmetric: 700 mm long)
    rotor = Rotor.from_toml(MODELS / "rotor_paper.toml")
    phi = rotor.rigid_modes()
    assert np.abs(rotor.K @ phi).max() <= 1e-12 * np.abs(rotor.K).max()
    Fy, Fz, My, Mz = phi.T @ rotor.weight_vector(G)
    W = _paper_weight_by_hand()
    assert Fy == 0.0 and My == 0.0 and Fz == pytest.approx(-W, rel=1e-12)
    assert Mz / Fz == pytest.approx(0.350, rel=1e-12)


def test_a_rotor_on_one_bearing_is_refused_with_its_load_and_moment(tmp_path, capsys):
    # before: Newton's round-off acceptance took the free end 10 000 km below the bearing, "ok".
    # By hand: the bearing (node 3, x = 50 mm) must carry the whole weight W, and the weight acts
    # at the centre of mass (x = 350 mm by symmetry): a moment W * 0.3 m no journal bearing takes.
    from rotor_host.cli import main

    W = _paper_weight_by_hand()
    code = main(["run", str(_scene(tmp_path, _one_bearing_rotor(tmp_path))), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "the rotor is not supported: bearing 1 (node 3) is its only support (x = 50 mm)" in err
    assert f"the {format_newtons(W)} load" in err and f"moment of {W * 0.3:.3g} N m" in err
    assert not (tmp_path / "out" / "s_map.json").exists()  # nothing stated as a result


def test_unbalanced_bearing_forces_are_named_with_their_numbers():
    # the paper rotor on its two bearings: by symmetry each carries W / 2 at equilibrium (balanced);
    # a state whose films carry 12.9 N of the weight is refused, naming each bearing's share
    rotor = Rotor.from_toml(MODELS / "rotor_paper.toml")
    fs = rotor.weight_vector(G)
    dofs = np.array([rotor.dof(n, d) for n in rotor.bearing_nodes for d in ("y", "z")])
    names = ["bearing 1 (node 3)", "bearing 2 (node 9)"]
    W = _paper_weight_by_hand()
    q = np.zeros(rotor.n_dof)
    assert support_check(q, np.array([0.0, W / 2, 0.0, W / 2]), fs, dofs, rotor.rigid_modes(), names) is None
    why = support_check(q, np.array([0.0, 6.45, 0.0, 6.45]), fs, dofs, rotor.rigid_modes(), names)
    assert why == (f"static equilibrium: the rotor is not supported: the bearings carry 12.9 N (bearing 1 (node 3) "
                   f"6.45 N; bearing 2 (node 9) 6.45 N) of {format_newtons(W)} (weight and static loads; the forces "
                   f"must balance to {BALANCE_RTOL:g} of them)")
    # the forces balance but not the moments: all of the weight on the bearing at node 3
    why = support_check(q, np.array([0.0, W, 0.0, 0.0]), fs, dofs, rotor.rigid_modes(), names)
    assert "moment" in why and f"{W * 0.3:.3g} N m of the loads' moment {W * 0.35:.3g} N m" in why


class Springs(LinearForce):
    """Linear springs at the bearing nodes, with the clearances a bearing set has."""

    def __init__(self, dofs, k, clearance):
        super().__init__(dofs, k * np.eye(len(dofs)))
        self.names = [f"bearing {i + 1}" for i in range(len(dofs) // 2)]
        self.clearances = [clearance] * (len(dofs) // 2)


@pytest.mark.parametrize("drop", [0.5, 3.0])
def test_a_journal_outside_its_clearance_is_no_equilibrium(drop):
    # each support of the symmetric rotor carries W / 2 (statics), so a spring k lets its journal
    # drop W / (2 k): below the clearance the state is the answer, beyond it a refusal naming it
    rotor = Rotor.from_toml(MODELS / "rotor_paper.toml")
    W, CR = _paper_weight_by_hand(), 90e-6
    dofs = [rotor.dof(n, d) for n in rotor.bearing_nodes for d in ("y", "z")]
    k = W / 2 / (drop * CR)
    solve = lambda: static_equilibrium(rotor.K, rotor.weight_vector(G), Springs(dofs, k, CR),  # noqa: E731
                                       np.zeros(rotor.n_dof), rigid_modes=rotor.rigid_modes())
    if drop < 1.0:
        q = solve()
        assert q[dofs[1]] == pytest.approx(-W / 2 / k, rel=1e-9) and q[dofs[3]] == pytest.approx(-W / 2 / k, rel=1e-9)
    else:
        with pytest.raises(RotorNotSupported, match=r"bearing 1 has its journal at eccentricity ratio 3, outside its "
                                                    r"clearance of 90 um"):
            solve()


def test_a_step_of_half_a_revolution_or_more_is_refused_by_its_key(tmp_path, capsys):
    # 22 Hz: a revolution takes 1 / 22 s; dt = 0.5 s is 11 of them. The limit is half a
    # revolution (two samples per period), 1 / 44 s; a tenth of one, 1 / 220 s, draws the orbit
    from rotor_host.cli import main

    rotor = MODELS / "rotor_paper.toml"
    scene = load_scene(_scene(tmp_path, rotor, dt_s=0.5, t_end_s=1.0))
    with pytest.raises(SceneError, match=rf"dt_s = 0\.5: 11 shaft revolutions per step at 22 Hz .*at most "
                                         rf"{1 / 44:.3g} s \(half a revolution\), and {1 / 220:.3g} s"):
        check_scene_physics(scene, Rotor.from_toml(rotor))
    code = main(["run", str(scene.source), "--out", str(tmp_path / "out")])
    assert code == 2 and "[time] dt_s = 0.5" in capsys.readouterr().err
    # a fifth of a revolution: warned, not refused; a twentieth: nothing said
    with pytest.warns(CoarseStepWarning, match=r"dt_s = 0\.01 is 0\.22 of a shaft revolution"):
        check_scene_physics(load_scene(_scene(tmp_path, rotor, dt_s=0.01)), Rotor.from_toml(rotor))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_scene_physics(load_scene(_scene(tmp_path, rotor, dt_s=1e-4)), Rotor.from_toml(rotor))


def test_absurd_mass_and_speed_are_named_before_the_solve(tmp_path):
    # the unbalance mass against the rotor's weight / g by hand; the speed against the speed of
    # sound in steel, sqrt(200 GPa / 7850 kg/m^3) = 5047.5 m/s, at the disk's rim (47.5 mm)
    rotor_path = MODELS / "rotor_paper.toml"
    rotor = Rotor.from_toml(rotor_path)
    mass = _paper_weight_by_hand() / G
    with pytest.raises(SceneError, match=rf"\[\[unbalance\]\] 1 mass_kg = 1e\+06: more than the whole rotor's mass "
                                         rf"\({mass:.4g} kg\)"):
        check_scene_physics(load_scene(_scene(tmp_path, rotor_path, mass_kg=1e6)), rotor)
    c = math.sqrt(200e9 / 7850.0)
    with pytest.raises(SceneError, match=rf"speed_hz = 1e\+09: .* radius 47\.5 mm .* \(sqrt\(E / density\) = "
                                         rf"{c:.4g} m/s.* below {re.escape(f'{c / (2 * math.pi * 0.0475):.4g}')} Hz"):
        check_scene_physics(load_scene(_scene(tmp_path, rotor_path, speed_hz=1e9, dt_s=1e-12, t_end_s=1e-11)), rotor)
    check_scene_physics(load_scene(_scene(tmp_path, rotor_path, speed_hz=10e3, dt_s=1e-6, t_end_s=1e-5)), rotor)


def test_stability_of_a_rotor_on_one_bearing_is_bad_input(tmp_path, capsys):
    # the same rotor as above to `stability`: it said "no speed has a static equilibrium", exit 1;
    # no speed can hold it, so it is refused before any solve, by the rotor file, exit 2
    from rotor_host.cli import main

    rotor = _one_bearing_rotor(tmp_path)
    code = main(["stability", str(rotor), "--internal", "map", "--speeds-hz", "20:24:2", "--no-plots",
                 "--out", str(tmp_path / "out")])
    out, err = capsys.readouterr()
    assert code == 2, err
    assert f"{rotor}: static equilibrium: the rotor is not supported: bearing 1 (node 3) is its only support" in err
    assert "Traceback" not in err and "Hz:" not in out  # no speed was tried
    assert not list((tmp_path / "out").glob("stability_*"))


def test_stability_where_no_speed_holds_the_rotor_is_bad_input(tmp_path, capsys, monkeypatch):
    # the equilibrium's own refusal (journals outside the clearance, loads not carried) at every
    # speed is the rotor's or its loads' fault, not a failed run: exit 2, the reason named
    from rotor_host.analyses.linear.stability import Stability
    from rotor_host.cli import main

    why = "static equilibrium: the rotor is not supported: bearing 1 (node 3) carries 12.9 N of 33.3 N"

    def unsupported(self, omega, q0=None):
        raise RotorNotSupported(why)

    monkeypatch.setattr(Stability, "equilibrium", unsupported)
    rotor = MODELS / "rotor_paper.toml"
    code = main(["stability", str(rotor), "--internal", "map", "--speeds-hz", "20:24:2", "--no-plots",
                 "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and f"{rotor}: at every speed of 20-24 Hz: {why}" in err, err


def test_absurd_material_and_speed_of_a_linear_analysis_are_named(tmp_path, capsys):
    # density 1e30 kg/m^3 was found out as a bearing asked for 2e27 N (exit 1); 1e12 Hz gave a
    # Campbell diagram (exit 0). The densest solid, osmium, is 22 590 kg/m^3; the speed limit is
    # the speed of sound in steel at the disk's rim, as above
    from rotor_host.cli import main

    dense = tmp_path / "rotor_dense.toml"
    dense.write_text((MODELS / "rotor_paper.toml").read_text().replace("density_kg_m3 = 7850.0", "density_kg_m3 = 1e30")
                     .replace('"bearing_paper.toml"', f'"{MODELS / "bearing_paper.toml"}"'))
    code = main(["stability", str(dense), "--internal", "map", "--speeds-hz", "20:24:2", "--no-plots",
                 "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and f"{dense}: [material] density_kg_m3 = 1e+30 must be a finite number > 0 and <= 100000" in err
    code = main(["stability", str(MODELS / "rotor_paper.toml"), "--internal", "map", "--speeds-hz", "1e12:1e12:1",
                 "--no-plots", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    c = math.sqrt(200e9 / 7850.0)
    assert code == 2 and "the top speed (--speeds-hz) = 1e+12: the rotor's surface at radius 47.5 mm" in err
    assert f"below {c / (2 * math.pi * 0.0475):.4g} Hz" in err
    assert not list((tmp_path / "out").glob("stability_*"))


def test_the_step_is_checked_against_the_highest_mode_of_interest(tmp_path, capsys):
    # At 15 Hz the paper rotor's first bending pair (its 22 Hz first critical, paper Fig. 4)
    # lies above the speed and inside the band of 2 x 15 Hz: a step that half-resolves the
    # shaft's turn (dt = 0.025 s, 0.375 of a revolution: warned) cannot resolve that mode
    # (fewer than two steps per period): refused by [time] dt_s with both limits, 0.5 / f and
    # 0.1 / f of the mode, whose frequency comes from the dense eigensolution of the stability
    # analysis at the same speed (tests/test_stability.py checks it against the paper)
    from rotor_host.analyses.linear.stability import Stability
    from rotor_host.cli import main

    rotor = Rotor.from_toml(MODELS / "rotor_paper.toml")
    st = Stability(rotor, "map", {"map": str(MODELS / "maps" / "paper_bearing.json")})
    st.band_hz = 30.0
    point, _ = st.at(15.0)
    f_m = max(f for f, ld in zip(point.freq_hz, point.log_dec) if f <= 30.0 and ld < 1.257)
    assert 21.0 < f_m < 23.0  # the first critical, near 22 Hz
    scene = _scene(tmp_path, MODELS / "rotor_paper.toml", speed_hz=15.0, dt_s=0.025, t_end_s=0.1)
    code = main(["run", str(scene), "--out", str(tmp_path / "out"), "--quiet", "--no-plots"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert (f"[time] dt_s = 0.025: {0.025 * f_m:.3g} periods per step of the highest mode of interest, "
            f"{f_m:.4g} Hz") in err
    assert f"dt_s must be at most {0.5 / f_m:.3g} s, and {0.1 / f_m:.3g} s (a tenth)" in err
    assert not list((tmp_path / "out").glob("*.npz"))
    # a step that resolves the mode coarsely is warned about; a fine one passes in silence
    from rotor_host.scenes.run import run_scene

    with pytest.warns(CoarseStepWarning, match=rf"dt_s = 0\.01 is {0.01 * f_m:.3g} of a period of the highest mode"):
        run_scene(load_scene(_scene(tmp_path, MODELS / "rotor_paper.toml", speed_hz=15.0, dt_s=0.01, t_end_s=0.05)),
                  tmp_path / "out")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        run_scene(load_scene(_scene(tmp_path, MODELS / "rotor_paper.toml", speed_hz=15.0, dt_s=0.002,
                                    t_end_s=0.01)), tmp_path / "out")
