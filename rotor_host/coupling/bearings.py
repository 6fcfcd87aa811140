"""Bearing forces on the rotor through the integrator's NodalForce protocol.

One ``BearingSet`` holds all bearings of a rotor: it maps the integrator's displacements and
velocities at the bearing DOFs (y, z of each bearing node, in that order) to the journal
states, asks each bearing for its film force and local Jacobian, and hands back the
stacked force and a block-diagonal tangent. Two kinds share this bookkeeping:

* ``DirectBearings`` calls bearing internals in-process (no FMI): the reference a
  co-simulation is checked against, and the fastest way to run a scene.
* ``rotor_host.coupling.cosim.FMUBearings`` asks one FMU instance per bearing, the FMI 2.0 way.

A bearing that cannot evaluate a state (journal at the wall, non-finite input) raises
``StepRejected`` naming the bearing, the state and the time, so the integrator cuts the step.

With a film temperature that lags (a scene with a supply temperature: ``LaggedThermal``
in-process, an FMU's thermal ports) a set has ``thermal_fields`` and ``thermal_record()``: each
bearing's film temperature, viscosity, friction power and flows at its last evaluation, which a
run reads at its recorded times only (``Newmark.run``'s ``record_extra``), never per iteration.
"""

from __future__ import annotations

import numpy as np

from bearing_fmu.internals.registry import BearingStateError
from bearing_fmu.physics.statics import film_jacobian

from ..integrate.forces import FORCE_TANGENTS, StepRejected, check_tangent

# what ``thermal_record`` gives per bearing, in this order: T_eff [K], mu_eff [Pa s], P_loss [W],
# Q_side [m^3/s] (the bearing FMU's thermal outputs, by their names) and Q_in [m^3/s] (in-process only)
THERMAL_FIELDS = ("T_eff", "mu_eff", "P_loss", "Q_side", "Q_in")


class BearingSet:
    """Common part: DOF mapping, stacking, per-bearing bookkeeping.

    bearing_dofs : list of (dof_y, dof_z) global indices, one pair per bearing
    omega        : shaft speed [rad/s]; ``speed`` (t -> omega), when set, updates it at each step
    names        : labels used in messages ("bearing 1", ...)
    clearances   : radial clearance CR [m] per bearing (None where not known), set by the
                   subclass: the static equilibrium's diagnosis places journals near the wall
    tangent      : the Newton tangent, one of ``rotor_host.integrate.forces.NEWTON_TANGENTS``; what
                   ``evaluate`` hands the integrator besides the force:
                   "bearing"  each bearing's own local tangent at every iterate (exact Newton);
                   "frozen"   the bearings' tangent at the first evaluation of the first time
                              step (the static equilibrium's Lund coefficients), then always that;
                   "fd", "linear"  no tangent (the integrator builds its own, by finite
                              differences or the linear rotor's), and the bearings skip their
                              Jacobian (``with_jacobian`` is False)
    """

    lund_sign = False  # True: _bearing returns K = -dF/dq, C = -dF/dv (evaluate negates them)
    thermal_fields: tuple = ()  # the columns of thermal_record (a prefix of THERMAL_FIELDS); () none

    def __init__(self, bearing_dofs, omega: float, names=None, tangent: str = "bearing"):
        pairs = [(int(a), int(b)) for a, b in bearing_dofs]
        self.n = len(pairs)
        self.dofs = np.array([d for pair in pairs for d in pair], dtype=int)
        self.omega = float(omega)
        self.speed = None  # callable t -> omega [rad/s] for a speed that changes (set by the scene)
        self.names = list(names) if names is not None else [f"bearing {k + 1}" for k in range(self.n)]
        self.clearances: list[float | None] = [None] * self.n
        self.tangent = check_tangent(tangent, f"{type(self).__name__} tangent")
        self.with_jacobian = tangent in FORCE_TANGENTS  # else evaluate returns the force alone
        self._frozen = None  # (dq, dv) once frozen
        m = 2 * self.n
        self._f = np.zeros(m)
        self._dq = np.zeros((m, m))
        self._dv = np.zeros((m, m))
        self.t = 0.0
        self.dt = 0.0
        # the last accepted film state per bearing: (eccentricity ratio,) for reports
        self.max_eccentricity = np.zeros(self.n)

    # -- NodalForce protocol -----------------------------------------------------------
    def begin_step(self, t: float, dt: float) -> None:
        self.t, self.dt = float(t), float(dt)
        if self.speed is not None:  # a run-up: the bearings see the speed at the end of the step
            self.omega = float(self.speed(self.t + self.dt))

    def evaluate(self, q: np.ndarray, v: np.ndarray):
        f, dq, dv = self._f, self._dq, self._dv
        for k in range(self.n):
            i = 2 * k
            fk, dqk, dvk = self._bearing(k, q[i], q[i + 1], v[i], v[i + 1])
            f[i:i + 2] = fk
            if dqk is not None:
                dq[i:i + 2, i:i + 2] = dqk
                dv[i:i + 2, i:i + 2] = dvk
        if not self.with_jacobian:
            return f, None, None
        if self.lund_sign:  # one in-place negation for all bearings, not two per bearing call
            np.negative(dq, out=dq)
            np.negative(dv, out=dv)
        if self.tangent == "frozen" and self.dt > 0.0:  # static evaluations keep exact Newton
            if self._frozen is None:
                self._frozen = (dq.copy(), dv.copy())
            return f, self._frozen[0], self._frozen[1]
        return f, dq, dv

    def accept_step(self) -> None:
        pass

    def reject_step(self) -> None:
        pass

    def compiled(self):
        """The bearings as compiled kernels for the integrator's compiled loop
        (``NodalForce.compiled``), or None; a set of FMUs has none."""
        return None

    def thermal_record(self) -> np.ndarray:
        """(n, len(thermal_fields)): each bearing's ``thermal_fields`` at its last evaluation."""
        raise NotImplementedError(f"{type(self).__name__}: no film temperature (thermal_fields is empty)")

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    # -- per bearing -------------------------------------------------------------------
    def _bearing(self, k: int, y: float, z: float, vy: float, vz: float):
        """(F (2,), dF/dq (2, 2), dF/dv (2, 2)) of bearing k, or raise StepRejected; the
        derivatives may be None when ``self.with_jacobian`` is False."""
        raise NotImplementedError

    def _reject(self, k: int, reason: str) -> StepRejected:
        return StepRejected(f"{self.names[k]}: {reason} (step t = {self.t:.6g} s + dt = {self.dt:.3g} s)")


class DirectBearings(BearingSet):
    """Bearing internals called in-process through their ``force_and_jacobian``."""

    def __init__(self, internals, bearing_dofs, omega: float, names=None, tangent: str = "bearing"):
        super().__init__(bearing_dofs, omega, names, tangent)
        if len(internals) != self.n:
            raise ValueError(f"DirectBearings: {len(internals)} internals for {self.n} bearing DOF pairs")
        self.internals = list(internals)
        self.clearances = [getattr(getattr(i, "params", None), "CR", None) for i in self.internals]
        # each internal's own derivatives where it has them, central differences otherwise
        self._jac = [getattr(i, "force_and_jacobian", None)
                     or (lambda y, z, vy, vz, om, i=i: film_jacobian(i, y, z, vy, vz, om))
                     for i in self.internals]
        # internals with a state over the step (a film temperature that lags: LaggedThermal)
        self._stepped = [i for i in self.internals if hasattr(i, "begin_step")]
        if self.n and all(hasattr(i, "thermal_record") for i in self.internals):
            self.thermal_fields = THERMAL_FIELDS

    def begin_step(self, t: float, dt: float) -> None:
        super().begin_step(t, dt)
        for i in self._stepped:
            i.begin_step(self.dt)

    def accept_step(self) -> None:
        if self.dt > 0.0:  # a static evaluation (dt = 0) is never committed, as in an FMU
            for i in self._stepped:
                i.accept_step()

    def compiled(self):
        """(forces, omega): each internal's compiled force (``compiled_force``,
        ``bearing_fmu.internals.compiled``) for the integrator's compiled loop, or None when one
        has none, or the set does more per evaluation than call its internals: a speed that
        follows a profile, internals with a state over the step (``begin_step``), or a tangent
        other than each bearing's own ("frozen" keeps one, "fd" and "linear" skip it)."""
        if self.speed is not None or self.tangent != "bearing" or self.lund_sign or self._stepped:
            return None  # (a stepped internal needs its step hooks, which a compiled chunk does not call)
        forces = []
        for internal in self.internals:
            get = getattr(internal, "compiled_force", None)
            cf = get() if get is not None else None
            if cf is None:
                return None
            forces.append(cf)
        return tuple(forces), self.omega

    def thermal_record(self) -> np.ndarray:
        if not self.thermal_fields:
            return super().thermal_record()
        return np.array([i.thermal_record() for i in self.internals])

    def _bearing(self, k, y, z, vy, vz):
        try:
            if not self.with_jacobian:
                return self.internals[k].force(y, z, vy, vz, self.omega), None, None
            return self._jac[k](y, z, vy, vz, self.omega)
        except BearingStateError as exc:
            raise self._reject(k, str(exc)) from None
