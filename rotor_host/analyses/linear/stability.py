"""Campbell diagram and stability threshold of a rotor on its hydrodynamic bearings.

At each speed of a range (``rotor-host stability ROTOR.toml --speeds-hz 10:70:1``):

1. the static equilibrium of the rotor on its nonlinear bearings, under its weight and any
   static point loads, as a scene starts (``run.bearing_loads``, ``run.static_start``,
   ``equilibrium.static_equilibrium``); from the second speed on, Newton starts from the
   previous speed's equilibrium (continuation; a fresh start if that fails);
2. each bearing linearised there with the internal's own analytic Jacobian
   (``bearing_fmu.physics.statics.linearize``: Lund's K = -dF/dq, C = -dF/dv); an internal whose
   coefficients depend on the whirl frequency (``Capabilities.whirl_reduced``: tilting pads, their
   tilts condensed) reports them reduced at the synchronous whirl, omega (API 684's practice);
   its modes take the pads' own coordinates into the eigenproblem instead (``pad_modes``: every
   mode with the pads at its own frequency);
3. the damped eigenvalues of the rotor with those bearings, its shaft damping and the
   gyroscopic term (``Rotor.modes``): damped frequency, logarithmic decrement
   delta = -2 pi Re(lam) / Im(lam) (negative: the mode grows) and complex shape, and the whirl
   direction of each shape (``Rotor.whirl``, at the node where the mode moves most).

The threshold of instability is the first speed at which the least stable mode's log
decrement crosses zero (ranked among the modes up to 2 x the top speed: ``modal``), found to
1e-4 Hz by Brent's method between the two speeds of the
range that bracket it (each evaluation is steps 1-3 again, from the equilibrium at the lower
speed); the whirl frequency is that mode's damped frequency there. The critical speeds are
where the 1x line crosses a damped natural frequency that can ring (``modal.critical_speeds``).
How an engineer reads the figures: docs/campbell.md.

Only the bearings are nonlinear here; the rotor is the linear FE model of ``rotor_host.model.rotor``.
The internals are built through the registry (``bearing_fmu.internals.create``) once for
the whole sweep: ``reynolds`` (any bearing; a fraction of a millisecond per force and
Jacobian at 128 x 16) or ``map`` (a force map of the bearing's L/D; microseconds). For the
paper rotor the eigenvalues cost more than the equilibria (docs/studies/2026-11-24-stability-threshold.md).
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from bearing_fmu.internals import registry
from bearing_fmu.internals.registry import Context
from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.io.interrupts import note_kept
from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

from ..computed_for import title_line
from ...model.band_modes import DENSE_MODES_MAX_DOF, band_modes, band_modes_with_pads
from ...model.rotor import Rotor
from .inputs import (check_speeds, check_supply, check_top_speed, internal_options, read_rotor,
                     refuse_unsupported)
from .pad_modes import modes_at, pad_blocks
from .stability_report import markdown, to_json
from .stability_result import DEFAULT_MODES, SpeedPoint, StabilityResult, Threshold, direction
from .modal import RANK_UP_TO, band_hz, critical_speeds, split_crossings

THRESHOLD_XTOL_HZ = 1e-4  # Brent's tolerance on the threshold speed [Hz]


# ----------------------------------------------------------------------------- the analysis

class Stability:
    """The rotor on its bearings, ready to be evaluated at any speed (``at``) or swept (``sweep``).

    rotor        : a Rotor with at least one bearing
    internal     : a registered internal valid at every speed and load (its capability
                   ``any_state``: the Reynolds solver, the force map, or one registered so)
    options      : that internal's options ({"n_theta": 64, "n_x": 8}, {"map": FILE})
    static_loads : (node0, Fy, Fz) point loads [N] on 0-based nodes, besides the weight
    g            : gravity [m/s^2] (the weight is applied as in a scene: -g M u_z)
    T_supply_K   : oil supply temperature [K]: at each speed every bearing runs at the viscosity of
                   its film's effective temperature under its static load (``physics.thermal``,
                   quasi-static; its internal's force scaled by mu_eff / mu, exact: F ~ mu); every
                   bearing then needs an [oil] table. None: the bearings' own (isoviscous) mu
    """

    def __init__(self, rotor: Rotor, internal: str = "reynolds", options: dict | None = None,
                 static_loads=(), g: float | None = None, where: str = "", T_supply_K: float | None = None):
        from ...scenes.run import bearing_loads
        from ...scenes.scene import G

        if not rotor.bearing_nodes:
            raise ValueError(f"{where or 'rotor'}: the rotor has no bearings; a stability analysis needs at "
                             "least one [[bearings]] entry (node, bearing file)")
        spec = registry.get(internal)
        if not spec.can.any_state:
            raise ValueError(f"internal {spec.name!r} answers only about the operating point it was made for; a "
                             "stability analysis moves the equilibrium with the speed and needs an internal valid "
                             f"at every speed and load: {', '.join(registry.having(any_state=True))}")
        self.rotor = rotor
        self.internal = spec.name
        self.options = dict(options or {})
        self.f_static = rotor.weight_vector(G if g is None else g) + rotor.point_load_vector(static_loads)
        self.loads = bearing_loads(rotor, self.f_static)
        self.pairs = [(rotor.dof(n, "y"), rotor.dof(n, "z")) for n in rotor.bearing_nodes]
        self.names = [f"bearing {k + 1} (node {n + 1})" for k, n in enumerate(rotor.bearing_nodes)]
        self.where = where or "rotor"
        refuse_unsupported(rotor, self.f_static, self.pairs, self.names, self.where)  # before any solve
        t0 = time.perf_counter()
        # a feed along the line of thickest film moves with each speed's equilibrium: placed per speed
        # (``at``), the plain bore until then (the same kernels, for the warm-up)
        self.unplaced = [k for k, p in enumerate(rotor.bearings) if p.geometry.feed_unplaced]
        self.T_supply_K = None if T_supply_K is None else float(T_supply_K)
        # the effective temperature from the run's own internal where the Reynolds solver cannot take the bore
        self.own_film = spec.can.pads
        if self.T_supply_K is not None:
            check_supply(rotor, self.T_supply_K, where or "rotor", "the supply temperature")
        self.internals = [self._create(k, p.with_geometry(Geometry()) if k in self.unplaced else p)
                          for k, p in enumerate(rotor.bearings)]
        self.own_dofs = spec.can.whirl_reduced  # bearings' own coordinates (tilting pads) in the eigenproblem
        self._warm_up()
        self.setup_s = time.perf_counter() - t0
        self.timings = {"equilibrium": 0.0, "eigen": 0.0}
        self.band_hz = math.inf  # the ranking band of ``at``'s points; ``sweep`` sets it from its top speed

    def _create(self, k: int, params):
        """Bearing k's internal (at mu_eff with a supply temperature: ``ViscosityScaled``)."""
        w = self.loads[k]
        internal = registry.create(self.internal, params, self.options, Context(load=(float(w[0]), float(w[1]))),
                                   where=f"{self.where}: {self.names[k]}")
        if self.T_supply_K is None:
            return internal
        from bearing_fmu.internals.scaled import ViscosityScaled

        return ViscosityScaled(internal)

    def _warm_up(self) -> None:
        """One force and Jacobian per internal, so that compiling (or loading) its kernels counts as
        setup, not as the sweep's time; a state the internal refuses here is left for the sweep."""
        from bearing_fmu.physics.statics import film_jacobian

        for internal in self.internals:
            try:
                film_jacobian(internal, 0.0, -0.1 * internal.params.CR, 0.0, 0.0, 2.0 * math.pi)
            except ValueError:  # BearingStateError: the sweep names it with its speed
                pass

    # -- one speed ---------------------------------------------------------------------------
    def equilibrium(self, omega: float, q0: np.ndarray | None = None) -> np.ndarray:
        """Static equilibrium q [m, rad] at ``omega`` [rad/s]: Newton from ``q0`` (continuation),
        and if that fails (or no q0) from the start a scene uses (``run.static_start``: the
        short-bearing estimate, the rotor deflected onto it). Raises EquilibriumError."""
        from bearing_fmu.physics.statics import EquilibriumError

        from ...coupling.bearings import DirectBearings
        from ...integrate.equilibrium import static_equilibrium
        from ...scenes.run import static_start

        t0 = time.perf_counter()
        try:
            bearings = DirectBearings(self.internals, self.pairs, omega, self.names)
            if q0 is not None:
                try:
                    return static_equilibrium(self.rotor.matrices()[1], self.f_static, bearings, q0,
                                              rigid_modes=self.rotor.rigid_modes())
                except EquilibriumError:
                    pass  # the previous speed's equilibrium was too far: start afresh, as a scene does
            return static_start(self.rotor, self.f_static, self.loads, bearings, omega)
        finally:
            self.timings["equilibrium"] += time.perf_counter() - t0

    def linearise(self, q: np.ndarray, omega: float) -> tuple[np.ndarray, np.ndarray]:
        """Lund's (K, C) of every bearing at the equilibrium q, shape (n_bearings, 2, 2) each."""
        from bearing_fmu.physics.statics import linearize

        K = np.empty((len(self.internals), 2, 2))
        C = np.empty_like(K)
        reduced = registry.get(self.internal).can.whirl_reduced  # a tilting pad's: synchronous reduction
        for k, (internal, (iy, iz)) in enumerate(zip(self.internals, self.pairs)):
            if reduced:
                K[k], C[k] = internal.reduced_coefficients(float(q[iy]), float(q[iz]), omega, omega)
            else:
                K[k], C[k] = linearize(internal, float(q[iy]), float(q[iz]), omega)
        for name, a in (("stiffness", K), ("damping", C)):
            if not np.all(np.isfinite(a)):
                k = int(np.argwhere(~np.isfinite(a))[0, 0])
                raise RuntimeError(f"{self.names[k]}: non-finite {name} coefficients at "
                                   f"{omega / (2 * math.pi):.6g} Hz ({a[k].tolist()}) from the {self.internal} internal")
        return K, C

    def _place_feeds(self, omega: float) -> None:
        """The bores fed along their line of thickest film: the line at this speed's equilibrium."""
        from bearing_fmu.physics.bore.feed import place_feed

        for k in self.unplaced:
            params = place_feed(self.rotor.bearings[k], self.loads[k], omega, name=f"{self.where}: {self.names[k]}")
            self.internals[k] = self._create(k, params)

    def thermal(self, omega: float) -> tuple[np.ndarray, np.ndarray]:
        """(T_eff [K], mu_eff [Pa s]) per bearing at ``omega`` [rad/s] under its static load, and the
        internals set to mu_eff; empty arrays without a supply temperature. A bearing without a
        film temperature there (no equilibrium at some viscosity) raises EquilibriumError naming it."""
        if self.T_supply_K is None:
            return np.zeros(0), np.zeros(0)
        from bearing_fmu.physics.statics import EquilibriumError
        from bearing_fmu.physics.thermal import ThermalError, effective_temperature

        T, mu = [], []
        for internal, w, name in zip(self.internals, self.loads, self.names):
            try:
                st = effective_temperature(internal.inner.params, (float(w[0]), float(w[1])), omega, self.T_supply_K,
                                           name=name, internal=internal.inner if self.own_film else None)
            except ThermalError as exc:
                raise EquilibriumError(str(exc), bearing=name) from None
            internal.set_viscosity(st.mu_eff_Pa_s)
            T.append(st.T_eff_K)
            mu.append(st.mu_eff_Pa_s)
        return np.array(T), np.array(mu)

    def at(self, speed_hz: float, q0: np.ndarray | None = None) -> tuple[SpeedPoint, np.ndarray]:
        """(SpeedPoint, equilibrium q) at ``speed_hz``; EquilibriumError if there is none."""
        omega = 2.0 * math.pi * speed_hz
        self._place_feeds(omega)
        T_eff, mu_eff = self.thermal(omega)
        q = self.equilibrium(omega, q0)
        t0 = time.perf_counter()
        K, C = self.linearise(q, omega)
        # every mode up to DENSE_MODES_MAX_DOF DOFs; a bigger rotor's around its ranking band (sparse)
        band = self.band_hz if math.isfinite(self.band_hz) else band_hz(speed_hz)
        if not self.own_dofs:
            freq, ld, shapes = band_modes(self.rotor, omega, K, C, band)
        elif self.rotor.n_dof <= DENSE_MODES_MAX_DOF:
            freq, ld, shapes = modes_at(self.rotor, self.internals, self.pairs, q, omega)
        else:  # the pads' coordinates in a big rotor's eigenproblem: sparse, around the band
            freq, ld, shapes = band_modes_with_pads(self.rotor, omega, pad_blocks(self.internals, self.pairs, q, omega),
                                                    band)
        if freq.size == 0 or not (np.all(np.isfinite(freq)) and np.all(np.isfinite(ld))):
            raise RuntimeError(f"{speed_hz:g} Hz: the eigenvalue problem gave "
                               f"{'no oscillatory mode' if freq.size == 0 else 'non-finite eigenvalues'}")
        whirl = np.array([self.rotor.whirl(shapes[:, i], _busiest_node(self.rotor, shapes[:, i]))
                          for i in range(freq.size)])
        journal = np.array([(q[iy], q[iz]) for iy, iz in self.pairs])
        ecc = np.hypot(journal[:, 0], journal[:, 1]) / np.array([p.CR for p in self.rotor.bearings])
        self.timings["eigen"] += time.perf_counter() - t0
        return SpeedPoint(speed_hz, journal=journal, eccentricity=ecc, K=K, C=C, freq_hz=freq, log_dec=ld,
                          whirl=whirl, band_hz=self.band_hz, shapes=shapes, T_eff_K=T_eff, mu_eff_Pa_s=mu_eff), q

    # -- a range -----------------------------------------------------------------------------
    def sweep(self, speeds_hz, *, n_modes: int = DEFAULT_MODES, rotor_name: str = "", log=None,
              rank_up_to: float = RANK_UP_TO) -> StabilityResult:
        """Every speed of ``speeds_hz`` (ascending) with continuation, then the threshold and
        the critical speeds; the least stable mode ranked up to ``rank_up_to`` x the top speed.
        A speed without an equilibrium is kept as a "no equilibrium"
        point (the next speed starts afresh). An interrupt is raised again with the result so
        far as its ``result`` attribute."""
        from bearing_fmu.physics.statics import EquilibriumError

        from ...integrate.equilibrium import RotorNotSupported

        res = StabilityResult(rotor_name or self.rotor.name, self.internal, self.options,
                              [n + 1 for n in self.rotor.bearing_nodes], self.loads.tolist(), n_modes=n_modes,
                              T_supply_K=self.T_supply_K)
        speeds_hz = [float(s) for s in speeds_hz]
        check_top_speed(self.rotor, speeds_hz, self.where)  # before any solve: no material turns so fast
        self.band_hz = res.band_hz = band_hz(max(speeds_hz, default=0.0), rank_up_to)
        res.rank_up_to = float(rank_up_to)
        res.timings["setup"] = self.setup_s
        qs: list[np.ndarray | None] = []
        q = None
        try:
            for s in speeds_hz:
                try:
                    point, q = self.at(float(s), q)
                except EquilibriumError as exc:
                    point, q = SpeedPoint(float(s), "no equilibrium", str(exc)), None
                    if isinstance(exc, RotorNotSupported):  # journals outside, loads not carried
                        res.unsupported.append(float(s))
                    if log is not None:
                        log(f"{s:g} Hz: {exc}")
                res.points.append(point)
                qs.append(q)
            t0 = time.perf_counter()
            res.threshold, res.unstable_from_start = self._threshold(res.points, qs)
            res.timings["refine"] = time.perf_counter() - t0
        except KeyboardInterrupt as exc:
            res.status = "interrupted"
            exc.result = res
            raise
        finally:
            res.timings["equilibrium"] = self.timings["equilibrium"]
            res.timings["eigen"] = self.timings["eigen"]
        res.criticals, res.damped_crossings = split_crossings(critical_speeds(res.points))
        return res

    def _threshold(self, points, qs) -> tuple[Threshold | None, bool]:
        """The first zero crossing of the least stable log decrement between two consecutive
        speeds that both have an equilibrium, refined by Brent's method; (None, True) when the
        first speed with an equilibrium is already unstable."""
        ok = [i for i, p in enumerate(points) if p.ok]
        if not ok:
            return None, False
        if points[ok[0]].least_log_dec <= 0.0:
            return None, True
        for i, j in zip(ok, ok[1:]):
            if j != i + 1:
                continue  # a speed without equilibrium in between: no continuous crossing to refine
            a, b = points[i], points[j]
            if a.least_log_dec > 0.0 >= b.least_log_dec:
                return self._refine(a, b, qs[i]), False
        return None, False

    def _refine(self, a: SpeedPoint, b: SpeedPoint, qa: np.ndarray) -> Threshold:
        from scipy.optimize import brentq

        from bearing_fmu.physics.statics import EquilibriumError

        if b.least_log_dec == 0.0:
            p = b
            how = "brent"
        else:
            try:
                s = brentq(lambda sp: self.at(sp, qa)[0].least_log_dec, a.speed_hz, b.speed_hz,
                           xtol=THRESHOLD_XTOL_HZ)
                p, how = self.at(s, qa)[0], "brent"
            except EquilibriumError:  # cannot evaluate inside the bracket: interpolate between its ends
                fa, fb = a.least_log_dec, b.least_log_dec
                w = fa / (fa - fb)
                s = a.speed_hz + w * (b.speed_hz - a.speed_hz)
                near = a if w < 0.5 else b
                return Threshold(s, (1 - w) * a.freq_hz[a.least] + w * b.freq_hz[b.least], float(near.whirl[near.least]),
                                 near, (a.speed_hz, b.speed_hz), "interpolated")
        return Threshold(p.speed_hz, float(p.freq_hz[p.least]), float(p.whirl[p.least]), p,
                         (a.speed_hz, b.speed_hz), how)


def _busiest_node(rotor: Rotor, shape: np.ndarray) -> int:
    """The 0-based node with the largest translational amplitude |y|^2 + |z|^2 of a complex shape."""
    yz = shape.reshape(rotor.n_nodes, 4)[:, :2]
    return int(np.argmax(np.sum(np.abs(yz) ** 2, axis=1)))


def stability(rotor_path, speeds_hz, internal: str = "reynolds", options: dict | None = None,
              static_loads=(), n_modes: int = DEFAULT_MODES, log=None,
              rank_up_to: float = RANK_UP_TO, T_supply_K: float | None = None) -> StabilityResult:
    """Read the rotor file and sweep it (see the module docstring). ``static_loads`` are
    (node, Fy, Fz) with 1-based nodes as in the rotor file; ``T_supply_K`` the oil's supply
    temperature (``Stability``); bad input raises ValueError naming it."""
    rotor, loads = read_rotor(rotor_path, static_loads)
    speeds = check_speeds(speeds_hz)
    analysis = Stability(rotor, internal, options, loads, where=str(rotor_path), T_supply_K=T_supply_K)
    return analysis.sweep(speeds, n_modes=n_modes, rotor_name=rotor.name or Path(rotor_path).stem, log=log,
                          rank_up_to=rank_up_to)


# ----------------------------------------------------------------------------- the command


def command(*, rotor_file, speeds_hz, internal: str = "reynolds", data_files=None, grid=None, static_load=(), modes:
            int = DEFAULT_MODES, out="out", no_plots: bool = False, rank_up_to: float = RANK_UP_TO,
            supply_c: float | None = None) -> int:
    """``rotor-host stability``: equilibrium, linearised bearings and damped modes of the rotor file
    ``rotor_file`` at each speed of ``speeds_hz`` [Hz]; writes the table, json and figures into ``out``.
    ``supply_c``: the oil's supply temperature [C] (bearings with [oil]: at mu_eff per speed)."""
    out = ensure_writable(out)
    rotor, loads = read_rotor(rotor_file, static_load)
    options = internal_options(internal, data_files, grid, bearings=rotor.bearings)
    stem = f"stability_{Path(rotor_file).stem}_{internal}"
    if supply_c is not None:  # the command line's value, named before any data file is read
        check_supply(rotor, supply_c + 273.15, str(rotor_file), "--supply-c")
    try:
        analysis = Stability(rotor, internal, options, loads, where=str(rotor_file),
                             T_supply_K=None if supply_c is None else supply_c + 273.15)
    except ValueError as exc:  # a data file's own one line (L/D, not a map file): name the option that chose it
        chosen = [o.name for o in registry.get(internal).file_options() if o.name in options]
        if chosen:
            raise ValueError(f"--{chosen[0]} {options[chosen[0]]}: {exc}") from None
        raise
    try:
        res = analysis.sweep(check_speeds(speeds_hz), n_modes=modes,
                             rotor_name=rotor.name or Path(rotor_file).stem, log=lambda msg: print(f"  {msg}"),
                             rank_up_to=rank_up_to)
    except KeyboardInterrupt as exc:
        res = getattr(exc, "result", None)
        if res is not None and res.points:
            res.inputs = title_line(rotor, rotor_file, internal, options, res.T_supply_K)
            write_text(out / f"{stem}.md", markdown(res) + "\n**interrupted: the speeds above finished**\n")
            write_json(out / f"{stem}.json", to_json(res, rotor_file))
            note_kept(exc, f"{out / f'{stem}.md'} ({len(res.points)} speed(s))")
        raise
    res.inputs = title_line(rotor, rotor_file, internal, options, res.T_supply_K)
    files = [write_text(out / f"{stem}.md", markdown(res)), write_json(out / f"{stem}.json", to_json(res, rotor_file))]
    if res.unsupported and len(res.unsupported) == len(res.points):  # the rotor file or its loads: exit 2
        from ...integrate.equilibrium import RotorNotSupported

        raise RotorNotSupported(f"{rotor_file}: at every speed of {speeds_hz[0]:g}-{speeds_hz[-1]:g} Hz: "
                                f"{res.points[0].message}; wrote {files[0]}")
    if not res.ok_points:
        raise RuntimeError(f"{rotor_file}: no speed of {speeds_hz[0]:g}-{speeds_hz[-1]:g} Hz has a static "
                           f"equilibrium (first: {res.points[0].message}); wrote {files[0]}")
    tm = res.timings
    print(f"computed for: {res.inputs}")
    print(f"{res.rotor} [{res.internal}]: {len(res.points)} speeds in {tm['equilibrium'] + tm['eigen']:.2f} s "
          f"(equilibria {tm['equilibrium']:.2f} s, linearisation and modes {tm['eigen']:.2f} s; threshold "
          f"refinement {tm['refine']:.2f} s; setup {tm['setup']:.2f} s)")
    for c in res.criticals:
        print(f"critical speed {c['speed_hz']:.2f} Hz ({direction(c['whirl'])}, log dec {c['log_dec']:.3f}, AF "
              f"{c['amplification_factor']:.3g})")
    print("\n".join(res.notes()))
    print(res.verdict())
    if not no_plots:
        from .campbell import plot_campbell, plot_log_dec, plot_mode_shape

        files += [plot_campbell(res, out / f"{stem}_campbell.png"), plot_log_dec(res, out / f"{stem}_logdec.png")]
        shape = plot_mode_shape(res, rotor, out / f"{stem}_mode.png")
        if shape is not None:
            files.append(shape)
    print("wrote " + ", ".join(str(f) for f in files))
    return 0


__all__ = ["Stability", "StabilityResult", "SpeedPoint", "Threshold", "stability", "read_rotor", "check_speeds",
           "critical_speeds",
           "markdown", "to_json", "command"]
