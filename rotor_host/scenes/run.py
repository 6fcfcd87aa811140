"""Running a scene: its bearings (FMU instances or internals in-process), forces, static
equilibrium, the integration, and what it writes.

``run_scene(scene, out_dir)`` builds the rotor, the bearings for the scene's internal only (a
Taylor scene never imports the Reynolds solver; a scene's FMU is built once per content into
``<out>/fmu/``), the static equilibrium as the initial state, integrates, and writes
``<out>/<name>.npz`` plus ``<out>/<name>.json`` (metadata) even when the run fails part-way or is
interrupted, and a checkpoint while it runs (README: "When a run stops, fails or runs twice").
The scene itself -- its file, keys and checks -- is ``rotor_host.scenes.scene``.
"""

from __future__ import annotations

import math
import os
import platform
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bearing_fmu.internals import registry
from bearing_fmu.io.interrupts import as_interrupted, deferred, handled, note_kept
from bearing_fmu.io.fixed_costs import command_add_since, command_mark
from bearing_fmu.io.outputs import claim, ensure_writable, savez, write_json

from ..integrate.banded import is_sparse
from ..integrate.equilibrium import solve_part, static_equilibrium
from ..integrate.loads import RotatingLoads
from ..integrate.newmark import IntegrationError, Newmark, NewmarkConfig
from ..analyses.computed_for import scene_line
from ..model.rotor import Rotor
from .run_record import domain_report, package_versions, peak_pressures
from .bearings import InternalWarnings, build_bearings, linearisable, place_feeds_at_speed
from .sanity import check_scene_physics, check_step_against_modes
from .scene import G, Scene
from .thermal import scene_thermal, thermal_arrays, thermal_meta, with_history

# ---------------------------------------------------------------------------------- statics

def bearing_loads(rotor: Rotor, f_static: np.ndarray) -> np.ndarray:
    """Static load (Wy, Wz) [N] on each bearing's journal, shape (n_bearings, 2).

    The reactions of the rotor pinned (y, z held) at its bearing nodes under ``f_static``:
    K q = f + r with r on the held DOFs only. On two bearings the shaft is statically
    determinate, so these are the film forces at equilibrium whatever the bearing stiffness;
    the load on the journal (``bearing_fmu.physics.statics.equilibrium``'s convention) is -r.
    """
    q = _start_guess(rotor, f_static, np.zeros((len(rotor.bearing_nodes), 2)))
    r = rotor.matrices()[1] @ q - f_static
    fixed = [rotor.dof(nd, d) for nd in rotor.bearing_nodes for d in ("y", "z")]
    return -r[fixed].reshape(-1, 2)


def _start_guess(rotor: Rotor, f_static: np.ndarray, journal: np.ndarray) -> np.ndarray:
    """Rotor deflection with the bearing nodes held at the given journal positions."""
    n = rotor.n_dof
    fixed = np.array([rotor.dof(nd, d) for nd in rotor.bearing_nodes for d in ("y", "z")])
    free = np.setdiff1d(np.arange(n), fixed)
    q = np.zeros(n)
    q[fixed] = journal.reshape(-1)
    K = rotor.matrices()[1]
    # the held DOFs' push on the free ones (q is 0 on the free DOFs, so a sparse K @ q is just that)
    push = (K @ q)[free] if is_sparse(K) else K[np.ix_(free, fixed)] @ q[fixed]
    q[free] = solve_part(K, free, f_static[free] - push)
    return q


def external_force(scene: Scene, rotor: Rotor, f_static: np.ndarray):
    """f_ext(t): static loads and weight plus the rotating unbalance forces. Under a speed
    profile the mass sits at the integrated shaft angle and, besides m r Omega^2 outward, pulls
    back with m r dOmega/dt against the turning (the reaction to its tangential acceleration)."""
    om = scene.omega
    parts = []
    for u in scene.unbalances:
        parts.append((rotor.dof(u.node, "y"), rotor.dof(u.node, "z"), u.mass_kg * u.radius_m, u.phase_rad, u.t_on_s))
    out = np.empty_like(f_static)
    profile = scene.speed_profile
    if profile is None:  # a constant speed: loads the compiled integrator loop evaluates itself
        return RotatingLoads(f_static, parts, om)

    def f_ext_profile(t: float) -> np.ndarray:
        out[:] = f_static
        if parts:
            w, dw, th = profile.omega(t), profile.alpha(t), profile.angle(t)
            for iy, iz, mr, ph, t_on in parts:
                if t >= t_on:
                    c, s = math.cos(th + ph), math.sin(th + ph)
                    out[iy] += mr * (w * w * c + dw * s)
                    out[iz] += mr * (w * w * s - dw * c)
        return out

    return f_ext_profile


def initial_state(scene: Scene, rotor: Rotor, f_static, loads, bearings) -> np.ndarray:
    """The scene's initial state: the static equilibrium (``static_start``) or, with
    ``[initial] state = "centred"``, the rotor undeformed and centred."""
    if scene.initial == "centred":
        return np.zeros(rotor.n_dof)
    return static_start(rotor, f_static, loads, bearings, scene.omega)


def static_start(rotor: Rotor, f_static, loads, bearings, omega: float) -> np.ndarray:
    """Static equilibrium of the whole rotor on its nonlinear bearings at ``omega`` [rad/s],
    from the short-bearing (Ocvirk) journal positions under each bearing's ``loads``."""
    from bearing_fmu.physics.statics import short_bearing_estimate

    journal = np.array([short_bearing_estimate(p, w, omega) for p, w in zip(rotor.bearings, loads)])
    # keep the short-bearing start inside the clearance: a finite bearing carries more
    for k, p in enumerate(rotor.bearings):
        e = np.hypot(*journal[k]) / p.CR
        if e > 0.9:
            journal[k] *= 0.9 / e
    q0 = _start_guess(rotor, f_static, journal)
    return static_equilibrium(rotor.matrices()[1], f_static, bearings, q0, t=0.0, rigid_modes=rotor.rigid_modes())


# ---------------------------------------------------------------------------------- running

@dataclass
class SceneRun:
    """What a run produced: arrays (as saved in the .npz) and metadata (as in the .json)."""

    arrays: dict
    meta: dict
    npz: Path | None = None
    json: Path | None = None

    @property
    def ok(self) -> bool:
        return self.meta["status"] == "ok"


def run_scene(scene: Scene, out_dir=None, *, progress: bool = False, stem: str | None = None,
              work_dir=None) -> SceneRun:
    """Run a scene; write ``<out_dir>/<stem>.npz`` and ``.json``. Returns the SceneRun.

    What was computed is always written: a failed integration or static equilibrium gives
    meta["status"] == "failed" (with the message), an interrupt (Ctrl-C, SIGTERM) status
    "interrupted" and the signal, after which the interrupt is raised again; while running, a
    checkpoint (status "running") is written every ``scene.checkpoint_s`` of wall time. Files
    are written under a temporary name and renamed into place; a name another running process
    holds gets a suffix (``bearing_fmu.io.outputs.claim``); a result the folder refuses (a full
    disk, made read-only) goes to its rescue folder (``outputs``), a checkpoint it refuses is a
    one-line warning and the run goes on."""
    native = "_native" if scene.via == "fmu" and scene.fmu_kind == "native" else ""
    stem = stem or f"{Path(scene.source).stem if scene.source else scene.name}_{scene.internal}{native}"
    # made, not probed: the command probed it before any work (``ensure_writable``); a folder that
    # refuses writes now (full, made read-only) has this run's result rescued, not lost
    out_dir = ensure_writable(out_dir, probe=False) if out_dir is not None else None
    work = Path(work_dir) if work_dir is not None else None  # None: the user's FMU cache (scene_fmu)
    with handled():
        holder = claim(out_dir, stem) if out_dir is not None else None
        try:
            return _run(scene, holder, work, progress)
        finally:
            if holder is not None:
                with deferred():  # a signal now waits until the name is freed (no lock left behind)
                    holder.release()


class _Writer:
    """Turns the integrator's (partial) result into the run's arrays and metadata and writes
    them; one instance per run, used for checkpoints, failures, interrupts and the end."""

    def __init__(self, scene: Scene, rotor: Rotor, loads, holder, t_wall0: float):
        self.scene, self.rotor, self.holder, self.t_wall0 = scene, rotor, holder, t_wall0
        # the bearings and the disks always: the plots and reports show them
        self.rec_nodes = sorted(set(scene.record_nodes) | set(rotor.bearing_nodes) | {d.node for d in rotor.disks})
        self.rec_dofs = [rotor.dof(n, d) for n in self.rec_nodes for d in ("y", "z")]
        self.q0 = None
        self.thermal_fields = ()  # the bearings' (BearingSet.thermal_fields): a film temperature recorded
        self.checkpoint_failed = False
        self.warnings = InternalWarnings()
        self.times = {"setup_time_s": 0.0, "kernels_time_s": 0.0, "equilibrium_time_s": 0.0}
        self.meta = {
            "scene": scene.name, "description": scene.description, "source": str(scene.source),
            "rotor_file": str(scene.rotor_path), "inputs": scene_line(scene, rotor),
            "internal": scene.internal, "via": scene.via, "fmu_kind": scene.fmu_kind, "speed_hz": scene.speed_hz,
            "speed_profile": None if scene.speed_profile is None else scene.speed_profile.describe(), "dt_s": scene.dt_s,
            "t_end_s": scene.t_end_s, "hht_alpha": scene.alpha, "newton_tangent": scene.newton_tangent,
            "internal_options": scene.internal_options(),
            "bearing_loads_N": np.asarray(loads).tolist(), "recorded_nodes": [n + 1 for n in self.rec_nodes],
            "bearing_nodes": [n + 1 for n in rotor.bearing_nodes],
            "versions": package_versions(), "machine": platform.machine(), "pid": os.getpid(),
            "status": "ok", "message": "",
        }

    def checkpoint(self, res) -> None:
        """Write the partial result (status running); a write that fails is one warning line
        (the first time) and the run goes on: its end writes the result, or rescues it."""
        try:
            self.run(res, "running", "checkpoint written while running: the run had not finished when this was "
                     "written", rescue=False)
        except OSError as exc:
            if not self.checkpoint_failed:
                print(f"warning: checkpoint not written: {exc.filename}: {exc.strerror} (the run goes on)",
                      file=sys.stderr, flush=True)
            self.checkpoint_failed = True

    def run(self, res, status: str = "ok", message: str = "", rescue: bool = True, **extra) -> SceneRun:
        """The SceneRun of ``res`` (a NewmarkResult, or None before the integration started),
        written to disk when the run has an output folder (``rescue``: ``outputs.savez``)."""
        rotor, scene = self.rotor, self.scene
        nb, n_rec = len(rotor.bearing_nodes), len(self.rec_nodes)
        if res is None:
            t = np.zeros(0)
            q = v = np.zeros((0, 2 * n_rec))
            f = np.zeros((0, 2 * nb))
            its, n_cuts, n_eval, wall, mean_its = np.zeros(0, int), 0, 0, 0.0, 0.0
        else:
            t, q, v, f = res.t, res.q, res.v, res.f_nl
            its, n_cuts, n_eval, wall, mean_its = (res.iterations, res.n_cuts, res.n_evaluations, res.wall_time,
                                                   res.mean_iterations)
        col = {n: i for i, n in enumerate(self.rec_nodes)}
        yz = q.reshape(len(t), n_rec, 2)
        vyz = v.reshape(len(t), n_rec, 2)
        fb = f.reshape(len(t), nb, 2)
        bcols = [col[n] for n in rotor.bearing_nodes]
        CR = np.array([p.CR for p in rotor.bearings])
        ecc = np.hypot(yz[:, bcols, 0], yz[:, bcols, 1]) / CR
        q0 = self.q0[self.rec_dofs] if self.q0 is not None else np.full(len(self.rec_dofs), np.nan)
        arrays = {
            "t": t, "nodes": np.array(self.rec_nodes) + 1,
            "y": yz[:, :, 0], "z": yz[:, :, 1], "vy": vyz[:, :, 0], "vz": vyz[:, :, 1],
            "Fy": fb[:, :, 0], "Fz": fb[:, :, 1], "eccentricity": ecc,
            "bearing_nodes": np.array(rotor.bearing_nodes) + 1, "CR": CR, "q0": q0,
            "disk_nodes": np.array([d.node for d in rotor.disks], dtype=int) + 1,
            "speed_hz": np.asarray(scene.speed.hz(t), float),  # at every recorded time, one interp
        }
        if self.thermal_fields:
            arrays.update(thermal_arrays(None if res is None else res.extra, self.thermal_fields, len(t), nb))
        max_ecc = ecc.max(axis=0) if ecc.size else np.zeros(nb)
        meta = dict(self.meta)
        meta.update(status=status, message=message, internal_warnings=self.warnings.report(), **extra)
        if self.thermal_fields:
            meta["thermal"] = with_history(meta["thermal"], arrays)
        meta.update({
            "wall_time_s": time.perf_counter() - self.t_wall0, **self.times,
            "integration_time_s": wall, "steps": int(its.size),
            "t_reached_s": float(t[-1]) if t.size else 0.0,
            "newton_mean_evaluations_per_step": mean_its,
            "newton_max_evaluations_per_step": int(its.max()) if its.size else 0,
            "force_evaluations": int(n_eval), "step_cuts": int(n_cuts),
            "max_eccentricity": max_ecc.tolist(),
            "crossed_clearance": bool(np.any(max_ecc >= 1.0)),
            "equilibrium_eccentricity": (None if self.q0 is None else
                                         (np.hypot(self.q0[[rotor.dof(n, "y") for n in rotor.bearing_nodes]],
                                                   self.q0[[rotor.dof(n, "z") for n in rotor.bearing_nodes]])
                                          / CR).tolist()),
        })
        if status != "running":  # the film's peak pressure where each journal came closest to its bore
            meta.update(peak_pressures(rotor.bearings, arrays, registry.get(scene.internal).can.any_state))
        if registry.get(scene.internal).can.fitted_domain and ecc.size and status != "running":
            meta.update(domain_report(scene, rotor, yz[:, bcols], vyz[:, bcols]))
            worst = max(meta["max_domain_excess"])
            if meta["status"] != "ok" and worst > 1e-12:
                # the failure itself may read like a solver problem: say where the surrogate was
                meta["message"] += (f" [the surrogate had left its fitted domain: up to {100 * worst:.3g} % of its "
                                    f"size beyond it, {100 * max(meta['out_of_domain_fraction']):.3g} % of the recorded "
                                    "states outside; its forces there are extrapolations]")
        run = SceneRun(arrays, meta)
        if self.holder is not None:
            run.npz = savez(self.holder.path(".npz"), rescue=rescue, **arrays)
            run.json = write_json(self.holder.path(".json"), meta, rescue=rescue)
        return run


def _run(scene: Scene, holder, work: Path, progress: bool) -> SceneRun:
    from bearing_fmu.physics.statics import EquilibriumError

    t_wall0 = time.perf_counter()
    rotor = Rotor.from_toml(scene.rotor_path)
    check_scene_physics(scene, rotor)  # values no rotor has, by key, before any solve
    f_static = rotor.weight_vector(G) + rotor.point_load_vector(scene.static_loads)
    loads = bearing_loads(rotor, f_static)
    out = _Writer(scene, rotor, loads, holder, t_wall0)
    integ = None
    try:
        try:
            place_feeds_at_speed(scene, rotor, loads)
            thermal = scene_thermal(scene, rotor, loads)
        except EquilibriumError as exc:
            return out.run(None, "failed", str(exc))
        if thermal is not None:
            out.meta["thermal"] = thermal_meta(thermal)
        mark = command_mark()
        with build_bearings(scene, rotor, loads, work, warn=out.warnings, thermal=thermal) as bearings:
            command_add_since("bearings", mark)  # a command's fixed costs: its FMUs built or extracted, loaded
            out.thermal_fields = bearings.thermal_fields
            out.times["kernels_time_s"] = load_kernels(scene, bearings)
            t_setup = time.perf_counter()
            out.times["setup_time_s"] = t_setup - t_wall0
            try:
                out.q0 = initial_state(scene, rotor, f_static, loads, bearings)
            except EquilibriumError as exc:
                if isinstance(exc, ValueError):  # RotorNotSupported: the rotor file or its loads, exit 2
                    raise
                return out.run(None, "failed", str(exc),
                               equilibrium={k: v for k, v in exc.diagnosis().items() if v is not None})
            out.times["equilibrium_time_s"] = time.perf_counter() - t_setup
            check_step_against_modes(scene, rotor, linearisable(scene, rotor, loads, bearings), out.q0)
            if scene.speed_profile is not None:  # a run-up: the bearings and D follow the speed
                bearings.speed = scene.speed_profile.omega
            mM, mK, mG, mC = rotor.matrices()
            integ = Newmark(mM, mK, mC, mG,
                            scene.omega if scene.speed_profile is None else scene.speed_profile.omega,
                            external_force(scene, rotor, f_static), bearings,
                            NewmarkConfig(alpha=scene.alpha, tangent=scene.newton_tangent))
            bar = None
            if progress:
                from tqdm import tqdm

                bar = tqdm(total=scene.t_end_s, unit="s", desc=f"{scene.name} [{scene.internal}]",
                           bar_format="{l_bar}{bar}| {n:.3f}/{total:.3f} s [{elapsed}<{remaining}]")
            last = [time.perf_counter()]

            def tick(t):
                if bar is not None:
                    bar.update(t - bar.n)
                now = time.perf_counter()
                if holder is not None and now - last[0] >= scene.checkpoint_s:
                    out.checkpoint(integ.partial_result())
                    last[0] = time.perf_counter()

            try:
                res = integ.run(out.q0, np.zeros(rotor.n_dof), 0.0, scene.t_end_s, scene.dt_s,
                                record_every=scene.record_every, record_dofs=out.rec_dofs, progress=tick,
                                progress_every=_progress_every(scene),
                                record_extra=bearings.thermal_record if bearings.thermal_fields else None)
                status, message = "ok", ""
            except IntegrationError as exc:
                res, status, message = exc.result, "failed", str(exc)
            finally:
                if bar is not None:
                    bar.close()
    except KeyboardInterrupt as exc:
        sig = as_interrupted(exc).signal_name
        res = integ.partial_result() if integ is not None and integ.started else None
        t = float(res.t[-1]) if res is not None and res.t.size else 0.0
        run = out.run(res, "interrupted", f"interrupted by {sig} at t = {t:.6g} s", signal=sig)
        if run.json is not None:
            note_kept(exc, f"{run.npz}, {run.json} (status interrupted, t = {t:.6g} s)")
        raise
    return out.run(res, status, message)


def load_kernels(scene: Scene, bearings=None) -> float:
    """Load the compiled kernels this run calls in this process before any clock starts, so the
    equilibrium and integration times count work, not their loading: the integrator's, and the
    internal's when it is called in-process (an FMU loads its own when it is instantiated), its
    compiled force too (``bearings.compiled()``: a cfunc made or loaded at its first use).
    Returns the seconds taken (part of the setup time; ~0 for a process's later runs)."""
    from bearing_fmu.internals.warmup import load_loaded_under, warm_internal

    t0 = time.perf_counter()
    load_loaded_under(Newmark.__module__.rpartition(".")[0])  # rotor_host.integrate, whatever its modules
    if scene.via == "direct":
        warm_internal(scene.internal)
        if bearings is not None:
            bearings.compiled()
    return time.perf_counter() - t0


def _progress_every(scene: Scene) -> int:
    """Steps between progress calls (which also write checkpoints): ~200 per run, at most 50
    steps apart so a long run's checkpoints come on time."""
    n_steps = max(1, int(round(scene.t_end_s / scene.dt_s)))
    return max(1, min(n_steps // 200, 50))
