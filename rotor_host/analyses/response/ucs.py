"""``rotor-host ucs``: the undamped critical speed map.

**Criticals against support stiffness.** Every bearing replaced by the same isotropic spring k
[N/m] (no damping, no cross-coupling), the undamped critical speeds are the spin speeds Omega
at which the rotor can whirl forward synchronously: with q = Re(X e^{i Omega t}) in
M qdd + Omega G qd + (K + K_s) q = 0 (docs/conventions.md; ``Rotor``)::

    (K + K_s) X = Omega^2 (M - i G) X

solved for forward whirl only (``forward_basis``: Z = -i Y at every node, the tilt alike; an
axisymmetric rotor on isotropic supports keeps it), whose real positive eigenvalues Omega^2
are the forward synchronous criticals; the gyroscopic term stiffens them (a disk's polar
inertia); the backward ones (not excited by unbalance) are left out. The map draws the lowest ``n`` against k on log axes: at small k
they tend to the rigid-body modes on the springs (bounce sqrt(2k/m), rocking), at large k to
the criticals on rigid (pinned) supports.

**Bearings overlaid.** The bearings' direct stiffnesses K_yy, K_zz at their static equilibrium
at each speed of a range (``linear.stability.Stability``) are drawn as curves of speed against
stiffness; where such a curve crosses a critical's line the rotor on those bearings has an
undamped critical there. The mode shapes of the first criticals are drawn at those crossings
(with the bearings' mean direct stiffness; the damped, anisotropic answer is the Campbell
diagram's, ``rotor-host stability``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..computed_for import wrapped
from ...model.rotor import Rotor

DEFAULT_STIFFNESS = (1e5, 1e10)  # N/m: the support stiffness range of the map
DEFAULT_POINTS = 41
DEFAULT_CRITICALS = 4


def forward_basis(rotor: Rotor) -> np.ndarray:
    """T (n_dof x 2 n_nodes, complex): a forward synchronous whirl X = T u, u = (u_y, u_t) per node.
    Forward circles: Z = -i Y for the centre and, for the axis' tilt (dy/dx, dz/dx) =
    (theta_z, -theta_y), -Theta_y = -i Theta_z; so Y = u_y, Z = -i u_y, Theta_z = u_t,
    Theta_y = i u_t. An axisymmetric rotor on isotropic supports keeps this subspace."""
    T = np.zeros((rotor.n_dof, 2 * rotor.n_nodes), complex)
    for n in range(rotor.n_nodes):
        T[rotor.dof(n, "y"), 2 * n] = 1.0
        T[rotor.dof(n, "z"), 2 * n] = -1j
        T[rotor.dof(n, "tz"), 2 * n + 1] = 1.0
        T[rotor.dof(n, "ty"), 2 * n + 1] = 1j
    return T / math.sqrt(2.0)


def forward_criticals(rotor: Rotor, k_support: float, n: int = DEFAULT_CRITICALS) -> tuple[np.ndarray, np.ndarray]:
    """(speeds [Hz], shapes (n_dof x m)) of the lowest ``n`` forward synchronous undamped criticals
    with every bearing an isotropic spring ``k_support`` [N/m] (module docstring), solved in the
    forward subspace (``forward_basis``: T^H (K + K_s) T u = Omega^2 T^H (M - i G) T u); the
    shapes scaled so the largest y entry is 1."""
    import scipy.linalg

    T = forward_basis(rotor)
    K = T.conj().T @ (rotor.K + rotor.bearing_matrix(np.eye(2) * float(k_support))) @ T
    B = T.conj().T @ (rotor.M - 1j * rotor.G) @ T
    lam, vec = scipy.linalg.eig(K.real, B.real)  # both real symmetric: T's phases make them so
    ok = np.isfinite(lam) & (lam.real > 0.0) & (np.abs(lam.imag) <= 1e-9 * np.abs(lam))
    lam, vec = lam[ok].real, vec[:, ok]
    order = np.argsort(lam)[:n]
    X = T @ vec[:, order]
    ys = X[0::4]
    X = X / ys[np.argmax(np.abs(ys), axis=0), np.arange(X.shape[1])]
    return np.sqrt(lam[order]) / (2.0 * math.pi), X


@dataclass
class UCSMap:
    """``stiffness_N_m`` (the map's k), ``criticals_hz`` (len(k) x n, NaN where fewer), the bearings'
    direct stiffness ``bearing_k`` [N/m] (n_speeds x n_bearings x 2: K_yy, K_zz; NaN without
    equilibrium) at ``speeds_hz``, and the ``crossings`` (mode, speed, stiffness, shape)."""

    stiffness_N_m: np.ndarray
    criticals_hz: np.ndarray
    speeds_hz: list[float] = field(default_factory=list)
    bearing_k: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 2)))
    crossings: list[dict] = field(default_factory=list)
    meta: dict = field(default_factory=dict)


def critical_map(rotor: Rotor, stiffness, n: int = DEFAULT_CRITICALS) -> np.ndarray:
    """len(stiffness) x n forward criticals [Hz] (NaN where fewer than n)."""
    out = np.full((len(stiffness), n), np.nan)
    for i, k in enumerate(stiffness):
        s, _ = forward_criticals(rotor, k, n)
        out[i, :s.size] = s
    return out


def crossings(rotor: Rotor, m: UCSMap) -> list[dict]:
    """Where the bearings' mean direct stiffness against speed meets each critical's line: the
    speed Omega with crit_j(k_mean(Omega)) = Omega (linear between the speeds, the critical
    interpolated in log k), and the shape there."""
    if not m.speeds_hz:
        return []
    s = np.asarray(m.speeds_hz)
    kmean = np.nanmean(m.bearing_k.reshape(len(s), -1), axis=1) if m.bearing_k.size else np.full(len(s), np.nan)
    lk = np.log(m.stiffness_N_m)
    out = []
    for j in range(m.criticals_hz.shape[1]):
        line = m.criticals_hz[:, j]
        good = np.isfinite(line)
        if good.sum() < 2:
            continue
        gap = []
        for sp, k in zip(s, kmean):
            if k > 0.0 and m.stiffness_N_m[0] <= k <= m.stiffness_N_m[-1]:
                gap.append(np.interp(math.log(k), lk[good], line[good]) - sp)
            else:
                gap.append(np.nan)
        for a in range(len(s) - 1):
            ga, gb = gap[a], gap[a + 1]
            if np.isfinite(ga) and np.isfinite(gb) and (ga > 0.0 >= gb or ga < 0.0 <= gb):
                w = ga / (ga - gb)
                speed = s[a] + w * (s[a + 1] - s[a])
                k = math.exp((1 - w) * math.log(kmean[a]) + w * math.log(kmean[a + 1]))
                f, shapes = forward_criticals(rotor, k, j + 1)
                if f.size > j:
                    out.append({"mode": j + 1, "speed_hz": float(speed), "stiffness_N_m": k,
                                "critical_hz": float(f[j]), "shape_y": shapes[rotor.dof(0, "y")::4, j].real.tolist()})
    return sorted(out, key=lambda d: d["speed_hz"])


def bearing_stiffness(analysis, speeds_hz, log=None) -> np.ndarray:
    """n_speeds x n_bearings x 2 direct stiffnesses (K_yy, K_zz) [N/m] at each speed's equilibrium
    (NaN where there is none)."""
    from bearing_fmu.physics.statics import EquilibriumError

    from .unbalance import stability_coefficients

    coeff = stability_coefficients(analysis)
    out = np.full((len(speeds_hz), len(analysis.rotor.bearing_nodes), 2), np.nan)
    for i, s in enumerate(speeds_hz):
        try:
            K, _ = coeff(s)
        except EquilibriumError as exc:
            if log is not None:
                log(f"{s:g} Hz: {exc}")
            continue
        out[i] = np.stack([K[:, 0, 0], K[:, 1, 1]], axis=1)
    return out


def plot_map(m: UCSMap, rotor: Rotor, path, inputs: str = "") -> Path:
    from ..plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 6.5))
    for j in range(m.criticals_hz.shape[1]):
        ax.loglog(m.stiffness_N_m, m.criticals_hz[:, j], "-", label=f"critical {j + 1}")
    styles = ("-", "--", ":", "-.")
    for b in range(m.bearing_k.shape[1] if m.bearing_k.ndim == 3 else 0):
        for d, name in ((0, "K_yy"), (1, "K_zz")):
            ax.loglog(m.bearing_k[:, b, d], np.asarray(m.speeds_hz), styles[b % 4], color="k" if d else "0.5",
                      lw=1.2, label=f"bearing {b + 1} {name} at speed")
    for c in m.crossings:
        ax.plot(c["stiffness_N_m"], c["speed_hz"], "o", mfc="none", color="tab:red")
        ax.annotate(f"{c['speed_hz']:.1f} Hz", (c["stiffness_N_m"], c["speed_hz"]), textcoords="offset points",
                    xytext=(6, -10), fontsize=8, color="tab:red")
    ax.set_xlabel("support stiffness [N/m] (each bearing, isotropic)")
    ax.set_ylabel("undamped critical speed [Hz]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Undamped critical speed map (forward synchronous)\n{wrapped(inputs, 110)}", fontsize=9)
    return save_figure(fig, path)


def plot_shapes(m: UCSMap, rotor: Rotor, path, inputs: str = "") -> Path:
    from ..plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    x = rotor.node_x * 1e3
    for c in m.crossings:
        ax.plot(x, c["shape_y"], "o-", ms=3, label=f"critical {c['mode']} at {c['speed_hz']:.1f} Hz "
                                                  f"(k {c['stiffness_N_m']:.3g} N/m)")
    for n in rotor.bearing_nodes:
        ax.axvline(x[n], color="k", lw=0.8, ls="--")
    for d in rotor.disks:
        ax.axvline(x[d.node], color="tab:brown", lw=2, alpha=0.4)
    ax.axhline(0.0, color="0.5", lw=0.5)
    ax.set_xlabel("axial position [mm] (dashed: bearings, brown: disks)")
    ax.set_ylabel("y displacement (largest 1)")
    ax.grid(True, alpha=0.3)
    if m.crossings:
        ax.legend(fontsize=8)
    ax.set_title(f"Mode shapes of the undamped criticals on the bearings\n{wrapped(inputs, 110)}", fontsize=9)
    return save_figure(fig, path)


DEFAULT_SPEEDS_HZ = (5.0, 100.0, 5.0)  # the bearings' overlay: START, STOP, STEP [Hz]


def build(rotor: Rotor, stiffness_n_m, points: int, n: int, speeds_hz, bearing_k) -> UCSMap:
    """The map over ``points`` log-spaced stiffnesses in ``stiffness_n_m`` (min, max) [N/m], the
    bearings' direct stiffness ``bearing_k`` (n_speeds x n_bearings x 2) at ``speeds_hz`` and the crossings."""
    lo, hi = (float(v) for v in stiffness_n_m)
    if not (0.0 < lo < hi and math.isfinite(hi)):
        raise ValueError(f"--stiffness-n-m {lo:g}:{hi:g}: expected MIN:MAX with 0 < MIN < MAX [N/m]")
    k = np.geomspace(lo, hi, int(points))
    m = UCSMap(k, critical_map(rotor, k, n), list(speeds_hz), np.asarray(bearing_k, float))
    m.crossings = crossings(rotor, m)
    return m


def ucs(rotor_file, *, stiffness_n_m=DEFAULT_STIFFNESS, points: int = DEFAULT_POINTS, n: int = DEFAULT_CRITICALS,
        speeds_hz=None, internal: str = "reynolds", options=None, static_loads=(), T_supply_K=None, log=None) -> UCSMap:
    """The map of the rotor file with its bearings' stiffness overlaid (module docstring)."""
    from ..linear.stability import Stability
    from ..linear.inputs import check_speeds, read_rotor
    from ..computed_for import title_line

    rotor, loads = read_rotor(rotor_file, static_loads)
    if speeds_hz is None:
        a, b, step = DEFAULT_SPEEDS_HZ
        speeds_hz = list(np.arange(a, b + step / 2, step))
    speeds = check_speeds(speeds_hz)
    analysis = Stability(rotor, internal, options, loads, where=str(rotor_file), T_supply_K=T_supply_K)
    m = build(rotor, stiffness_n_m, points, n, speeds, bearing_stiffness(analysis, speeds, log))
    m.meta = {"rotor": rotor.name or Path(rotor_file).stem, "rotor_file": str(rotor_file),
              "internal": analysis.internal, "options": analysis.options,
              "inputs": title_line(rotor, rotor_file, analysis.internal, analysis.options, T_supply_K)}
    return m


def to_json(m: UCSMap) -> dict:
    def clean(a):
        return [[None if not np.isfinite(v) else float(v) for v in row] for row in np.asarray(a)]

    return {"stiffness_N_m": m.stiffness_N_m.tolist(), "criticals_hz": clean(m.criticals_hz),
            "speeds_hz": list(m.speeds_hz),
            "bearing_Kyy_N_m": clean(m.bearing_k[:, :, 0]), "bearing_Kzz_N_m": clean(m.bearing_k[:, :, 1]),
            "crossings": m.crossings, **m.meta}


def markdown(m: UCSMap, inputs: list[str], figures=()) -> str:
    from ..tables import markdown_table

    lines = [f"# Undamped critical speed map: {m.meta.get('rotor', '')}", "", "## Inputs", ""]
    lines += [f"- {x}" for x in inputs] + [""]
    lines += ["Forward synchronous undamped criticals with every bearing an isotropic spring k, gyroscopics "
              "included (docs/response.md).", ""]
    idx = np.unique(np.linspace(0, len(m.stiffness_N_m) - 1, 9).round().astype(int))
    rows = [{"k_N_m": f"{m.stiffness_N_m[i]:.3g}", **{f"crit {j + 1} Hz": "-" if not np.isfinite(v) else f"{v:.2f}"
                                                       for j, v in enumerate(m.criticals_hz[i])}} for i in idx]
    lines += [markdown_table(rows, [(c, c, "") for c in rows[0]]), "", "## On the bearings", ""]
    if m.crossings:
        rows = [{"critical": c["mode"], "speed_hz": f"{c['speed_hz']:.2f}", "k_N_m": f"{c['stiffness_N_m']:.3g}"}
                for c in m.crossings]
        lines += ["Where the bearings' mean direct stiffness at speed meets a critical's line:", "",
                  markdown_table(rows, [(c, c, "") for c in rows[0]]), ""]
    else:
        lines += ["The bearings' stiffness curve crosses no critical's line in the speeds computed.", ""]
    if figures:
        lines += ["## Figures", ""] + [f"![{f.stem}]({f.name})" for f in figures] + [""]
    return "\n".join(lines)


def command(*, rotor_file, stiffness_n_m=DEFAULT_STIFFNESS, points: int = DEFAULT_POINTS,
            criticals: int = DEFAULT_CRITICALS, speeds_hz=None, internal: str = "reynolds", data_files=None, grid=None,
            static_load=(), supply_c=None, out="out", no_plots: bool = False) -> int:
    """``rotor-host ucs``: writes ucs.json, ucs.md, ucs_map.png and ucs_modes.png into ``out``."""
    from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

    from ..linear.inputs import internal_options
    from ..computed_for import bearing_lines, internal_words

    out = ensure_writable(out)
    T = None if supply_c is None else supply_c + 273.15
    m = ucs(rotor_file, stiffness_n_m=stiffness_n_m, points=points, n=criticals, speeds_hz=speeds_hz,
            internal=internal, options=internal_options(internal, data_files, grid), static_loads=static_load,
            T_supply_K=T, log=lambda msg: print(f"  {msg}"))
    rotor = Rotor.from_toml(rotor_file)
    files = [] if no_plots else [plot_map(m, rotor, out / "ucs_map.png", m.meta["inputs"]),
                                 plot_shapes(m, rotor, out / "ucs_modes.png", m.meta["inputs"])]
    inputs = [f"rotor: {rotor_file} ({m.meta['rotor']})", *bearing_lines(rotor, rotor_file),
              f"internal (bearing stiffness overlay): {internal_words(m.meta['internal'], m.meta['options'])}"]
    files = [write_json(out / "ucs.json", to_json(m)), write_text(out / "ucs.md", markdown(m, inputs, files)), *files]
    print(f"computed for: {m.meta['inputs']}")
    print(f"{m.meta['rotor']}: criticals on rigid supports ({m.stiffness_N_m[-1]:.3g} N/m): "
          + ", ".join(f"{v:.2f}" for v in m.criticals_hz[-1] if np.isfinite(v)) + " Hz")
    for c in m.crossings:
        print(f"critical {c['mode']} on the bearings: {c['speed_hz']:.2f} Hz (k {c['stiffness_N_m']:.3g} N/m)")
    print("wrote " + ", ".join(str(f) for f in files))
    return 0


__all__ = ["ucs", "build", "to_json", "markdown", "command", "DEFAULT_SPEEDS_HZ", "forward_basis", "forward_criticals", "critical_map", "crossings", "bearing_stiffness", "UCSMap", "plot_map", "plot_shapes",
           "DEFAULT_STIFFNESS", "DEFAULT_POINTS", "DEFAULT_CRITICALS"]
