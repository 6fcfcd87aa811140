"""The modes of a big rotor without a dense n x n matrix (rotor_host.model.band_modes: ARPACK in
shift-invert mode on the sparse M, K, G about the band of interest) against the dense
state-space eigensolution of ``Rotor.modes``, on the bundled rotors: the same modes in the band,
and the same stability sweep (least stable log decrement, threshold, critical speeds).

Round-off: both paths are backward stable; the sparse one's eigenpairs are checked directly by
their residual ||(lam^2 M + lam C + K) x|| against the terms' sizes (measured 2e-18 near the
shift, up to 4e-12 in the band and 1e-11 for the disk's modes farthest from the shift, where
shift-invert amplifies least; so 1e-11 in the band, 1e-9 beyond), and the two eigenvalues agree to what the dense path's own backward error of ~3e-16
moves a mode of this conditioning (measured: 5e-8 relative for the paper rotor's oil-film
modes, 1e-12 for Friswell's), so 1e-7 relative.
"""

import math
import os
from pathlib import Path

import numpy as np
import pytest

from rotor_host.model import band_modes as bm
from rotor_host.model.rotor import Rotor

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
PAPER_MAP = MODELS / "maps" / "paper_bearing.json"


def _backward_error(rotor, speed, K, C, freq, log_dec, shapes) -> float:
    Kt = rotor.K + rotor.bearing_matrix(K)
    Ct = rotor.C + rotor.bearing_matrix(C) + speed * rotor.G
    M = rotor.M
    scale = [np.linalg.norm(A, 2) for A in (M, Ct, Kt)]
    worst = 0.0
    for f, ld, x in zip(freq, log_dec, shapes.T):
        wd = 2 * math.pi * f
        lam = complex(-ld * wd / (2 * math.pi), wd)
        r = np.linalg.norm((lam ** 2 * M + lam * Ct + Kt) @ x)
        worst = max(worst, r / ((abs(lam) ** 2 * scale[0] + abs(lam) * scale[1] + scale[2]) * np.linalg.norm(x)))
    return worst


@pytest.mark.parametrize("name", ["rotor_paper", "rotor_friswell"])
def test_the_band_s_modes_are_the_dense_solution_s(name):
    from rotor_host.analyses.linear.stability import Stability
    from rotor_host.analyses.linear.inputs import internal_options

    rotor = Rotor.from_toml(MODELS / f"{name}.toml")
    st = Stability(rotor, "reynolds", internal_options("reynolds", grid=(64, 8)))
    for speed_hz in (10.0, 25.0, 45.0):
        omega = 2 * math.pi * speed_hz
        K, C = st.linearise(st.equilibrium(omega), omega)
        band = 2.0 * speed_hz  # modal.RANK_UP_TO x the speed, as a stability sweep ranks
        fd, ld, sd = rotor.modes(omega, K, C)
        fs, ls, ss = bm.band_modes(rotor, omega, K, C, band, sparse=True)
        near = fs <= band
        assert _backward_error(rotor, omega, K, C, fs[near], ls[near], ss[:, near]) < 1e-11
        assert _backward_error(rotor, omega, K, C, fs, ls, ss) < 1e-9  # the disk's far side too
        lam_d = (-ld * fd + 2j * math.pi * fd) / (2 * math.pi) * 2 * math.pi
        lam_s = (-ls * fs + 2j * math.pi * fs) / (2 * math.pi) * 2 * math.pi
        sigma, radius = 0.5j * 2 * math.pi * band, bm.DISK_RADIUS * 2 * math.pi * band
        inside = np.abs(lam_d - sigma) <= radius
        assert np.any(fd[inside] <= band) or speed_hz == 10.0  # the comparison is not empty where modes are
        # every dense mode of the disk is found, and nothing else
        assert lam_s.size == inside.sum(), (fd, fs)
        np.testing.assert_allclose(lam_s, lam_d[inside], rtol=1e-7)
        # the shapes as well (largest entry 1; where two entries are equally large, as on a
        # symmetric rotor, each path may pick the other: compared up to that unit factor)
        # the shapes up to a unit factor, to 1e-5: in a cluster (four heavily damped pad modes about
        # -205 + 250j 1/s, 2-4 1/s apart) a shape is that much worse conditioned than its eigenvalue
        # (measured: 1.6e-6 at most, there; elsewhere 4e-7)
        for i, j in enumerate(np.flatnonzero(inside)):
            c = np.vdot(sd[:, j], ss[:, i]) / np.vdot(sd[:, j], sd[:, j])
            assert abs(abs(c) - 1.0) < 1e-5 and np.max(np.abs(ss[:, i] - c * sd[:, j])) < 1e-5


def test_a_stability_sweep_on_the_sparse_path_is_the_dense_sweep(monkeypatch):
    # the paper rotor through its threshold (~43 Hz, tests/test_stability.py) and its first
    # critical (22 Hz): with every rotor sent down the sparse path, the same answers
    from rotor_host.analyses.linear.stability import stability

    speeds = np.arange(18.0, 46.1, 4.0)
    dense = stability(MODELS / "rotor_paper.toml", speeds, "map", {"map": str(PAPER_MAP)})
    monkeypatch.setattr(bm, "DENSE_MODES_MAX_DOF", 0)
    sparse = stability(MODELS / "rotor_paper.toml", speeds, "map", {"map": str(PAPER_MAP)})
    for a, b in zip(dense.points, sparse.points):
        assert b.least_log_dec == pytest.approx(a.least_log_dec, rel=1e-6, abs=1e-9)
        assert b.freq_hz[b.least] == pytest.approx(a.freq_hz[a.least], rel=1e-7)
    assert sparse.threshold.speed_hz == pytest.approx(dense.threshold.speed_hz, abs=1e-3)  # Brent's xtol 1e-4 Hz
    assert sparse.threshold.whirl_hz == pytest.approx(dense.threshold.whirl_hz, rel=1e-6)
    assert [c["mode"] for c in sparse.criticals] == [c["mode"] for c in dense.criticals]
    np.testing.assert_allclose([c["speed_hz"] for c in sparse.criticals], [c["speed_hz"] for c in dense.criticals],
                               rtol=1e-7)


def test_a_big_rotor_is_not_solved_densely(monkeypatch):
    # the band is required above DENSE_MODES_MAX_DOF; a rotor whose matrices are sparse never
    # builds a dense matrix (the paper rotor cut into 25 pieces per element: 1004 DOFs)
    import rotor_host.integrate.banded as banded

    rotor = Rotor.from_toml(MODELS / "rotor_paper.toml").refined(25)
    assert rotor.n_dof > bm.DENSE_MODES_MAX_DOF and banded.is_sparse(rotor.matrices()[1])
    with pytest.raises(ValueError, match=r"a rotor of 1004 DOFs is solved in a band; up_to_hz = inf"):
        bm.band_modes(rotor, 0.0, np.eye(2) * 1e7, np.eye(2) * 1e3)

    def no_dense(*_):
        raise AssertionError("a dense n x n matrix was built")

    monkeypatch.setattr(banded, "from_band", no_dense)
    f, ld, shapes = bm.band_modes(rotor, 2 * math.pi * 22.0, np.eye(2) * 1e7, np.eye(2) * 1e3, 44.0)
    assert f.size and shapes.shape == (rotor.n_dof, f.size) and np.all(np.isfinite(ld))


@pytest.mark.parametrize("band_hz", [44.0, 500.0])
def test_the_first_count_is_the_undamped_disk_s_by_sylvester(band_hz):
    # ARPACK's first count (band_modes._undamped_count, the negative pivots of K_s - w^2 M) against
    # the dense generalised eigenvalues w_j^2 of (K_s, M): +i w_j in the disk for w_j <= Im(sigma) + R,
    # -i w_j for w_j <= R - Im(sigma); the paper rotor on stiff, cross-coupled bearings
    import scipy.linalg

    rotor = Rotor.from_toml(MODELS / "rotor_paper.toml")
    K = np.array([[2e7, 5e6], [-3e6, 1e7]])
    M, Kt, _ = bm._system(rotor, 0.0, K, np.zeros((2, 2)))
    wb = 2 * math.pi * band_hz
    sigma, radius = 0.5j * wb, bm.DISK_RADIUS * wb
    Ks = 0.5 * (Kt + Kt.T).toarray()
    w = np.sqrt(scipy.linalg.eigh(Ks, M.toarray(), eigvals_only=True))
    expected = int(np.sum(w <= sigma.imag + radius) + np.sum(w <= radius - sigma.imag))
    assert 0 < expected < 2 * rotor.n_dof  # the disk neither empty nor everything
    assert bm._undamped_count(M, Kt, sigma, radius) == expected


def test_arpack_runs_on_one_blas_thread_and_the_count_is_restored():
    calls = bm._openblas_threads()
    if calls is None:
        pytest.skip("scipy's BLAS here is not an OpenBLAS with thread functions: one_blas_thread changes nothing")
    get, put = calls
    before = get()
    many = min(2, os.cpu_count() or 1)
    put(many)
    try:
        with bm.one_blas_thread():
            assert get() == 1
        assert get() == many
    finally:
        put(before)


@pytest.mark.parametrize("inertia", [None, 2e-6])
def test_tilting_pads_in_the_band_are_the_dense_pad_modes(inertia):
    # band_modes_with_pads (the pads' coordinates in a sparse descriptor pencil, shift-invert)
    # against pad_modes.modes (the dense state matrix) on the bundled five-pad rotor, massless pads
    # and pads of 2e-6 kg m^2: every dense mode of the disk, to 1e-7 (measured: 2e-8 at most; the
    # sparse path's modes farthest from the shift carry 1e-8 of ARPACK's round-off there, the
    # dense one's 1e-11: both against the reduction's fixed point, pad_modes.iterate_mode)
    from dataclasses import replace

    from rotor_host.analyses.linear import pad_modes as pm
    from rotor_host.analyses.linear.stability import Stability

    rotor = Rotor.from_toml(MODELS / "rotor_paper_5pad_lbp.toml")
    st = Stability(rotor, "tilting_pad", {"n_theta": 24, "n_x": 4})
    for speed_hz in (20.0, 60.0):
        omega, band = 2 * math.pi * speed_hz, 2.0 * speed_hz
        blocks = pm.pad_blocks(st.internals, st.pairs, st.equilibrium(omega), omega)
        if inertia is not None:
            blocks = [replace(b, inertia=np.full_like(b.inertia, inertia)) for b in blocks]
        fd, ld, sd = pm.modes(rotor, omega, blocks)
        fs, ls, ss = bm.band_modes_with_pads(rotor, omega, blocks, band)
        lam_d, lam_s = -ld * fd + 2j * math.pi * fd, -ls * fs + 2j * math.pi * fs
        sigma, radius = 0.5j * 2 * math.pi * band, bm.DISK_RADIUS * 2 * math.pi * band
        inside = np.abs(lam_d - sigma) <= radius
        assert 0 < inside.sum() < fd.size  # modes in the disk and beyond it
        assert lam_s.size == inside.sum(), (fd, fs)
        np.testing.assert_allclose(lam_s, lam_d[inside], rtol=1e-7)
        # the shapes up to a unit factor, to 1e-5: in a cluster (four heavily damped pad modes about
        # -205 + 250j 1/s, 2-4 1/s apart) a shape is that much worse conditioned than its eigenvalue
        # (measured: 1.6e-6 at most, there; elsewhere 4e-7)
        for i, j in enumerate(np.flatnonzero(inside)):
            c = np.vdot(sd[:, j], ss[:, i]) / np.vdot(sd[:, j], sd[:, j])
            assert abs(abs(c) - 1.0) < 1e-5 and np.max(np.abs(ss[:, i] - c * sd[:, j])) < 1e-5


def test_a_mid_size_rotor_takes_the_band_not_one_long_dense_call(monkeypatch):
    # above DENSE_MODES_MAX_DOF (the paper rotor cut 8 times: 324 DOFs) the default is the band:
    # Rotor.modes, one LAPACK call of ~0.6 s here and 10 s at 1000 DOFs that Ctrl-C cannot stop, is not
    # called. The disk's modes are the dense solution's: in the band to 1e-7, beyond it to 1e-6.
    # Measured against shift-invert with the shift next to each mode: in the band the dense path is
    # 3e-8 off and the band's 3e-10; the disk's far side (1140, 1246 1/s; the shift 138 1/s) 1.6e-9
    # and 4.2e-7, the band's operator applied with round-off that shift-invert amplifies there (with
    # SuperLU's solve as before the banded LU, the same size, 2-5e-7)
    rotor = Rotor.from_toml(MODELS / "rotor_paper.toml").refined(8)
    assert rotor.n_dof > bm.DENSE_MODES_MAX_DOF
    K, C, omega, band = np.array([[2e7, 5e6], [-3e6, 1e7]]), np.eye(2) * 1e3, 2 * math.pi * 22.0, 44.0
    fd, ld, _ = rotor.modes(omega, K, C)

    def no_dense(*_):
        raise AssertionError("the dense eigenproblem was solved")

    monkeypatch.setattr(Rotor, "modes", no_dense)
    fs, ls, _ = bm.band_modes(rotor, omega, K, C, band)
    lam_d, lam_s = -ld * fd + 2j * math.pi * fd, -ls * fs + 2j * math.pi * fs
    wb = 2 * math.pi * band
    inside = np.abs(lam_d - 0.5j * wb) <= bm.DISK_RADIUS * wb
    assert 0 < lam_s.size == inside.sum()
    in_band = fd[inside] <= band
    assert 0 < in_band.sum() < in_band.size  # modes in the band and beyond it
    np.testing.assert_allclose(lam_s[in_band], lam_d[inside][in_band], rtol=1e-7)
    np.testing.assert_allclose(lam_s, lam_d[inside], rtol=1e-6)


def test_a_stability_point_on_pads_takes_the_band_above_the_dense_size(monkeypatch):
    # Stability.at on tilting pads: up to DENSE_MODES_MAX_DOF DOFs the dense pad modes (modes_at),
    # above them band_modes_with_pads (checked against the dense solution above); with every rotor sent
    # to the band, the same least stable mode (to 1e-7, the band's accuracy in its disk)
    import rotor_host.analyses.linear.stability as stab
    from rotor_host.analyses.linear import pad_modes as pm

    rotor = Rotor.from_toml(MODELS / "rotor_paper_5pad_lbp.toml")
    dense, _ = stab.Stability(rotor, "tilting_pad", {"n_theta": 24, "n_x": 4}).at(44.0)
    monkeypatch.setattr(stab, "DENSE_MODES_MAX_DOF", 0)
    monkeypatch.setattr(stab, "modes_at", lambda *a, **k: pytest.fail("the dense pad modes were solved"))
    banded_point, _ = stab.Stability(rotor, "tilting_pad", {"n_theta": 24, "n_x": 4}).at(44.0)
    assert banded_point.freq_hz[banded_point.least] == pytest.approx(dense.freq_hz[dense.least], rel=1e-7)
    assert banded_point.least_log_dec == pytest.approx(dense.least_log_dec, rel=1e-6, abs=1e-9)
