"""What goes into and comes out of the Newmark integrator (``newmark``): its settings
(``NewmarkConfig``), its time history (``NewmarkResult``, saved and loaded as npz), and the
error that carries what was computed before a failure (``IntegrationError``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .forces import check_tangent

# =============================================================================== errors

class IntegrationError(RuntimeError):
    """The integration could not continue. ``result`` holds everything computed so far
    (status "failed"); ``t``, ``iterations``, ``residual`` describe the failing step;
    ``state`` = (t, q, v, a) is the last accepted state (possibly between output times)."""

    def __init__(self, message: str, result: "NewmarkResult | None" = None, *, t: float = math.nan,
                 iterations: int = 0, residual: float = math.nan, state=None):
        super().__init__(message)
        self.result = result
        self.t = t
        self.iterations = iterations
        self.residual = residual
        self.state = state


# =============================================================================== config / result

@dataclass
class NewmarkConfig:
    """Integrator settings.

    alpha: HHT parameter in [-1/3, 0]; 0 = average acceleration (no numerical damping).
    beta, gamma: Newmark parameters; None = the HHT values (1 - alpha)^2 / 4 and 1/2 - alpha.
    rtol_force: residual tolerance relative to ||f_ext|| + ||f_nl|| + ||M a||.
    rtol_disp, atol_disp: tolerance on the Newton correction, relative to ||q|| plus absolute.
    max_iter: Newton corrections allowed per step (force evaluations <= max_iter + 1).
    max_halvings: how many times a step may be halved before IntegrationError.
    tangent: the Newton tangent, one of ``rotor_host.integrate.forces.NEWTON_TANGENTS``. "bearing" and
        "frozen" = use the derivatives evaluate returns (whether they change or stay fixed is
        the force's business), the linear tangent if it returns none (modified Newton);
        "fd" = the same, but finite differences when it returns none (m extra evaluations per
        tangent, kept across steps and refreshed when the chord iteration gets slow);
        "linear" = never use the nonlinear tangent.
    fd_rel, fd_qtyp: finite-difference step h_j = fd_rel * max(|q_j|, fd_qtyp) (q units).
    trace: keep each step's residual norms ||R(q_k)|| (one array per attempt) in the result.
    compiled: run chunks of steps in one compiled call (``newmark_loop``) when the nonlinear
        force offers compiled kernels (same numbers, same Newton statistics); False: the Python
        driver always (for comparisons and benchmarks).
    """

    alpha: float = 0.0
    beta: float | None = None
    gamma: float | None = None
    rtol_force: float = 1e-8
    rtol_disp: float = 1e-8
    atol_disp: float = 0.0
    max_iter: int = 20
    max_halvings: int = 6
    tangent: str = "bearing"
    fd_rel: float = 1.5e-8
    fd_qtyp: float = 1e-6
    trace: bool = False
    compiled: bool = True

    def __post_init__(self):
        if not (-1.0 / 3.0 - 1e-15 <= self.alpha <= 0.0):
            raise ValueError(f"HHT alpha must lie in [-1/3, 0], got {self.alpha}")
        if self.beta is None:
            self.beta = (1.0 - self.alpha) ** 2 / 4.0
        if self.gamma is None:
            self.gamma = 0.5 - self.alpha
        if not self.beta > 0.0:
            raise ValueError(f"Newmark beta must be > 0, got {self.beta}")
        check_tangent(self.tangent, "NewmarkConfig.tangent")
        if self.max_iter < 1 or self.max_halvings < 0:
            raise ValueError("max_iter must be >= 1 and max_halvings >= 0")


@dataclass
class NewmarkResult:
    """Time history on the output grid.

    t (n_out,); q, v (n_out, len(dofs)) for the recorded DOFs ``dofs``; f_nl (n_out, m) the
    nonlinear force on ``nl_dofs``; iterations (n_steps,) force evaluations (= Newton
    iterations, 1 = predictor accepted) spent on each grid step, failed attempts and sub-steps
    included; n_cuts step halvings; n_evaluations all force evaluations (incl. the initial
    one and finite differences); wall_time [s]; status "ok" or "failed" with message; extra
    (n_out, ...) what ``Newmark.run``'s ``record_extra`` returned at each record (None without it).
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    f_nl: np.ndarray
    dofs: np.ndarray
    nl_dofs: np.ndarray
    iterations: np.ndarray
    n_cuts: int = 0
    n_evaluations: int = 0
    wall_time: float = 0.0
    status: str = "ok"
    message: str = ""
    residual_history: list | None = field(default=None, repr=False)
    extra: np.ndarray | None = field(default=None, repr=False)

    @property
    def mean_iterations(self) -> float:
        return float(np.mean(self.iterations)) if self.iterations.size else 0.0

    def save(self, path) -> Path:
        path = Path(path)
        np.savez(path, t=self.t, q=self.q, v=self.v, f_nl=self.f_nl, dofs=self.dofs,
                 nl_dofs=self.nl_dofs, iterations=self.iterations, n_cuts=self.n_cuts,
                 n_evaluations=self.n_evaluations, wall_time=self.wall_time,
                 status=self.status, message=self.message)
        return path if path.suffix == ".npz" else path.with_name(path.name + ".npz")

    @classmethod
    def load(cls, path) -> "NewmarkResult":
        with np.load(path) as d:
            return cls(t=d["t"], q=d["q"], v=d["v"], f_nl=d["f_nl"], dofs=d["dofs"],
                       nl_dofs=d["nl_dofs"], iterations=d["iterations"], n_cuts=int(d["n_cuts"]),
                       n_evaluations=int(d["n_evaluations"]), wall_time=float(d["wall_time"]),
                       status=str(d["status"]), message=str(d["message"]))


__all__ = ["IntegrationError", "NewmarkConfig", "NewmarkResult"]
