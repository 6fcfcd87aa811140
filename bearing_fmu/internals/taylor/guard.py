"""The fitted-domain guard of the Taylor surrogate, shared by the FMU slave and the host.

A polynomial fitted over a domain of journal states is only trustworthy inside it. The guard
wraps a ``Taylor`` internal (it is itself an internal: ``force``, ``force_and_jacobian``) and,
at every evaluation, measures how far the state lies outside the fitted domain, one number
``d`` (``Taylor.domain_distance``), the larger of

* the relative excess over the domain's bounds (eccentricity, position and velocity discs,
  bounding box: ``Taylor.bounds_distance``), each widened by as much as r_lin (below) widens
  the radius, and
* the excess of the distance nn to the nearest stored training state over their radius, in
  the scaled state space u, as a fraction of the domain's size: (nn - radius) / size
  (``NearestTraining``, a KD-tree of the states the file stores; files without them: bounds
  only, unwidened, said once in a warning). The bounds enclose the training orbits loosely;
  this part flags a state inside them but off every orbit the fit saw (22 Hz:
  (0, -0.5 CR, 0, 0), Fy -15130 N where Reynolds gives 50 N).

The radius is the larger of two distances from the training states:

* r_cv, the one the file stores: their spacing, the distances at which cross-validation
  tested the fit (bearing_fmu.fitting.neighbours);
* r_lin, computed here when the file is read (``linear_radius``): how far from a training
  state the fit's value stays within TOLERANCE (5 %) of its own first-order extrapolation
  from that state. Where the truth is nearly linear over that distance this departure is the
  fit's error; where the truth bends (near the wall) it overstates the error, so r_lin errs
  short. It is what lets a fit to thin orbits on a nearly linear film (the Friswell bearings at
  25 Hz: orbits of 0.016 CR, r_cv 0.009, r_lin 0.07) serve the neighbouring orbits it is right
  on (docs/studies/2026-11-25-guard-false-alarms.md).

d <= 0 is inside; d = 0.1 is 10 % beyond the nearest violated bound, or a tenth of the
domain's size (half the diagonal of its box in u, or the radius if larger) beyond the radius.
Then:

* inside: the surrogate's value;
* outside, but less than ``limit`` beyond: depending on ``action``
    - "warn"     : the surrogate's value; each excursion (outside after inside) is reported
                   once, when it begins (``on_warn``),
    - "fallback" : the truth's value (the Reynolds internal, built at the first exit only,
                   so a run that stays inside never imports it), blended smoothly with the
                   surrogate's over the first FALLBACK_BAND (10 %) beyond the domain so the
                   force has no jump at its edge,
    - "discard"  : BearingStateError (the FMU discards the step, the host cuts it);
* more than ``limit`` beyond, or the journal at or beyond the wall: BearingStateError with
  the distance, whatever the action -- a polynomial far from its data is not a force.

``last_out_of_domain`` tells the caller (the FMU's ``out_of_domain`` output) about the last
evaluated state.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..base import BearingStateError, check_finite
from ..catalogue import DEFAULT_DOMAIN_LIMIT as DEFAULT_LIMIT
from ..catalogue import DOMAIN_ACTIONS
from .nearest import TOLERANCE, NearestTraining, linear_radius

REARM = 50  # evaluations inside that end an excursion (about 25 time steps of a run)
FALLBACK_BAND = 0.1  # fallback: Taylor and truth blended from the domain's edge to 10 % beyond it
class DomainGuard:
    """A Taylor internal behind its domain guard (see the module docstring).

    taylor   : the ``Taylor`` internal
    action   : "warn" | "fallback" | "discard"
    limit    : refuse states more than this far outside (relative excess, > 0)
    truth    : zero-argument callable returning the fallback internal (Reynolds); needed for
               "fallback", called at the first exit only
    on_warn  : callable(message) for the one warning per excursion (default: warnings.warn)
    """

    def __init__(self, taylor, action: str = "warn", limit: float = DEFAULT_LIMIT, truth=None, on_warn=None):
        action = str(action).strip().lower()
        if action not in DOMAIN_ACTIONS:
            raise ValueError(f"domain_action = {action!r}; choose one of {', '.join(DOMAIN_ACTIONS)}")
        if not (math.isfinite(limit) and limit > 0.0):
            raise ValueError(f"domain_limit = {limit!r} must be a finite number > 0 (relative excess over the "
                             "fitted domain's bounds, e.g. 0.5 = 50 % beyond)")
        if action == "fallback" and truth is None:
            raise ValueError("domain_action = 'fallback' needs the truth internal (Reynolds) to fall back to")
        self.taylor = taylor
        self.params = taylor.params
        self.action = action
        self.limit = float(limit)
        self._truth_factory = truth
        self._truth = None
        self._on_warn = on_warn or (lambda msg: warnings.warn(msg, stacklevel=3))
        self.outside = False  # the last state selected lay outside (its excursion was warned); a caller may reset it
        self._inside_run = REARM  # evaluations inside since the last one outside
        self.last_out_of_domain = False
        self.last_distance = -math.inf

    @classmethod
    def from_options(cls, params, options, context) -> "DomainGuard":
        """The taylor internal from the registry's checked options (``internals.REGISTRY["taylor"]``):
        the surrogate file (``context.path`` finds it), checked against ``params``, behind its guard;
        the fallback builds Reynolds from the reynolds options at the first exit only. A file
        without stored training states (written before them) is guarded by its bounds only,
        which the warning sink hears once, here."""
        if not options["surrogate"]:
            raise ValueError("internal 'taylor' needs the option surrogate (a surrogate JSON file)")
        from .taylor import Taylor

        guard = cls(Taylor.from_file(context.path(options["surrogate"]), params), options["domain_action"],
                    options["domain_limit"], truth=lambda: _reynolds(params, options), on_warn=context.warn)
        if guard.taylor.surrogate.neighbours is None:
            guard._on_warn(f"surrogate {options['surrogate']!r} stores no training states (key 'neighbours', "
                           "written before the nearest-neighbour guard): its domain guard checks the fitted "
                           "domain's bounds only, so a state inside them but far from every training orbit is not "
                           "flagged; fit it again, or add them (benchmarks/add_neighbours.py)")
        return guard

    @property
    def omega(self) -> float:
        return self.taylor.omega

    def in_domain(self, y: float, z: float, vy: float, vz: float) -> bool:
        return self.taylor.in_domain(y, z, vy, vz)

    def domain_distance(self, y: float, z: float, vy: float, vz: float) -> float:
        """The exact domain distance (``Taylor.domain_distance``): what a run's domain report uses."""
        return self.taylor.domain_distance(y, z, vy, vz)

    def distance(self, y: float, z: float, vy: float, vz: float) -> float:
        """The state's domain distance d (``Taylor.domain_distance``: bounds and nearest training
        state), skipping the KD-tree query inside where it can: exact when > 0, else <= 0."""
        d = self.taylor.bounds_distance(y, z, vy, vz)
        near = self.taylor.neighbours
        if near is None or d != d:
            return d
        return max(d, near.distance(y, z, vy, vz, exact=False))

    def _select(self, y, z, vy, vz):
        """The internal that evaluates this state, or raise BearingStateError."""
        d = self.distance(y, z, vy, vz)
        self.last_distance = d
        ood = not (d <= 1e-12)  # NaN (non-finite input) counts as outside; Taylor names the variable
        self.last_out_of_domain = ood
        if not ood:
            # an excursion ends once the state has stayed inside for REARM evaluations: Newton
            # iterates dithering across the edge are one excursion, one warning (the FMU sets
            # ``outside`` from its committed state instead)
            self._inside_run += 1
            if self._inside_run >= REARM:
                self.outside = False
            return self.taylor
        self._inside_run = 0
        check_finite(y, z, vy, vz, 0.0)
        ecc = math.hypot(y, z) / self.params.CR
        where = (f"y = {y:.4g} m, z = {z:.4g} m, vy = {vy:.4g} m/s, vz = {vz:.4g} m/s "
                 f"(eccentricity ratio {ecc:.3f})")
        if ecc >= 1.0:
            raise BearingStateError(f"eccentricity ratio {ecc:.4g} >= 1: the journal is at or beyond the wall "
                                    f"({where}); the Taylor surrogate does not evaluate there")
        if d > self.limit or self.action == "discard":
            why = (f"more than domain_limit = {self.limit:g} beyond" if d > self.limit
                   else "outside (domain_action = 'discard')")
            raise BearingStateError(f"state {100 * d:.3g} % beyond the surrogate's fitted domain "
                                    f"({self._reasons(y, z, vy, vz)}), {why}: {where}")
        if not self.outside:
            self.outside = True
            what = ("the Reynolds internal evaluates such states" if self.action == "fallback"
                    else "its value is an extrapolation")
            self._on_warn(f"state outside the surrogate's fitted domain ({self._reasons(y, z, vy, vz)}) at {where}; "
                          f"{what} (warned once per excursion)")
        if self.action == "fallback":
            if self._truth is None:
                self._truth = self._truth_factory()
            return self._truth
        return self.taylor

    def _reasons(self, y, z, vy, vz) -> str:
        """Which part of the domain distance the state violates, in words (for messages)."""
        parts = []
        b = self.taylor.bounds_distance(y, z, vy, vz)
        if b > 1e-12:
            parts.append(f"{100 * b:.3g} % beyond its bounds")
        near = self.taylor.neighbours
        if near is not None:
            nn, _ = near.nearest(y, z, vy, vz)
            if nn > near.radius:
                how = f" (their spacing {near.cv_radius:.3g}, widened to where the fit was checked)" * (
                    near.widening > 0.0)
                parts.append(f"nearest training state {nn:.3g} away in the scaled state u, {nn / near.radius:.3g} x "
                             f"their radius {near.radius:.3g}{how}, {100 * (nn - near.radius) / near.size:.3g} % of "
                             f"the domain's size {near.size:.3g} beyond it")
        return " and ".join(parts) or "at its edge"

    def _blend_weight(self, d: float | None = None) -> float:
        """Weight of the truth in fallback mode at domain distance d (default: the state just
        selected): 0 inside the domain, rising smoothly (smoothstep) to 1 at FALLBACK_BAND."""
        x = min(max((self.last_distance if d is None else d) / FALLBACK_BAND, 0.0), 1.0)
        return x * x * (3.0 - 2.0 * x)

    def _blend_gradient(self, y, z, vy, vz):
        """d(weight)/d(y, z, vy, vz) by central differences of the domain distance (its
        active bound or nearest training state changes from state to state; 8 calls, in the
        band only)."""
        s = self.taylor.surrogate
        x = [y, z, vy, vz]
        h = [1e-7 * s.pos_scale, 1e-7 * s.pos_scale, 1e-7 * s.vel_scale, 1e-7 * s.vel_scale]
        g = np.empty(4)
        for i in range(4):
            hi, lo = list(x), list(x)
            hi[i] += h[i]
            lo[i] -= h[i]
            g[i] = (self._blend_weight(self.distance(*hi)) - self._blend_weight(self.distance(*lo))) / (2 * h[i])
        return g

    def compiled_force(self):
        """Its force and Jacobian inside the fitted domain as a compiled kernel
        (``internals.compiled``, ``guard_kernels``): outside it the kernel hands the state back
        and this guard decides (warn, fall back, refuse)."""
        from ..compiled import CompiledForce
        from .kernels import pack, taylor_kernel

        t, near = self.taylor, self.taylor.neighbours
        meta, exps, coef, *shape = t._args
        sexps, scoef = shape if shape else (None, None)
        data = pack(meta, t._dom, exps, coef, sexps, scoef, None if near is None else near.points,
                    near.radius if near is not None else 0.0, near.size if near is not None else 1.0, t._cr2)
        return CompiledForce(taylor_kernel, data, sync=self._kept_inside)

    def _kept_inside(self, n: int) -> None:
        """n evaluations the compiled kernel answered inside the domain were kept: the
        excursion bookkeeping ``_select`` does for each."""
        if n > 0:
            self.last_out_of_domain = False
            self._inside_run += n
            if self._inside_run >= REARM:
                self.outside = False

    def force(self, y: float, z: float, vy: float, vz: float, omega: float):
        internal = self._select(y, z, vy, vz)
        if internal is self.taylor or internal is not self._truth:
            return internal.force(y, z, vy, vz, omega)
        w = self._blend_weight()
        if w >= 1.0:
            return internal.force(y, z, vy, vz, omega)
        f_r, f_t = internal.force(y, z, vy, vz, omega), self.taylor.force(y, z, vy, vz, omega)
        return tuple((1.0 - w) * a + w * b for a, b in zip(f_t, f_r))

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        internal = self._select(y, z, vy, vz)
        out = _jacobian(internal, y, z, vy, vz, omega)
        if internal is self.taylor or internal is not self._truth:
            return out
        w = self._blend_weight()
        if w >= 1.0:
            return out
        # A hard switch at the domain's edge is a jump in the force, and Newton stalls on a
        # state that sits on it; blending over a thin band keeps the force continuous. Across
        # the band the force changes by F_truth - F_taylor, so the weight's gradient belongs
        # in the tangent: without it Newton diverges where the two differ by much.
        tay = self.taylor.force_and_jacobian(y, z, vy, vz, omega)
        F, dq, dv = ((1.0 - w) * np.asarray(a, float) + w * np.asarray(b, float) for a, b in zip(tay, out))
        dw = self._blend_gradient(y, z, vy, vz)
        diff = np.asarray(out[0], float) - np.asarray(tay[0], float)
        return F, dq + np.outer(diff, dw[:2]), dv + np.outer(diff, dw[2:])


    @property
    def film_flow_why(self) -> str:
        """'' when the surrogate file has its film fit, else why not (``Taylor.film_flow_why``)."""
        return self.taylor.film_flow_why

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float):
        """The film's friction and flows (``physics.solver.film.FilmReport``) as the force is guarded: inside
        the fitted domain the surrogate's film fit (``Taylor.film_report``), with no bookkeeping (the
        force call at the state has done it); outside it what ``force`` does (warn: the surrogate's
        value, once warned; fallback: the Reynolds report, blended over the same band; discard or
        beyond domain_limit: BearingStateError), so the report never extrapolates silently."""
        if self.distance(y, z, vy, vz) <= 1e-12:
            return self.taylor.film_report(y, z, vy, vz, omega)
        internal = self._select(y, z, vy, vz)
        if internal is self.taylor:
            return self.taylor.film_report(y, z, vy, vz, omega)
        w = self._blend_weight()
        truth = internal.film_report(y, z, vy, vz, omega)
        if w >= 1.0:
            return truth
        tay = self.taylor.film_report(y, z, vy, vz, omega)
        return type(truth)(**{k: (1.0 - w) * a + w * b for (k, a), b in zip(tay.as_dict().items(),
                                                                            truth.as_dict().values())})


def _reynolds(params, options):
    from ...physics.solver.reynolds import Reynolds

    return Reynolds.from_options(params, options)


def _jacobian(internal, y, z, vy, vz, omega):
    jac = getattr(internal, "force_and_jacobian", None)
    if jac is None:
        from ...physics.statics import film_jacobian

        return film_jacobian(internal, y, z, vy, vz, omega)
    return jac(y, z, vy, vz, omega)


__all__ = ["DomainGuard", "NearestTraining", "linear_radius", "DOMAIN_ACTIONS", "DEFAULT_LIMIT", "TOLERANCE"]
