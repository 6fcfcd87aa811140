"""The state of one Newmark run and what it records (``newmark``): the work arrays a step
uses, the output grid, the Newton statistics, and the partial result that a checkpoint, an
interrupt or a failure keeps (``RunState.result``)."""

from __future__ import annotations

import numpy as np

from .newmark_data import NewmarkResult

__all__ = ["RunState"]


class RunState:
    """The state of one ``Newmark.run``: the step's work arrays (X = (q, v, a), the Newton rows V,
    the nonlinear DOFs' values and tangents), the force's last tangent, and the records on the
    output grid with the Newton statistics. The compiled driver (``newmark_loop``) reads and
    writes the same arrays."""

    def __init__(self, n, m, n_steps, n_out, rec, trace, tangent):
        self.X = np.zeros(3 * n)
        self.V = np.zeros((10, n))
        self.Pm = np.zeros((4, m))
        self.AJ = np.zeros((4, m, m))
        self.qP, self.vP = self.Pm[0], self.Pm[1]
        self.fe0 = np.zeros(n)
        self.f0 = np.zeros(m)
        self.fe_shape = (n,)
        self.f_shape = (m,)
        self.Jq_prev, self.Jv_prev = self.AJ[2], self.AJ[3]  # views: k_iter writes them
        self.Z = np.zeros((m, m))
        self.mm = (m, m)
        self.have_J = False
        self.use_fd = tangent == "fd"  # finite differences where the force returns no tangent
        self.tangent_linear = tangent == "linear"  # never the force's tangent
        self.fd_J = None
        self.fd_h = None
        self.fd_stale = True
        self.rec = rec
        self.rec_all = rec.size == n and bool(np.all(rec == np.arange(n)))
        self.out_t = np.zeros(n_out)
        self.out_q = np.zeros((n_out, rec.size))
        self.out_v = np.zeros((n_out, rec.size))
        self.out_f = np.zeros((n_out, m))
        self.iters = np.zeros(n_steps, dtype=np.int32)
        self.step_its = 0
        self.n_rec = 0
        self.steps_done = 0
        self.n_cuts = 0
        self.n_eval = 0
        self.Ma_norm = 0.0
        self.trace = [] if trace else None
        self.in_first_bracket = False
        self.extra_fn, self.out_x = None, []  # record_extra and its records
        self.t0 = self.t = self.dt = 0.0  # the run's start, current time and step [s] (set by run)
        self.record_every = 1

    def record(self, i: int) -> None:
        """Record the current state as output i (at t0 + i record_every dt)."""
        n = self.X.size // 3
        self.out_t[i] = self.t0 + i * self.record_every * self.dt
        if self.rec_all:
            self.out_q[i] = self.X[:n]
            self.out_v[i] = self.X[n:2 * n]
        else:
            self.out_q[i] = self.X[:n][self.rec]
            self.out_v[i] = self.X[n:2 * n][self.rec]
        self.out_f[i] = self.f0
        if self.extra_fn is not None:  # what the force had at its recorded evaluation (the last one)
            self.out_x[i:] = [np.array(self.extra_fn(), dtype=float)]
        self.n_rec = i + 1

    def result(self, nl_dofs, wall_time: float, status: str = "ok", message: str = "") -> NewmarkResult:
        """What has been recorded so far, as copies: the result at the end, a checkpoint while
        running, or what an interrupted or failed run keeps."""
        k = self.n_rec
        return NewmarkResult(
            t=self.out_t[:k].copy(), q=self.out_q[:k].copy(), v=self.out_v[:k].copy(), f_nl=self.out_f[:k].copy(),
            dofs=self.rec.copy(), nl_dofs=nl_dofs.copy(), iterations=self.iters[:self.steps_done].copy(),
            n_cuts=self.n_cuts, n_evaluations=self.n_eval, wall_time=wall_time,
            status=status, message=message, residual_history=self.trace,
            extra=None if self.extra_fn is None else np.array(self.out_x[:k]))
