"""The checks behind docs/studies/2026-11-24-second-machine.md: the second machine in rotor_host/bundled/
(Friswell, Penny, Garvey & Lees, Dynamics of Rotating Machines, CUP 2010, Example 5.9.6:
rotor_host/bundled/rotor_friswell.toml on rotor_host/bundled/bearing_friswell.toml) against its sources.

    python benchmarks/second_machine.py                      # statics, modes, bearing, stability (seconds)
    python benchmarks/second_machine.py --run25 out/friswell_25hz_map.npz --run40 out/friswell_40hz_map.npz

Prints: the rotor's mass and weight split; its natural frequencies on the 1 MN/m bearings of
Examples 5.9.1 and 5.9.5 against ROSS's notebooks of those examples; the bearing at the book's
Example 5.5.1 (1500 rev/min, 525 N) against the book's short-bearing coefficients, with the
finite-length effect against L/D; the first critical speed and the linear stability threshold
on the Reynolds bearings (and on the book's short-bearing model). With run files: the 1x orbit of
a run (after its transient) against the linear unbalance response, and the growth rate of the
sub-synchronous whirl against the linear log decrement.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this checkout's packages

from bearing_fmu.physics.params import BearingParams  # noqa: E402
from bearing_fmu.physics.solver.reynolds import Reynolds  # noqa: E402
from bearing_fmu.physics.solver.shortbearing import short_bearing_coefficients, short_bearing_eccentricity  # noqa: E402
from bearing_fmu.physics.statics import equilibrium, linearize  # noqa: E402
from rotor_host.model.rotor import Rotor  # noqa: E402

ROTOR = ROOT / "rotor_host" / "bundled" / "rotor_friswell.toml"
G = 9.81
RPM = math.pi / 30.0  # rad/s per rev/min
# Friswell et al. (2010) Example 5.5.1 (p. 200): K [N/m], C [N s/m], (u, v) = (y, z)
BOOK_K = np.array([[12.81, 16.39], [-25.06, 8.815]]) * 1e6
BOOK_C = np.array([[232.9, -81.92], [-81.92, 294.9]]) * 1e3
# ROSS notebooks (github.com/petrobras/ross at 631a249, docs/user_guide/): printed outputs
ROSS_591 = {2000: [86.04146288, 87.24209546, 263.2823758, 284.80108656, 657.49926135],  # example_3, rad/s
            4000: [85.389467, 87.7958637, 251.78460413, 294.71333087, 600.17936195, 827.07536192]}
ROSS_595_0RPM = [834.32208726, 2890.6574236, 8223.63465095]  # example_6, |lambda| in rev/min


def bearing_loads(rotor: Rotor) -> list[tuple[float, float]]:
    """(Wy, Wz) [N] on each journal: the reactions of the rotor on rigid supports under weight."""
    k = 1e13
    q = np.linalg.solve(rotor.K + rotor.bearing_matrix(np.eye(2) * k), rotor.weight_vector(G))
    return [(0.0, k * q[rotor.dof(n, "z")]) for n in rotor.bearing_nodes]


def coefficients(rotor, loads, f_hz, model="reynolds", grid=None):
    """Per-bearing Lund K, C [N/m, N s/m] at f_hz under loads: Reynolds or short bearing."""
    w = 2 * math.pi * f_hz
    Ks, Cs = [], []
    for p, load in zip(rotor.bearings, loads):
        if model == "short":
            eps, phi = short_bearing_eccentricity(p, -load[1], w)
            K, C = short_bearing_coefficients(p, eps * p.CR * math.sin(phi), -eps * p.CR * math.cos(phi), w)
        else:
            r = Reynolds(p, *(grid or ()))
            K, C = linearize(r, *equilibrium(r, load, w), w)
        Ks.append(K)
        Cs.append(C)
    return np.array(Ks), np.array(Cs)


def least_stable(rotor, loads, f_hz, **kw):
    """(log decrement, frequency [Hz]) of the least stable mode at f_hz on the linearised films."""
    K, C = coefficients(rotor, loads, f_hz, **kw)
    fr, ld, _ = rotor.modes(2 * math.pi * f_hz, K, C, n=8)
    i = int(np.argmin(ld))
    return ld[i], fr[i]


def report_statics_and_modes(rotor):
    loads = bearing_loads(rotor)
    print(f"mass {rotor.mass:.3f} kg, weight {rotor.mass * G:.2f} N; bearing loads "
          + ", ".join(f"{-w[1]:.2f} N" for w in loads) + " (book: 525 N each)")
    for rpm, ref in ROSS_591.items():
        f = rotor.natural_frequencies(1e6, speed=rpm * RPM, n=len(ref)) * 2 * math.pi
        print(f"Ex. 5.9.1, 1 MN/m, {rpm} rev/min [rad/s]: "
              + ", ".join(f"{a:.3f} ({100 * (a / b - 1):+.4f} %)" for a, b in zip(f, ref)))
    fr, ld, _ = rotor.modes(0.0, np.eye(2) * 1e6, np.eye(2) * 3e3, n=6)
    zeta = ld / np.sqrt(4 * math.pi**2 + ld**2)
    wn = fr / np.sqrt(1 - zeta**2) * 60  # |lambda| in rev/min, as ROSS's wn
    print("Ex. 5.9.5, 1 MN/m + 3 kN s/m, 0 rev/min, |lambda| [rev/min]: "
          + ", ".join(f"{a:.2f} ({100 * (a / b - 1):+.4f} %)" for a, b in zip(wn[::2], ROSS_595_0RPM)))
    return loads


def report_bearing(params: BearingParams):
    w = 1500 * RPM
    eps_s, _ = short_bearing_eccentricity(params, 525.0, w)
    print(f"Ex. 5.5.1, 1500 rev/min, 525 N: short bearing eps {eps_s:.4f}")
    for grid in ((128, 16), (256, 32)):
        for cav in ("reynolds", "gumbel"):
            r = Reynolds(params, *grid, cavitation=cav)
            y, z = equilibrium(r, (0.0, -525.0), w)
            K, C = linearize(r, y, z, w)
            eps = math.hypot(y, z) / params.CR
            print(f"  Reynolds {grid[0]} x {grid[1]} {cav:8s}: eps {eps:.4f} ({100 * (eps / eps_s - 1):+.2f} %), "
                  f"attitude {math.degrees(math.atan2(y, -z)):.2f} deg")
            print("    K/book - 1 [%]: " + " ".join(f"{100 * v:+.2f}" for v in (K / BOOK_K - 1).ravel())
                  + "   C/book - 1 [%]: " + " ".join(f"{100 * v:+.2f}" for v in (C / BOOK_C - 1).ravel()))
    for ld in (0.1, 0.2, 0.3, 0.5):  # the same Ocvirk eccentricity at each L/D: W scales as L^3
        p = BearingParams(D=params.D, L=params.D * ld, CR=params.CR, mu=params.mu)
        W = 525.0 * (ld / 0.3) ** 3
        devs = []
        for cav in ("gumbel", "reynolds"):
            e = math.hypot(*equilibrium(Reynolds(p, cavitation=cav), (0.0, -W), w)) / p.CR
            devs.append(f"{cav} {100 * (e / eps_s - 1):+.2f} %")
        print(f"  L/D {ld}: eccentricity against short-bearing theory: " + ", ".join(devs))


def report_stability(rotor, loads):
    def forward_bending_minus_speed(f):
        K, C = coefficients(rotor, loads, f)
        fr, ld, sh = rotor.modes(2 * math.pi * f, K, C, n=8)
        disk = rotor.disks[-1].node
        # the lowest lightly damped mode whirling forward at the heavier disk: the first bending mode
        return min(a for i, (a, d) in enumerate(zip(fr, ld)) if d < 0.5 and rotor.whirl(sh[:, i], disk) > 0) - f
    fc = brentq(forward_bending_minus_speed, 10.0, 25.0, xtol=1e-3)
    print(f"first critical speed (forward bending mode = 1x): {fc:.2f} Hz = {fc * 60:.0f} rev/min")
    for label, kw, ld in (("Reynolds 128 x 16", {}, loads), ("Reynolds 256 x 32", {"grid": (256, 32)}, loads),
                          ("short bearing, these loads", {"model": "short"}, loads),
                          ("short bearing, 525 N each (the book's)", {"model": "short"}, [(0.0, -525.0)] * 2)):
        f = brentq(lambda s: least_stable(rotor, ld, s, **kw)[0], 25.0, 45.0, xtol=1e-3)
        print(f"threshold, {label}: {f:.2f} Hz = {f * 60:.0f} rev/min, whirl {least_stable(rotor, ld, f, **kw)[1]:.2f} Hz")
    for f in (25.0, 33.0, 37.0, 40.0, 50.0):
        K, C = coefficients(rotor, loads, f)
        fr, ld, _ = rotor.modes(2 * math.pi * f, K, C, n=8)
        sub = [(d, a) for a, d in zip(fr, ld) if a < 0.8 * f and d < 0.5]  # the lightly damped sub-synchronous modes
        d, a = min(sub)
        print(f"  {f:.0f} Hz: least stable sub-synchronous mode {a:.2f} Hz, log dec {d:+.4f}, growth rate {-d * a:+.3f} 1/s; "
              f"least stable of all: {fr[np.argmin(ld)]:.2f} Hz, log dec {ld.min():+.4f}")


def report_unbalance(rotor, loads, npz, node=3, mass_radius=0.001):
    """1x part of the last 2 s of a run against the linear unbalance response (mass_radius [kg m]
    on 1-based ``node``, force m r W^2 (cos, sin)(W t))."""
    d = np.load(npz)
    f = float(d["speed_hz"][-1])
    W = 2 * math.pi * f
    K, C = coefficients(rotor, loads, f)
    F = np.zeros(rotor.n_dof, complex)
    F[rotor.dof(node - 1, "y")] = mass_radius * W**2
    F[rotor.dof(node - 1, "z")] = -1j * mass_radius * W**2  # sin(W t) = Re(-i e^{i W t})
    X = np.linalg.solve(-W**2 * rotor.M + 1j * W * (rotor.C + rotor.bearing_matrix(C) + W * rotor.G)
                        + rotor.K + rotor.bearing_matrix(K), F)
    t = d["t"]
    m = t > t[-1] - 2.0
    A = np.column_stack([np.cos(W * t[m]), np.sin(W * t[m]), np.ones(m.sum())])
    print(f"{npz}: 1x orbit over the last 2 s against the linear unbalance response at {f:g} Hz")
    for k, n in enumerate(d["nodes"]):
        row = []
        for key in ("y", "z"):
            c = np.linalg.lstsq(A, d[key][m, k], rcond=None)[0]
            sim, lin = complex(c[0], -c[1]), X[rotor.dof(int(n) - 1, key)]
            row.append(f"{key} {abs(sim) * 1e6:.3f} um vs {abs(lin) * 1e6:.3f} um ({100 * (abs(sim) / abs(lin) - 1):+.2f} %, "
                       f"{math.degrees(np.angle(sim / lin)):+.2f} deg)")
        print(f"  node {int(n)}: " + "; ".join(row))


def report_growth(npz, node=3, ecc_linear=0.45):
    """Growth rate [1/s] of the largest sub-synchronous line of a node's orbit (1 s windows every
    0.25 s), fitted while the bearings stay below ecc_linear (the linear part)."""
    d = np.load(npz)
    t, f = d["t"], float(d["speed_hz"][-1])
    dt = t[1] - t[0]
    k = list(d["nodes"]).index(node)
    sig = (d["y"][:, k] - d["y"][0, k]) + 1j * (d["z"][:, k] - d["z"][0, k])
    win, hop = int(round(1.0 / dt)), int(round(0.25 / dt))
    fq = np.fft.fftfreq(win, dt)
    band = (fq > 5.0) & (fq < 0.8 * f)
    rows = []
    for s in range(0, len(t) - win, hop):
        sp = np.abs(np.fft.fft(sig[s:s + win] * np.hanning(win))) * band
        mid = t[s + win // 2]
        rows.append((mid, sp.max(), d["eccentricity"][s:s + win].max()))
    tm, amp, ecc = map(np.array, zip(*rows))
    ok = (ecc < ecc_linear) & (tm > 0.75)
    rate = np.polyfit(tm[ok], np.log(amp[ok]), 1)[0]
    m = t > t[-1] - 2.0
    ang = np.unwrap(np.angle(sig[m] - sig[m].mean()))
    whirl = np.polyfit(t[m], ang, 1)[0] / (2 * math.pi)
    print(f"{npz}: {f:g} Hz, sub-synchronous growth rate {rate:+.3f} 1/s over {tm[ok].min():.2f}-{tm[ok].max():.2f} s; "
          f"whirl over the last 2 s {whirl:+.2f} Hz ({whirl / f:.2f}x); max eccentricity {d['eccentricity'].max():.3f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--run25", help="a run of friswell_25hz (npz), best 8 s long: its 1x orbit against the linear response")
    ap.add_argument("--run40", nargs="*", default=[], help="runs above the threshold (npz): their whirl growth rates")
    args = ap.parse_args(argv)
    rotor = Rotor.from_toml(ROTOR)
    loads = report_statics_and_modes(rotor)
    report_bearing(rotor.bearings[0])
    report_stability(rotor, loads)
    if args.run25:
        report_unbalance(rotor, loads, args.run25)
    for npz in args.run40:
        report_growth(npz)


if __name__ == "__main__":
    main()
