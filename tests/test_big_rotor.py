"""Big rotors at banded cost (rotor_host.model.rotor band assembly, Rotor.matrices; the static
equilibrium's banded tangent with the bearings as a rank-m correction, integrate.equilibrium;
the integrator on sparse matrices): a 2000-element shaft on bearings at both ends runs in
seconds without an n x n matrix, its static deflection against beam theory, and the sparse
path equal to the dense one on a medium rotor.
"""

import math
import time
from pathlib import Path

import numpy as np
import pytest

from rotor_host.integrate.banded import is_sparse
from rotor_host.model.assembly import DENSE_MAX_DOF
from rotor_host.model.rotor import Rotor
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"


def _uniform_shaft(tmp_path, n_el: int, *, length_mm=1000.0, od_mm=20.0) -> Path:
    """A uniform steel shaft of n_el equal elements on the paper's bearing at both ends."""
    le = length_mm / n_el
    els = "\n".join(f"  {{ nodes = [{i + 1}, {i + 2}], od_mm = {od_mm}, length_mm = {le!r} }}," for i in range(n_el))
    bearing = MODELS / "bearing_paper.toml"
    path = tmp_path / f"shaft_{n_el}.toml"
    path.write_text(f"elements = [\n{els}\n]\n[material]\nE_GPa = 200.0\ndensity_kg_m3 = 7850.0\npoisson = 0.3\n"
                    f'[[bearings]]\nnode = 1\nbearing = "{bearing}"\n'
                    f'[[bearings]]\nnode = {n_el + 1}\nbearing = "{bearing}"\n')
    return path


def _scene(tmp_path, rotor: Path, record: list[int], t_end=2e-3) -> Path:
    path = tmp_path / "big.toml"
    path.write_text(f'name = "big"\nrotor = "{rotor}"\ninternal = "map"\nvia = "direct"\nspeed_hz = 22.0\n'
                    f'[map]\nmap = "{MODELS / "maps" / "paper_bearing.json"}"\n'
                    f"[time]\nt_end_s = {t_end!r}\ndt_s = 1e-4\n[record]\nnodes = {record}\n")
    return path


def test_a_2000_element_shaft_sags_as_beam_theory_says(tmp_path):
    # A uniform shaft on two supports is statically determinate: relative to the line through its
    # journals, its middle sags by the simply supported beam's 5 w L^4 / (384 E I) plus the
    # Timoshenko shear part w L^2 / (8 kappa G A) (kappa of a solid circle, Hutchinson 2001:
    # 6 (1 + nu)^2 / (7 + 12 nu + 4 nu^2)), w = rho g A, whatever the films do at its ends
    n_el = 2000
    rotor_path = _uniform_shaft(tmp_path, n_el)
    mid = n_el // 2 + 1  # 1-based
    t0 = time.perf_counter()
    run = run_scene(load_scene(_scene(tmp_path, rotor_path, [mid])), tmp_path / "out")
    wall = time.perf_counter() - t0
    assert run.meta["status"] == "ok", run.meta["message"]
    assert run.meta["equilibrium_time_s"] < 5.0 and wall < 60.0  # was 400 s and 7.2 GB
    nodes = [int(n) for n in run.arrays["nodes"]]
    q0 = np.asarray(run.arrays["q0"])
    z = {n: q0[2 * nodes.index(n) + 1] for n in (1, mid, n_el + 1)}
    L, d, E, nu, rho, g = 1.0, 0.02, 200e9, 0.3, 7850.0, 9.81
    A, I = math.pi * d ** 2 / 4, math.pi * d ** 4 / 64
    w = rho * g * A
    kappa = 6 * (1 + nu) ** 2 / (7 + 12 * nu + 4 * nu ** 2)
    sag = 5 * w * L ** 4 / (384 * E * I) + w * L ** 2 / (8 * kappa * E / (2 * (1 + nu)) * A)
    assert -(z[mid] - (z[1] + z[n_el + 1]) / 2) == pytest.approx(sag, rel=1e-7)


def test_sparse_matrices_give_the_dense_answer_on_a_medium_rotor(tmp_path):
    # the paper rotor cut 30 times (1204 DOFs, above DENSE_MAX_DOF: the run takes sparse matrices)
    # against the same rotor's dense matrices: equilibrium and a short run equal to round-off
    from rotor_host.integrate.equilibrium import static_equilibrium
    from rotor_host.integrate.newmark import Newmark
    from rotor_host.scenes.bearings import build_bearings
    from rotor_host.scenes.run import bearing_loads, static_start

    rotor = Rotor.from_toml(MODELS / "rotor_paper.toml").refined(30)
    assert rotor.n_dof > DENSE_MAX_DOF and is_sparse(rotor.matrices()[1])
    scene = load_scene(_scene(tmp_path, MODELS / "rotor_paper.toml", []))
    f = rotor.weight_vector(9.81)
    loads = bearing_loads(rotor, f)
    with build_bearings(scene, rotor, loads, tmp_path) as bearings:
        q_sparse = static_start(rotor, f, loads, bearings, scene.omega)
        q_dense = static_equilibrium(rotor.K, f, bearings, q_sparse * (1 + 1e-6), rigid_modes=rotor.rigid_modes())
        assert np.max(np.abs(q_sparse - q_dense)) <= 1e-8 * np.max(np.abs(q_dense))
        runs = []
        for M, K, G, C in (rotor.matrices(), (rotor.M, rotor.K, rotor.G, rotor.C)):
            res = Newmark(M, K, C, G, scene.omega, f, bearings).run(q_dense, np.zeros(rotor.n_dof), 0.0, 2e-3, 1e-4)
            runs.append(res.q)
    assert np.max(np.abs(runs[0] - runs[1])) <= 1e-9 * np.max(np.abs(runs[1]))
