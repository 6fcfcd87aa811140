"""The compiled Newmark driver: whole chunks of steps, Newton iterations and bearing force
evaluations included, in one numba call (``run_chunk``).

It makes the decisions of ``Newmark._attempt`` (``rotor_host.integrate.newmark``) with the same
kernels (``newmark_kernels``), in the same order, so it gives the same numbers and the same
Newton statistics. The forces are compiled kernels of the bearing internals
(``bearing_fmu.internals.compiled``: first-class functions of one signature, so this loop is
compiled once and cached on disk for all of them); the external force is ``loads.rotating_loads``.
Whatever is not the plain path hands the step back to Python untouched: a state a kernel
refuses, a Newton failure (which Python redoes and then cuts), a singular predictor. The
chunk returns the index of the first step it did not do; the state X, the last force f0 and
the predictor's tangent are then those at that step's start, as the Python driver expects.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from bearing_fmu.internals.compiled import OUT_SIZE, address, advance, kernel_at
from bearing_fmu.io.interrupts import enter_deferred, leave_deferred

from .loads import rotating_loads
from .newmark_kernels import Q0, Q1, k_accept, k_begin, k_iter

__all__ = ["run_chunk", "ChunkBuffers", "ChunkDriver", "CFG_SIZE", "CNT_STEPS", "CNT_EVAL", "CNT_REC", "CNT_HAVE_J",
           "CNT_WHY"]

# cfg (float64): rtol_force, rtol_disp, atol_disp, max_iter, alpha, t0, dt, Ma_norm (in/out)
CFG_SIZE = 8
_MA = 7
# cnt (int64), in/out: steps done, force evaluations, records, have_J (the predictor's tangent
# is the force's own), why the chunk stopped early (0: it did not)
CNT_STEPS, CNT_EVAL, CNT_REC, CNT_HAVE_J, CNT_WHY = range(5)
WHY_REFUSED, WHY_PREDICTOR, WHY_NEWTON = 1, 2, 3


class ChunkBuffers:
    """The loop's own work arrays for m nonlinear DOFs (allocated once per run)."""

    def __init__(self, n: int, m: int):
        self.fe1 = np.zeros(n)
        self.f = np.zeros(m)
        self.f0 = np.zeros(m)
        self.Jq = np.zeros((m, m))
        self.Jv = np.zeros((m, m))
        self.Z = np.zeros((m, m))
        self.Jsave = np.zeros((2, m, m))
        self.out = np.zeros(OUT_SIZE)
        self.cfg = np.zeros(CFG_SIZE)
        self.cnt = np.zeros(5, dtype=np.int64)


@njit(cache=True)
def _forces(kaddr, data, doff, omega, qP, vP, out, f, Jq, Jv):
    """Every bearing's kernel at the iterate: f and the block-diagonal tangent (Jq, Jv hold
    zeros off the 2 x 2 blocks). Bearing b's kernel is at address kaddr[b], its data at
    data[doff[b]:]. False when a kernel refuses its state."""
    base = address(data.ctypes.data)
    op = address(out.ctypes.data)
    for b in range(kaddr.size):
        i = 2 * b
        kernel = kernel_at(kaddr[b])
        status = kernel(advance(base, doff[b]), qP[i], qP[i + 1], vP[i], vP[i + 1], omega, op)
        if status != 0:
            return False
        f[i] = out[0]
        f[i + 1] = out[1]
        for r in range(2):
            for c in range(2):
                Jq[i + r, i + c] = out[2 + 4 * r + c]
                Jv[i + r, i + c] = out[4 + 4 * r + c]
    return True


@njit(cache=True)
def run_chunk(kaddr, data, doff, omega, clock, k0, k1, X, MDK, SB, W, MB, dofs, cs, V, Pm, AJ,
              loads_static, loads_idx, loads_par, fe0, fe1, f0, f, Jq, Jv, Z, Jsave, out, cfg, cnt,
              iters, rec, rec_every, out_t, out_q, out_v, out_f):
    """Steps k0 .. k1 - 1 of the run (t = t0 + k dt) at the full step dt. Returns the index of
    the first step not done (k1 when all were); cnt[CNT_WHY] says why it stopped early. clock
    (t, h) is the step's start and size, written at each step for kernels that read it (a
    bearing FMU's doStep: ``rotor_host.coupling.fmu_kernel``)."""
    rtol_f, rtol_q, atol_q = cfg[0], cfg[1], cfg[2]
    max_iter = int(cfg[3])
    alpha, t0, dt = cfg[4], cfg[5], cfg[6]
    n = X.size // 3
    m = dofs.size
    qP, vP = Pm[0], Pm[1]
    Jql, Jvl = AJ[2], AJ[3]
    cnt[CNT_WHY] = 0
    for k in range(k0, k1):
        t_b = t0 + (k + 1) * dt
        clock[0] = t0 + k * dt
        clock[1] = dt
        rotating_loads(loads_static, loads_idx, loads_par, t_b, fe1)
        have_J = cnt[CNT_HAVE_J] != 0
        for i in range(m):  # the predictor's tangent, restored if the step goes back to Python
            for j in range(m):
                Jsave[0, i, j] = Jql[i, j]
                Jsave[1, i, j] = Jvl[i, j]
        if have_J:
            ok, fe1n, bn = k_begin(X, MDK, SB, W, dofs, fe1, fe0, f0, Jql, Jvl, cs, V, Pm, AJ)
        else:
            ok, fe1n, bn = k_begin(X, MDK, SB, W, dofs, fe1, fe0, f0, Z, Z, cs, V, Pm, AJ)
        if not ok:
            cnt[CNT_WHY] = WHY_PREDICTOR
            return k
        fscale = fe1n + cfg[_MA]
        floor = 1e-13 * bn
        iq = Q0
        its = 0
        done = False
        for it in range(max_iter + 1):
            its += 1
            if not _forces(kaddr, data, doff, omega, qP, vP, out, f, Jq, Jv):
                cnt[CNT_WHY] = WHY_REFUSED
                break
            rn, dn, qnorm, fn, okc = k_iter(iq, f, Jq, Jv, SB, W, dofs, cs, V, Pm, AJ)
            tol = rtol_f * (fscale + fn) + floor
            if rn <= tol and dn <= rtol_q * qnorm + atol_q:
                done = True
                break
            if not (math.isfinite(rn) and math.isfinite(dn)) or not okc or it == max_iter:
                cnt[CNT_WHY] = WHY_NEWTON
                break
            iq = Q0 + Q1 - iq
        if not done:
            for i in range(m):
                for j in range(m):
                    Jql[i, j] = Jsave[0, i, j]
                    Jvl[i, j] = Jsave[1, i, j]
            return k
        # accept: the iterate just evaluated is the state at t_b
        cfg[_MA] = k_accept(X, iq, cs, V, MB)
        if alpha != 0.0:
            for i in range(n):
                fe0[i] = fe1[i]
        for j in range(m):
            f0[j] = f[j]
        cnt[CNT_HAVE_J] = 1
        cnt[CNT_EVAL] += its
        cnt[CNT_STEPS] = k + 1
        iters[k] = its
        if (k + 1) % rec_every == 0:
            r = (k + 1) // rec_every
            out_t[r] = t0 + r * rec_every * dt
            for i in range(rec.size):
                out_q[r, i] = X[rec[i]]
                out_v[r, i] = X[n + rec[i]]
            for j in range(m):
                out_f[r, j] = f0[j]
            cnt[CNT_REC] = r + 1
    return k1


class ChunkDriver:
    """The compiled driver's side of a run of ``integ`` (a ``newmark.Newmark``): its buffers,
    and the state handed to and from ``run_chunk`` (the integrator's run state stays the one
    record). ``plan`` = (forces, omega), (forces, omega, clock) or (forces, omega, clock,
    (enter, leave)) from ``NodalForce.compiled`` (clock: the float64 (2,) array the forces read
    the step's (t, h) from; such forces call foreign code, FMUs, so signals are held while a
    chunk runs, as the Python driver holds them around each FMU call:
    ``bearing_fmu.io.interrupts.deferred``; enter() before every chunk and leave(gave_back) after it,
    gave_back True when the chunk stopped at a step Python redoes: forces with a state over the
    step hand it between the two drivers there); ``rec`` the recorded DOFs."""

    def __init__(self, integ, plan, n: int, rec):
        self.integ = integ
        forces, self.omega = plan[0], float(plan[1])
        self.foreign = len(plan) > 2
        self.clock = plan[2] if self.foreign else np.zeros(2)
        self.enter, self.leave = plan[3] if len(plan) > 3 else (None, None)
        self.forces = forces  # keeps the kernels and their data alive while their addresses are used
        self.kaddr = np.array([cf.address for cf in forces], dtype=np.int64)
        self.data = np.ascontiguousarray(np.concatenate([cf.data for cf in forces]), dtype=np.float64)
        self.doff = np.cumsum([0] + [cf.data.size for cf in forces])[:-1].astype(np.int64)
        m = integ.dofs.size
        self.b = ChunkBuffers(n, m)
        cfg = integ.cfg
        self.b.cfg[:7] = (cfg.rtol_force, cfg.rtol_disp, cfg.atol_disp, cfg.max_iter, cfg.alpha, 0.0, 0.0)
        self.rec = np.ascontiguousarray(rec, dtype=np.int64)

    def run(self, k0: int, k1: int) -> int:
        """Steps k0 .. k1 - 1 compiled; returns the first step not done."""
        integ = self.integ
        st, b = integ._state, self.b
        ops = integ._ops_cache.get(st.dt) or integ._ops(st.dt)
        b.f0[:] = st.f0
        b.cfg[5], b.cfg[6], b.cfg[7] = st.t0, st.dt, st.Ma_norm
        cnt = b.cnt
        cnt[:] = (st.steps_done, st.n_eval, st.n_rec, int(st.have_J), 0)
        loads = integ._loads
        n_eval = st.n_eval
        if self.enter is not None:
            self.enter()
        if self.foreign:
            enter_deferred()
        try:
            k = run_chunk(self.kaddr, self.data, self.doff, self.omega, self.clock, k0, k1, st.X, ops.MDK, ops.SB,
                          ops.W, integ.MB, integ.dofs, ops.cs, st.V, st.Pm, st.AJ, loads.f_static, loads.idx,
                          loads.par, st.fe0, b.fe1, b.f0, b.f, b.Jq, b.Jv, b.Z, b.Jsave, b.out, b.cfg, cnt, st.iters,
                          self.rec, st.record_every, st.out_t, st.out_q, st.out_v, st.out_f)
            self._kept(k0, k, n_eval)
            if self.leave is not None:
                self.leave(k < k1)
        finally:
            if self.foreign:
                leave_deferred()  # a signal held meanwhile is raised here, the steps done kept
        return k

    def _kept(self, k0: int, k: int, n_eval: int) -> None:
        """The run state after a chunk that did steps k0 .. k - 1."""
        st, b, cnt = self.integ._state, self.b, self.b.cnt
        # the forces were evaluated in this chunk: a step handed back opens its own bracket
        # (begin_step; a memoryless FMU is told there that the step is tried again)
        st.in_first_bracket = False
        if k > k0:
            st.steps_done, st.n_eval, st.n_rec = int(cnt[CNT_STEPS]), int(cnt[CNT_EVAL]), int(cnt[CNT_REC])
            st.have_J = bool(cnt[CNT_HAVE_J])
            st.Ma_norm = float(b.cfg[7])
            st.f0 = b.f0.copy()
            st.t = st.t0 + k * st.dt
            st.in_first_bracket = False
            kept = st.n_eval - n_eval  # evaluations per bearing in the steps kept
            for cf in self.forces:
                if cf.sync is not None:
                    cf.sync(kept)
