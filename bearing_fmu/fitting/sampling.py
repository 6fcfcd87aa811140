"""Training data for a surrogate fit: designed samples over a declared domain or in a tube
about recorded orbits, the truth's forces at them, a co-simulation time series from an
.npz, and the fitted domain a time series spans."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..physics.params import BearingParams
from ..surrogates.surrogate import Domain


def designed_samples(internal, y0: float, z0: float, omega: float, ecc_max: float, v_max: float, n: int,
                     seed: int = 0, *, radius: float | None = None):
    """n states over a declared domain and their forces from ``internal`` (no rotor run).

    Positions: uniform over a disc -- of radius ``ecc_max`` (in CR) about the bearing centre
    when ``radius`` is None, else of ``radius`` (in CR) about (y0, z0) intersected with the
    eccentricity bound |(y, z)| <= ecc_max CR. Velocities: uniform over the disc
    |(vy, vz)| <= v_max * omega * CR. Drawn as a Latin hypercube (scipy.stats.qmc) in
    (r^2, angle) of each disc; states beyond the eccentricity bound are discarded.
    Returns (states (n, 4) [m, m/s], forces (n, 2) [N], domain: Domain).
    """
    from scipy.stats import qmc

    p = internal.params
    cr, vs = p.CR, abs(omega) * p.CR
    if not 0 < ecc_max < 1:
        raise ValueError(f"designed_samples: ecc_max = {ecc_max!r} must lie in (0, 1)")
    if v_max < 0:
        raise ValueError(f"designed_samples: v_max = {v_max!r} must be >= 0")
    if radius is None:
        cy, cz, rad = 0.0, 0.0, ecc_max
    else:
        cy, cz, rad = y0 / cr, z0 / cr, float(radius)
        if math.hypot(cy, cz) > ecc_max:
            raise ValueError(f"designed_samples: the expansion point (eccentricity {math.hypot(cy, cz):.3f}) "
                             f"lies beyond ecc_max = {ecc_max}")
    sampler = qmc.LatinHypercube(d=4, seed=seed)
    pts = []
    have = 0
    m = n
    while have < n:
        s = sampler.random(max(m, 16))
        r = rad * np.sqrt(s[:, 0])
        a = 2 * np.pi * s[:, 1]
        qy, qz = cy + r * np.cos(a), cz + r * np.sin(a)
        ok = np.hypot(qy, qz) <= ecc_max
        rv = v_max * np.sqrt(s[:, 2])
        b = 2 * np.pi * s[:, 3]
        blk = np.column_stack([qy * cr, qz * cr, rv * np.cos(b) * vs, rv * np.sin(b) * vs])[ok]
        pts.append(blk)
        have += len(blk)
        m = int(1.3 * (n - have) * len(s) / max(len(blk), 1)) + 16
    states = np.concatenate(pts)[:n]
    forces = sample_forces(internal, states, omega)
    u = np.column_stack([(states[:, 0] - y0) / cr, (states[:, 1] - z0) / cr, states[:, 2] / vs, states[:, 3] / vs])
    domain = Domain(
        ecc_max=float(ecc_max),
        pos_center=(cy - y0 / cr, cz - z0 / cr),
        pos_radius=float(rad),
        v_max=float(v_max),
        box_lo=tuple(float(v) for v in u.min(axis=0)),
        box_hi=tuple(float(v) for v in u.max(axis=0)),
    )
    return states, forces, domain


def tube_samples(internal, orbit_states, y0: float, z0: float, omega: float, radius: float, n: int,
                 seed: int = 0, *, ecc_max: float | None = None):
    """n states in a tube about recorded orbit states and their forces from ``internal``.

    Each sample is a randomly chosen orbit state plus a displacement uniform in the 4-D ball
    of ``radius`` in scaled units (positions in CR, velocities in omega CR: the units of the
    surrogate's u); samples beyond eccentricity ``ecc_max`` (default: the orbit's largest) are
    drawn again. Returns (states (n, 4) [m, m/s], forces (n, 2) [N])."""
    p = internal.params
    cr, vs = p.CR, abs(omega) * p.CR
    orbit = np.asarray(orbit_states, float).reshape(-1, 4)
    if radius <= 0 or not len(orbit):
        raise ValueError(f"tube_samples: radius = {radius!r} must be > 0 and the orbit non-empty")
    ecc_orbit = float(np.max(np.hypot(orbit[:, 0], orbit[:, 1])) / cr)
    ecc_max = min(ecc_orbit if ecc_max is None else float(ecc_max), 0.999)
    rng = np.random.default_rng(seed)
    scale = np.array([cr, cr, vs, vs])
    out = []
    have = 0
    while have < n:
        m = 2 * (n - have) + 16
        base = orbit[rng.integers(0, len(orbit), m)]
        d = rng.normal(size=(m, 4))
        d *= (radius * rng.uniform(size=m) ** 0.25 / np.linalg.norm(d, axis=1))[:, None]
        st = base + d * scale
        st = st[np.hypot(st[:, 0], st[:, 1]) <= ecc_max * cr]
        out.append(st)
        have += len(st)
    states = np.concatenate(out)[:n]
    return states, sample_forces(internal, states, omega)


def sample_forces(internal, states, omega: float) -> np.ndarray:
    """The internal's force [N] at each state (rows y, z, vy, vz). An interrupt is raised again
    with the pairs computed so far as its ``samples`` attribute (states, forces)."""
    states = np.asarray(states, float)
    out = np.empty((len(states), 2))
    i = 0
    try:
        for i, (y, z, vy, vz) in enumerate(states):
            out[i] = internal.force(y, z, vy, vz, omega)
    except KeyboardInterrupt as exc:
        exc.samples = (states[:i].copy(), out[:i].copy())
        raise
    if not np.all(np.isfinite(out)):
        raise ValueError("training forces contain non-finite values")
    return out


def load_npz(path: str | Path):
    """Training time series from a co-simulation: an .npz with arrays y, z, vy, vz, Fy, Fz
    (one bearing, equal lengths). Returns (states (M, 4), forces (M, 2))."""
    from ..io.npz import read_npz

    path = Path(path)
    keys = ("y", "z", "vy", "vz", "Fy", "Fz")
    data = read_npz(path, f"a training time series (.npz with arrays {', '.join(keys)})")
    missing = [k for k in keys if k not in data]
    if missing:
        raise KeyError(f"training file {str(path)!r}: missing array(s) {', '.join(missing)}; "
                       f"expected {', '.join(keys)}, found {', '.join(data) or 'none'}")
    arrs = [np.asarray(data[k], float).ravel() for k in keys]
    n = {len(a) for a in arrs}
    if len(n) != 1:
        raise ValueError(f"training file {str(path)!r}: arrays have different lengths "
                         + ", ".join(f"{k}={len(a)}" for k, a in zip(keys, arrs)))
    for k, a in zip(keys, arrs):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"training file {str(path)!r}: array {k} has non-finite values")
    return np.column_stack(arrs[:4]), np.column_stack(arrs[4:])


def domain_from_data(states, y0, z0, params: BearingParams, omega: float, margin: float = 0.0) -> Domain:
    """Domain covering time-series states: discs about the expansion point and the box."""
    cr, vs = params.CR, abs(omega) * params.CR
    s = np.asarray(states, float)
    u = np.column_stack([(s[:, 0] - y0) / cr, (s[:, 1] - z0) / cr, s[:, 2] / vs, s[:, 3] / vs])
    f = 1.0 + margin
    return Domain(
        ecc_max=float(min(np.max(np.hypot(s[:, 0], s[:, 1])) / cr * f, 0.9999)),
        pos_center=(0.0, 0.0),
        pos_radius=float(np.max(np.hypot(u[:, 0], u[:, 1])) * f),
        v_max=float(np.max(np.hypot(u[:, 2], u[:, 3])) * f),
        box_lo=tuple(float(v) for v in u.min(axis=0)),
        box_hi=tuple(float(v) for v in u.max(axis=0)),
    )


__all__ = ["designed_samples", "tube_samples", "sample_forces", "load_npz", "domain_from_data"]
