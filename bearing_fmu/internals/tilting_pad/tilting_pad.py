"""The ``tilting_pad`` internal: the film force of a tilting-pad bearing on the journal, its pads
massless and in moment equilibrium at every call (``assembly.PadAssembly.equilibrate``).

Why an internal of its own and not the Reynolds internal taking the bore: a tilting-pad bearing
is N partial-arc solves plus a Newton iteration on the pads per call, its pads have states of
their own (with inertia: tilt and rate; the FMU and the host will carry them), and it reports
what no fixed bore has (pad tilts and loads, the (2 + N) x (2 + N) coefficients and their
reduction at a whirl frequency). The Reynolds solver stays what it is, the truth of one film,
and is what each pad is solved with; the force map's per-pad tables will be another pad solver
behind the same assembly.

As a memoryless internal (``force(y, z, vy, vz, omega)`` with no step begun) the pads are
quasi-static: each tilt solves M_k = 0 with the pad's own rate taken as 0 (the journal's velocity
is in the film); its Jacobian is that model's exact one (``PadAssembly.quasi_static_jacobian``: the
zero-frequency reduction of the stiffness). In a transient the host's step hooks (``begin_step(dt)``,
``accept_step``: ``rotor_host.coupling.bearings.DirectBearings`` calls them) make the pads' tilts (and
with inertia their rates) states carried from step to step (``stepping``: BDF2, Newton per pad,
warm-started), the force's derivatives total. The Python FMU carries them the same way over each
doStep (``Capabilities.step_states``: ``step_state``, ``set_step_state`` with its FMU state).
"""

from __future__ import annotations

import numpy as np

from ...physics.solver.film import FilmReport, assemble_report
from ...physics.params import BearingParams
from .assembly import PadAssembly, PadSolution
from .journal import journal_equilibrium
from .stepping import PadStepper


def viscosity_scaling_why(pads) -> str:
    """Why the film's temperature is refused for these pads ("" when it is not): a flexible pivot's spring
    does not scale with mu, so the pads' force at another viscosity is not the force times the ratio."""
    kp = pads.pivot_stiffness
    if kp is None:
        return ""
    return (f"[geometry] pivot_stiffness_N_m = {kp:g}: the film's temperature (a supply temperature, an [oil] "
            "table's mu_eff) with a flexible pivot is not modelled: the pads' force at another viscosity is not the "
            "force times the viscosity ratio; an isoviscous bearing (no [oil] table) or rigid pivots")


class TiltingPad:
    """The journal force of ``params``' tilting pads (``params.geometry.pads``), every pad the
    partial-arc Reynolds solver (grid ``n_theta`` cells on each pad's arc, ``n_x`` along the
    length; None: the solver's defaults), cavitation model ``cavitation``.

    ``last``: the pads' ``PadSolution`` of the last call (tilts, pad forces and moments)."""

    def __init__(self, params: BearingParams, n_theta: int | None = None, n_x: int | None = None,
                 cavitation: str = "reynolds", pad_map=None):
        self.params = params
        self.pads = PadAssembly(params, n_theta, n_x, cavitation)
        if pad_map:  # every pad from the pads' partial-arc force map (padmap), not the Reynolds solver
            from .padmap import PadMapSolver

            self.pads.use_solver(PadMapSolver(params, pad_map))
        self.last: PadSolution | None = None
        self.stepper = PadStepper(self.pads)
        # the film's flows (a temperature) need each pad's film report: the Reynolds pads have it, a force map not
        self.film_flow_why = (f"the pads' force map ({pad_map}) tabulates forces only, no friction or flows: the "
                              "film temperature needs the Reynolds pads (no pad_map)") if pad_map else ""
        # read by ViscosityScaled: with flexible pivots the force is not mu times one function of the state
        self.viscosity_scaling_why = viscosity_scaling_why(params.geometry.pads)

    @classmethod
    def from_options(cls, params: BearingParams, options, context=None) -> "TiltingPad":
        """From the registry's checked options (the Reynolds internal's grid and cavitation: 0 = default;
        ``pad_map``: the pads' force map file, ``bearing-fmu``'s ``padmap.build_pad_map``)."""
        pad_map = options.get("pad_map") or None
        if pad_map and context is not None:
            pad_map = context.path(pad_map)
        return cls(params, n_theta=options["n_theta"] or None, n_x=options["n_x"] or None,
                   cavitation=options["cavitation"], pad_map=pad_map)

    def __repr__(self) -> str:
        return f"TiltingPad({self.params!r})"

    # the host's step hooks (rotor_host.coupling.bearings.DirectBearings): the pads' states in a transient
    def begin_step(self, dt: float) -> None:
        """Evaluations until ``accept_step`` are at the end of a step of dt [s] from the committed pads
        (``stepping``); dt = 0: static, the pads in moment equilibrium (memoryless)."""
        self.stepper.begin_step(dt)

    def accept_step(self) -> None:
        """The last evaluation's pads become the state."""
        self.stepper.accept()

    def step_state(self) -> tuple[float, ...]:
        """The pads' committed state as floats (``stepping.PadStepper.state``): what an FMU state carries."""
        return self.stepper.state()

    def set_step_state(self, values) -> None:
        """The pads' committed state from ``step_state``'s floats (ValueError naming what does not fit)."""
        self.stepper.restore(values)

    def pad_report(self) -> tuple[np.ndarray, np.ndarray]:
        """(tilts [rad], loads [N]) of the pads at the last evaluation: each pad's tilt and the magnitude
        of its film force on the journal (zeros before any)."""
        if self.last is None:
            return np.zeros(self.pads.n), np.zeros(self.pads.n)
        return self.last.delta.copy(), np.hypot(self.last.pad_F[:, 0], self.last.pad_F[:, 1])

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N] on the journal: the pads in moment equilibrium, or at the end of
        the step begun (``begin_step`` with dt > 0)."""
        F, _, _ = self.force_and_jacobian(y, z, vy, vz, omega)
        return float(F[0]), float(F[1])

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(F (2,), dF/dq (2, 2), dF/dv (2, 2)): raw derivatives, the pads following the journal
        (quasi-static, or over the step begun)."""
        if self.stepper.dt > 0.0:
            self.last, dq, dv = self.stepper.solve(y, z, vy, vz, omega)
            return self.last.F.copy(), dq, dv
        self.last = self.pads.equilibrate(y, z, vy, vz, omega)
        self.stepper.static(self.last)
        dq, dv = self.pads.quasi_static_jacobian(self.last)
        return self.last.F.copy(), dq, dv

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float) -> FilmReport:
        """Friction and flows of the film at a journal state, the pads in moment equilibrium (quasi-static,
        as ``force`` answers without a step begun): each pad's partial-arc report summed, every pad fed at
        its leading edge (its inflow) and losing its side flow; the torques about the journal's centre, so
        the power is the journal's T omega - F . v (massless pads in equilibrium take no work). In a step
        (the film temperature of a transient, ``LaggedThermal``) the report is the quasi-static pads' at
        the journal's state: the temperature follows the film over its residence time, slower than the
        pads' own motion."""
        if self.film_flow_why:
            raise ValueError(f"tilting pads: {self.film_flow_why}")
        sol = self.pads.equilibrate(y, z, vy, vz, omega)  # not ``last``: a step's pads stay what they are
        radial = sol.u if sol.u is not None else np.zeros(self.pads.n)  # flexible pivots: the pads' displacements
        reps = [self.pads.solvers[k].film_report(*self.pads.frame_state(k, (y, z), (vy, vz), sol.delta[k], 0.0,
                                                                        radial[k]), omega) for k in range(self.pads.n)]
        return assemble_report(self.params, sum(r.couette_torque_Nm for r in reps),
                               sum(r.pressure_torque_Nm for r in reps), sol.F, (vy, vz), omega,
                               sum(r.inflow_m3_s for r in reps), sum(r.side_flow_m3_s for r in reps))

    def journal_equilibrium(self, load, omega: float, *, start=None, rtol: float = 1e-9) -> tuple[float, float]:
        """(y0, z0) [m] under the static ``load`` (Wy, Wz) [N] at ``omega`` [rad/s], the pads massless in
        equilibrium (``journal``: the wall is each pad's film, not the clearance circle;
        ``physics.statics.equilibrium`` hands an internal with this method its own search)."""
        return journal_equilibrium(self, load, omega, rtol=rtol, start=start)

    def coefficients(self, y: float, z: float, omega: float, whirl: float | None = None) -> dict:
        """At the journal position (y, z), still, the pads in equilibrium: the full (2 + N) x (2 + N)
        K, C (coordinates y, z, delta_1..N; Lund's signs) and the journal's K, C reduced at the whirl
        frequency ``whirl`` [rad/s] (None: synchronous, omega)."""
        sol = self.pads.equilibrate(y, z, 0.0, 0.0, omega)
        self.last = sol
        K, C = self.pads.coefficients(sol)
        Kr, Cr = self.pads.reduce(K, C, omega if whirl is None else whirl)
        return {"K_full": K, "C_full": C, "K": Kr, "C": Cr, "solution": sol}

    def reduced_coefficients(self, y: float, z: float, omega: float, whirl: float) -> tuple:
        """The journal's (K [N/m], C [N s/m]) at (y, z) reduced at ``whirl`` [rad/s]
        (``Capabilities.whirl_reduced``: what a linear analysis takes)."""
        co = self.coefficients(y, z, omega, whirl)
        return co["K"], co["C"]

    def reduce(self, K_full, C_full, whirl: float) -> tuple:
        """The journal's (K [N/m], C [N s/m]) of the full (2 + N) x (2 + N) ``K_full``, ``C_full`` at
        ``whirl`` [rad/s], the pads' coordinates condensed with their inertia (Lund's reduction)."""
        return self.pads.reduce(np.array(K_full, float), np.array(C_full, float), whirl)

    def full_coefficients(self, y: float, z: float, omega: float) -> tuple:
        """(K, C, inertia): the full (2 + N) x (2 + N) K, C at (y, z), still, the pads in equilibrium
        (coordinates y, z, delta_1..N; Lund's signs) and each pad's moment of inertia [kg m^2] (N,),
        0 for massless pads (``Capabilities.whirl_reduced``: the pads' coordinates in an eigenproblem).
        Flexible pivots: (2 + 2N) x (2 + 2N), the pads' radial displacements u_1..N after the tilts,
        their inertia 0 (``PadAssembly.coordinate_inertia``)."""
        co = self.coefficients(y, z, omega)
        return co["K_full"], co["C_full"], self.pads.coordinate_inertia()


__all__ = ["TiltingPad", "viscosity_scaling_why"]

