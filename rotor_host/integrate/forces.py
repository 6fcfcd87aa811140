"""Nonlinear nodal forces: the protocol the integrator talks to, its adapters, and the one
vocabulary of the Newton tangent.

A nonlinear force (the bearings) acts on a few DOFs of the rotor through :class:`NodalForce`:
the integrator (``rotor_host.integrate.newmark``) and the static equilibrium
(``rotor_host.integrate.equilibrium``) call it, ``rotor_host.coupling.bearings`` implements it for bearing
internals and bearing FMUs. A force that cannot evaluate a state raises
:class:`StepRejected`. :class:`FunctionForce`, :class:`LinearForce` and
:class:`CompositeForce` adapt plain callables, linear springs and dampers, and several forces.

The Newton tangent
------------------
One word per choice, the same for the scene key ``[time] newton_tangent``, ``rotor-host run
--tangent``, :class:`rotor_host.integrate.newmark.NewmarkConfig` and :class:`rotor_host.coupling.bearings.BearingSet`
(:data:`NEWTON_TANGENTS`):

``bearing``  each bearing's own local stiffness and damping at every iterate (the FMU's K, C
             outputs; exact Newton, the default)
``frozen``   the bearings' stiffness and damping at the static equilibrium (Lund's
             coefficients), fixed for the whole run
``fd``       the force alone; the integrator builds the tangent by finite differences, keeps
             it across steps and refreshes it when Newton slows (the bearings skip their Jacobian)
``linear``   the force alone and the rotor's linear tangent without the bearings, fixed

Each side reads the word for its own part. The integrator: "bearing" and "frozen" both mean
"use the tangent the nodal force returns" (the linear one where it returns none), "fd" the
same but finite differences where it returns none, "linear" never a nonlinear tangent. The
bearings: "bearing" their tangent at every evaluation, "frozen" the one at the first dynamic
evaluation, "fd" and "linear" no tangent and no Jacobian computed (:data:`FORCE_TANGENTS`
are the words under which the force returns one).
"""

from __future__ import annotations

from typing import Callable, Protocol, Sequence, runtime_checkable

import numpy as np

__all__ = [
    "NEWTON_TANGENTS",
    "FORCE_TANGENTS",
    "check_tangent",
    "StepRejected",
    "NodalForce",
    "FunctionForce",
    "LinearForce",
    "CompositeForce",
    "as_nodal_force",
]


# =============================================================================== tangent

NEWTON_TANGENTS = ("bearing", "frozen", "fd", "linear")
FORCE_TANGENTS = ("bearing", "frozen")


def check_tangent(tangent: str, setting: str) -> str:
    """``tangent`` if it is one of NEWTON_TANGENTS; otherwise ValueError naming ``setting``."""
    if tangent not in NEWTON_TANGENTS:
        raise ValueError(f"{setting} = {tangent!r}; choose one of {', '.join(NEWTON_TANGENTS)}")
    return tangent


# =============================================================================== errors

class StepRejected(Exception):
    """Raised by ``NodalForce.evaluate`` when the state cannot be evaluated (for example the
    journal at or beyond the bearing wall). The integrator cuts the step; give a message
    that says why (it appears in the final error if cutting does not help)."""


# =============================================================================== protocol

@runtime_checkable
class NodalForce(Protocol):
    """Nonlinear force acting on a few DOFs.

    Call sequence per time step (t, dt): ``begin_step(t, dt)``; then ``evaluate(q, v)`` one or
    more times with the DOF values at the END of the step (t + dt) of the current iterate;
    then ``accept_step()`` (the last evaluate was at the accepted state) or ``reject_step()``
    (the step is abandoned and will be redone in smaller pieces). The arrays passed to
    ``evaluate`` are fresh copies: the force may keep them; v is the Newmark velocity of the
    iterate, v = gamma / (beta dt) (q - q0) + ..., so df/dv enters the tangent times
    gamma / (beta dt). The returned arrays are copied at once: a force may reuse its buffers.
    The first step's bracket also holds the evaluation at (q0, v0) that gives the initial
    acceleration. With tangent="fd" some evaluations are at perturbed states; the accepted
    state is still the last one evaluated before ``accept_step()``.
    ``static_equilibrium`` brackets its evaluations in ``begin_step(t, 0.0)`` ...
    ``accept_step()`` (``reject_step()`` on failure); dt = 0.0 marks a static evaluation.

    Optional: ``compiled()`` -> (forces, omega), (forces, omega, clock), (forces, omega, clock,
    (enter, leave)) or None. A force whose hooks do nothing (or, with a ``clock``, whose kernels
    need only the step's (t, h), which the loop writes into that float64 (2,) array at each step:
    a memoryless FMU's doStep; or, with ``enter`` and ``leave``, whose kernels keep what the hooks
    do themselves and hand it over around each chunk: ``newmark_loop.ChunkDriver``) and
    whose evaluation is, per pair of DOFs (y, z), one compiled kernel of
    ``bearing_fmu.internals.compiled`` at the speed omega [rad/s] (with its own derivatives)
    may hand the integrator those kernels, one ``CompiledForce`` per pair; the
    integrator then runs whole chunks of steps compiled (``newmark_loop``), with no call of
    the hooks or of ``evaluate`` there, and calls them as usual for any step it gives back
    to Python.
    """

    dofs: np.ndarray

    def begin_step(self, t: float, dt: float) -> None: ...

    def evaluate(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
        """Return f (m,), and df/dq (m, m), df/dv (m, m) (raw derivatives) or None."""
        ...

    def accept_step(self) -> None: ...

    def reject_step(self) -> None: ...


def as_dofs(dofs) -> np.ndarray:
    d = np.ascontiguousarray(np.asarray(dofs, dtype=np.int64).reshape(-1))
    if np.unique(d).size != d.size:
        raise ValueError(f"nonlinear-force DOFs must be distinct, got {d.tolist()}")
    return d


class FunctionForce:
    """A NodalForce from a plain callable ``fn(q, v) -> (f, dfdq, dfdv)`` (or just ``f``);
    the step hooks do nothing."""

    def __init__(self, dofs, fn: Callable):
        self.dofs = as_dofs(dofs)
        self.fn = fn

    def begin_step(self, t: float, dt: float) -> None:
        pass

    def evaluate(self, q, v):
        out = self.fn(q, v)
        if isinstance(out, tuple):
            if len(out) == 3:
                return out
            if len(out) == 1:
                return out[0], None, None
            raise ValueError("FunctionForce callable must return f or (f, dfdq, dfdv)")
        return out, None, None

    def accept_step(self) -> None:
        pass

    def reject_step(self) -> None:
        pass


class LinearForce:
    """f = f0 - Kb (q - q_ref) - Cb v on ``dofs`` (Lund's sign: Kb, Cb are the stiffness and
    damping the force opposes the motion with). Exact derivatives. For linear bearings and tests."""

    def __init__(self, dofs, Kb, Cb=None, f0=None, q_ref=None):
        self.dofs = as_dofs(dofs)
        m = self.dofs.size
        self.Kb = np.array(Kb, dtype=float).reshape(m, m)
        self.Cb = np.zeros((m, m)) if Cb is None else np.array(Cb, dtype=float).reshape(m, m)
        self.f0 = np.zeros(m) if f0 is None else np.array(f0, dtype=float).reshape(m)
        self.q_ref = np.zeros(m) if q_ref is None else np.array(q_ref, dtype=float).reshape(m)
        self._dq = -self.Kb
        self._dv = -self.Cb

    def begin_step(self, t: float, dt: float) -> None:
        pass

    def evaluate(self, q, v):
        return self.f0 - self.Kb @ (q - self.q_ref) - self.Cb @ v, self._dq, self._dv

    def accept_step(self) -> None:
        pass

    def reject_step(self) -> None:
        pass


class CompositeForce:
    """Several NodalForces (e.g. one per bearing) seen as one: DOFs concatenated, derivatives
    block-diagonal. A member that returns no derivatives contributes zero blocks (its part of
    the tangent is then the linear one). Hooks are forwarded to every member."""

    def __init__(self, forces: Sequence[NodalForce]):
        self.forces = list(forces)
        sizes = [len(np.asarray(f.dofs).reshape(-1)) for f in self.forces]
        self.dofs = as_dofs(np.concatenate([np.asarray(f.dofs, dtype=np.int64).reshape(-1) for f in self.forces])
                             if self.forces else np.zeros(0, np.int64))
        self._slices = []
        o = 0
        for s in sizes:
            self._slices.append(slice(o, o + s))
            o += s
        m = self.dofs.size
        self._f = np.zeros(m)
        self._dq = np.zeros((m, m))
        self._dv = np.zeros((m, m))

    def begin_step(self, t: float, dt: float) -> None:
        for f in self.forces:
            f.begin_step(t, dt)

    def evaluate(self, q, v):
        f_all = np.empty(self.dofs.size)
        dq_all = np.zeros((self.dofs.size, self.dofs.size))
        dv_all = np.zeros((self.dofs.size, self.dofs.size))
        any_dq = any_dv = False
        for frc, s in zip(self.forces, self._slices):
            f, dq, dv = frc.evaluate(q[s].copy(), v[s].copy())
            f_all[s] = f
            if dq is not None:
                dq_all[s, s] = dq
                any_dq = True
            if dv is not None:
                dv_all[s, s] = dv
                any_dv = True
        return f_all, (dq_all if any_dq else None), (dv_all if any_dv else None)

    def accept_step(self) -> None:
        for f in self.forces:
            f.accept_step()

    def reject_step(self) -> None:
        for f in self.forces:
            f.reject_step()


class _NoForce:
    dofs = np.zeros(0, dtype=np.int64)
    _f = np.zeros(0)

    def begin_step(self, t, dt):
        pass

    def evaluate(self, q, v):
        return self._f, None, None

    def accept_step(self):
        pass

    def reject_step(self):
        pass


def as_nodal_force(nodal_force) -> NodalForce:
    """One NodalForce from a NodalForce, a list or tuple of them (a CompositeForce) or None
    (no force)."""
    if nodal_force is None:
        return _NoForce()
    if isinstance(nodal_force, (list, tuple)):
        return CompositeForce(nodal_force)
    return nodal_force
