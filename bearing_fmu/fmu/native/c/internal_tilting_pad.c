/* The tilting-pad internal (bearing_fmu/internals/tilting_pad: assembly.py, stepping.py): every
 * pad the C Reynolds solver (reynolds_solver.c) of the pad frame's partial arc (model_data.h:
 * generators/tilting_pad.py), at the equivalent journal state of its tilt delta and rate w
 * (y' + a delta, z', vy' + a w, vz' in the pad's frame, a = R + C_pad), its moment about the pivot
 * M = a F'y. The same equations and Newton iterations as the Python internal, line by line:
 *   Initialization Mode   the pads massless and in moment equilibrium, M_k(delta_k) = 0
 *                         (PadAssembly._moment_root), the Jacobian quasi-static
 *                         (quasi_static_jacobian); the tilts become the pads' state (rates 0);
 *                         Model Exchange: the outputs then at that state as below
 *   Co-Simulation step    BDF2 from the committed pads to the step's end (PadStepper.solve: backward
 *                         Euler after a static state), the Jacobian total (the pads following)
 *   Model Exchange        the pads at their states (Instance.r, set by fmi2SetContinuousStates):
 *                         massless, the rate whose squeeze balances the moment (PadAssembly.derivatives,
 *                         the Jacobian with that rate following); with inertia d rate/dt = M / I
 * (a Co-Simulation evaluation after a step, a directional derivative: that step again from its
 * start, kept in Instance.pads; before the first step: the pads at the committed state as Model
 * Exchange's). Each pad has a solver of its own (its own warm start),
 * one memory block for all, allocated when the parameters are fixed, freed with the instance. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#define BN_PART tilting_pad /* its functions' names in an FMU of several internals */
#define BN_PART_TILTING_PAD 1
#include "bearing_native.h"
#include "model_data.h"
#include "reynolds_solver.h"

#define NEWTON_EQ 120   /* assembly.NEWTON_MAX */
#define NEWTON_STEP 60  /* stepping.NEWTON_MAX */
#define WALL_MARGIN 1e-9 /* assembly.WALL_MARGIN */

static const double RS_EDGE_DATA[] = RS_EDGES;
static const int RS_FIXED_DATA[] = RS_SEG_FIXED;
static const double RS_SUPPLY_DATA[] = RS_SEG_SUPPLY;
static const double WALL_A[] = RS_WALL_A; /* the pad frame's closure weights */
static const double WALL_B[] = RS_WALL_B;
static const double PAD_COS[TP_N] = TP_COS; /* Rot(alpha_k) = [[c, -s], [s, c]], alpha_k = pi - theta_p,k */
static const double PAD_SIN[TP_N] = TP_SIN;
static const double PAD_DEG[TP_N] = TP_PIVOT_DEG;

/* one pad in its frame: force, dF/de', dF/dv' (row-major 2 x 2), dF/domega */
typedef struct {
    double F[2], Jq[4], Jv[4], Jw[2];
} Frame;

/* one pad in the bearing's frame: its force, Jacobians, dF/domega, and the moment's derivatives */
typedef struct {
    double F[2], Jq[4], Jv[4], Jw[2], M;
} Pad;

static double arm(const Instance *m) { return 0.5 * m->r[VR_D] + m->r[VR_CR] / (1.0 - TP_PRELOAD); }

#if TP_MAP
#include "pad_map.h" /* every pad from the pads' map: map_pad, pad_clearance */
#elif BN_FLOWS_TILTING_PAD
#include "film_friction.h" /* ff_power */
#endif

void bn_release(Instance *m) {
    if (m->work.block) m->release(m->work.block);
    m->work.block = NULL;
    m->work.solver = NULL;
    m->work.block_bytes = 0;
    for (int k = 0; k < BN_MAX_PADS; k++) m->work.pad_solver[k] = NULL;
}

static int build(Instance *m, int n_theta, int n_x) {
    size_t each = (rs_bytes(n_theta, n_x) + 15) / 16 * 16;
    char *mem = (char *)(((size_t)m->work.block + 15) / 16 * 16);
    int mode = strcmp(m->eff[S_OPT_CAVITATION], "gumbel") == 0 ? 0 : 1;
    char why[400];
    for (int k = 0; k < TP_N; k++) {
        m->work.pad_solver[k] = rs_create(mem + k * each, n_theta, n_x, mode, 1, m->r[VR_D], m->r[VR_L], m->r[VR_CR],
                                          m->r[VR_MU], RS_NSEG, RS_EDGE_DATA, RS_FIXED_DATA, RS_SUPPLY_DATA, RS_LOBES,
                                          RS_PRELOAD, RS_LOBE_OFFSET, RS_LOBE_ANGLE, why, sizeof why);
        if (!m->work.pad_solver[k]) {
            snprintf(m->msg, sizeof m->msg, "tilting pads: %s (%s)", why, TP_PADS_TEXT);
            return 1;
        }
    }
    m->work.solver = m->work.pad_solver[0];
    return 0;
}

int bn_setup(Instance *m) {
    int n_theta = BN_INT_OPTION(m, N_THETA), n_x = BN_INT_OPTION(m, N_X);
    /* 0: the defaults (the Python internal's: cells on each pad's arc, PadAssembly.default_cells) */
    if (n_theta == 0) n_theta = TP_DEFAULT_CELLS;
    if (n_x == 0) n_x = RS_DEFAULT_N_X;
    if (n_theta < 8 || n_theta > RS_MAX_CELLS || n_x < 2 || n_x % 2 || n_x > RS_MAX_CELLS) {
        snprintf(m->msg, sizeof m->msg, "tilting pads: the grid n_theta = %d (cells on each pad's arc), n_x = %d: "
                 "n_theta an integer >= 8, n_x an even integer >= 2, both at most %d (0: the default %d x %d)",
                 n_theta, n_x, RS_MAX_CELLS, TP_DEFAULT_CELLS, RS_DEFAULT_N_X);
        return 1;
    }
    n_theta += TP_EXTRA_CELLS; /* the frame's cells outside the pad's arc */
    size_t bytes = TP_N * ((rs_bytes(n_theta, n_x) + 15) / 16 * 16);
    if (m->work.block_bytes != bytes) {
        bn_release(m);
        m->work.block = m->allocate(1, bytes + 16);
        if (!m->work.block) {
            snprintf(m->msg, sizeof m->msg, "tilting pads: out of memory for %d pads of %d x %d cells (%.0f kB)", TP_N,
                     n_theta, n_x, (bytes + 16) / 1024.0);
            return 1;
        }
        m->work.block_bytes = bytes;
    }
    for (int k = 0; k < BN_MAX_PADS; k++) m->work.pad_warm[k] = 0.0;
    return build(m, n_theta, n_x);
}

/* ------------------------------------------------------------------------------ one pad */

/* the journal (x) and the tilt range of pad k that leaves its film open (assembly.tilt_range) */
static void tilt_range(const Instance *m, int k, const double x[5], double *lo, double *hi) {
    double c = PAD_COS[k], s = PAD_SIN[k], a = arm(m), cr = m->r[VR_CR] * (1.0 - WALL_MARGIN);
    double e0 = c * x[0] - s * x[1], e1 = s * x[0] + c * x[1], L = -INFINITY, H = INFINITY;
    int closed = 0, bad = 0;
    for (int i = 0; i < RS_NWALL; i++) {
        double room = cr - WALL_A[i] * e0 - WALL_B[i] * e1;
        if (WALL_A[i] != 0.0) {
            double u = room / (WALL_A[i] * a);
            if (!isfinite(u)) bad = 1;
            else if (WALL_A[i] > 0.0) H = u < H ? u : H;
            else L = u > L ? u : L;
        } else if (room <= 0.0) {
            closed = 1;
        }
    }
#if TP_MAP /* the map's domain (PadMapSolver.y_range): eps < eps_max of C_pad about the shifted centre */
    if (!bad) {
        double rr = MAP_EPS_MAX * (1.0 - 1e-9) * pad_clearance(m), zc = e1 - (pad_clearance(m) - m->r[VR_CR]);
        double w = fabs(zc) >= rr ? 0.0 : sqrt(rr * rr - zc * zc);
        L = fmax(L, (-w - e0) / a);
        H = fmin(H, (w - e0) / a);
    }
#endif
    *lo = bad || closed ? 0.0 : L;
    *hi = bad || closed ? 0.0 : H;
}

/* the journal at or beyond pad k's wall (assembly.wall_error's words); 1 */
static int wall_error(Instance *m, int k, const double x[5], double tilt) {
    char a[32], b[32], c[32], d[32], e[32], t[48] = "whatever its tilt";
    if (!isnan(tilt)) snprintf(t, sizeof t, "at its tilt %s rad", bn_num(e, 32, tilt, 4));
    snprintf(m->msg, sizeof m->msg, "eccentricity ratio %s: the journal (y = %s m, z = %s m) closes the film of the "
             "pad pivoted at %s deg %s (it is at or beyond that pad's wall; CR = %s m, %s)",
             bn_num(a, 32, hypot(x[0], x[1]) / m->r[VR_CR], 4), bn_num(b, 32, x[0], 4), bn_num(c, 32, x[1], 4),
             bn_num(d, 32, PAD_DEG[k], 4), t, bn_num(e, 32, m->r[VR_CR], 4), TP_PADS_TEXT);
    return 1;
}

/* pad k at tilt d and rate w with the journal at x: its frame's results (assembly._pad); 0, or 1 (m->msg) */
static int pad_frame(Instance *m, int k, const double x[5], double d, double w, Frame *f) {
    double c = PAD_COS[k], s = PAD_SIN[k], a = arm(m);
    double st[4] = {c * x[0] - s * x[1] + a * d, s * x[0] + c * x[1], c * x[2] - s * x[3] + a * w,
                    s * x[2] + c * x[3]};
    rs_solver *S = (rs_solver *)m->work.pad_solver[k];
    char b1[32], b2[32], b3[32], b4[32], b5[32];
    int status = RS_OVERFLOW;
#if TP_MAP
    if (isfinite(st[0]) && isfinite(st[1]) && isfinite(st[2]) && isfinite(st[3])) {
        double xs[5] = {st[0], st[1], st[2], st[3], x[4]};
        return map_pad(m, xs, f);
    }
#else
    if (isfinite(st[0]) && isfinite(st[1]) && isfinite(st[2]) && isfinite(st[3]))
        status = rs_call(S, st[0], st[1], st[2], st[3], x[4], 1);
#endif
    if (status == RS_NOT_CONVERGED) {
        snprintf(m->msg, sizeof m->msg, "tilting pads: the Reynolds active-set iteration of the pad pivoted at %s deg "
                 "did not converge in %d steps at y = %s m, z = %s m, omega = %s rad/s", bn_num(b1, 32, PAD_DEG[k], 4),
                 S->max_iter, bn_num(b2, 32, x[0], 17), bn_num(b3, 32, x[1], 17), bn_num(b4, 32, x[4], 17));
        return 1;
    }
    if (status == RS_OVERFLOW) { /* registry.overflow_error: the bearing's own input that drives it */
        static const char *const names[5] = {"y", "z", "vy", "vz", "omega"};
        static const char *const units[5] = {"m", "m", "m/s", "m/s", "rad/s"};
        double CR = m->r[VR_CR];
        double size[5] = {fabs(x[0]) / CR, fabs(x[1]) / CR, 2.0 * fabs(x[2]) / CR, 2.0 * fabs(x[3]) / CR, fabs(x[4])};
        int i, big = 0;
        for (i = 1; i < 5; i++)
            if (size[i] > size[big]) big = i;
        snprintf(m->msg, sizeof m->msg, "bearing input %s = %s %s is too large: it puts the film force and its "
                 "Jacobian beyond the floating-point range", names[big], bn_num(b5, 32, x[big], 17), units[big]);
        return 1;
    }
    memcpy(f->F, S->F, sizeof f->F);
    memcpy(f->Jq, S->dFq, sizeof f->Jq);
    memcpy(f->Jv, S->dFv, sizeof f->Jv);
    memcpy(f->Jw, S->dFw, sizeof f->Jw);
    return 0;
}

/* B = Rot^T A Rot (a 2 x 2 Jacobian into the bearing's frame) */
static void to_bearing2(double c, double s, const double A[4], double B[4]) {
    double T[4] = {A[0] * c + A[1] * s, -A[0] * s + A[1] * c, A[2] * c + A[3] * s, -A[2] * s + A[3] * c};
    B[0] = c * T[0] + s * T[2];
    B[1] = c * T[1] + s * T[3];
    B[2] = -s * T[0] + c * T[2];
    B[3] = -s * T[1] + c * T[3];
}

/* pad k's frame results in the bearing's frame (assembly._assemble) */
static void to_bearing(const Instance *m, int k, const Frame *f, Pad *p) {
    double c = PAD_COS[k], s = PAD_SIN[k];
    p->F[0] = c * f->F[0] + s * f->F[1];
    p->F[1] = -s * f->F[0] + c * f->F[1];
    p->Jw[0] = c * f->Jw[0] + s * f->Jw[1];
    p->Jw[1] = -s * f->Jw[0] + c * f->Jw[1];
    to_bearing2(c, s, f->Jq, p->Jq);
    to_bearing2(c, s, f->Jv, p->Jv);
    p->M = arm(m) * f->F[0];
}

/* t . J (a row) and J t (a column) with t = (c, -s), the pivot's tangent */
static void t_row(double c, double s, const double J[4], double out[2]) {
    out[0] = c * J[0] - s * J[2];
    out[1] = c * J[1] - s * J[3];
}
static void t_col(double c, double s, const double J[4], double out[2]) {
    out[0] = J[0] * c - J[1] * s;
    out[1] = J[2] * c - J[3] * s;
}

/* add the pad's follower term to the journal's Jacobian: the pad's scalar unknown (its tilt or its
 * rate) follows the journal as ds/dx = g_x / den, the force moving by Fs ds (g_q, g_v, g_w: the
 * numerators along q, v, omega) */
static void follow(const double Fs[2], const double gq[2], const double gv[2], double gw, double den, double J[8],
                   double dw[2]) {
    for (int i = 0; i < 2; i++) {
        J[4 * i + 0] += Fs[i] * gq[0] / den;
        J[4 * i + 1] += Fs[i] * gq[1] / den;
        J[4 * i + 2] += Fs[i] * gv[0] / den;
        J[4 * i + 3] += Fs[i] * gv[1] / den;
        dw[i] += Fs[i] * gw / den;
    }
}

/* the pad's own force, Jacobian and dF/domega into the sums */
static void add_pad(const Pad *p, double F[2], double J[8], double dw[2]) {
    for (int i = 0; i < 2; i++) {
        F[i] += p->F[i];
        J[4 * i + 0] += p->Jq[2 * i];
        J[4 * i + 1] += p->Jq[2 * i + 1];
        J[4 * i + 2] += p->Jv[2 * i];
        J[4 * i + 3] += p->Jv[2 * i + 1];
        dw[i] += p->Jw[i];
    }
}

/* ------------------------------------------------------------------------------ the three routes */

/* massless pad k in moment equilibrium, rate 0 (assembly._moment_root), from `start`: 0, or 1 */
static int moment_root(Instance *m, int k, const double x[5], double start, double *out, Frame *f) {
    double lo, hi, a = arm(m), CR = m->r[VR_CR], R = 0.5 * m->r[VR_D], omega = x[4];
    char b1[32], b2[32], b3[32], b4[32];
    tilt_range(m, k, x, &lo, &hi);
    if (!(lo < hi)) return wall_error(m, k, x, NAN);
    double span = isfinite(hi - lo) ? hi - lo : 1.0;
    double d = fmin(fmax(start, lo + 1e-3 * span), hi - 1e-3 * span);
    double tol = 1e-13 * CR / a;
    double m_scale = a * m->r[VR_MU] * (fabs(omega) + 2.0 * hypot(x[2], x[3]) / CR) * m->r[VR_L] * R * (R / CR) *
                     (R / CR);
    double m_tol = 1e-13 * m_scale;
    for (int it = 1; it <= NEWTON_EQ; it++) {
        if (pad_frame(m, k, x, d, 0.0, f)) return 1;
        double M = a * f->F[0], dM = a * a * f->Jq[0];
        if (M != 0.0 && fabs(M) <= m_tol) return *out = d, 0;
        if (M == 0.0 && dM == 0.0) { /* the pad carries nothing at this tilt */
            if (omega == 0.0) return *out = d, 0;
            if (omega > 0.0) lo = d;
            else hi = d;
        } else if (M > 0.0) {
            lo = d;
        } else {
            hi = d;
        }
        double step = dM < 0.0 ? -M / dM : NAN;
        if (fabs(step) <= tol) return *out = d, 0;
        double nxt = d + step;
        if (!(lo < nxt && nxt < hi)) nxt = 0.5 * (lo + hi);
        if (fabs(nxt - d) <= tol || hi - lo <= tol) {
            if (pad_frame(m, k, x, nxt, 0.0, f)) return 1;
            if (fabs(a * f->F[0]) > 1e-8 * m_scale) {
                snprintf(m->msg, sizeof m->msg, "tilting pads: the pad pivoted at %s deg finds no tilt that balances "
                         "its moment with its film open (moment %s N m left at the wall; y = %s m, z = %s m)",
                         bn_num(b1, 32, PAD_DEG[k], 4), bn_num(b2, 32, a * f->F[0], 4), bn_num(b3, 32, x[0], 4),
                         bn_num(b4, 32, x[1], 4));
                return 1;
            }
            return *out = nxt, 0;
        }
        d = nxt;
    }
    snprintf(m->msg, sizeof m->msg, "tilting pads: the moment of the pad pivoted at %s deg did not settle in %d Newton "
             "steps (y = %s m, z = %s m)", bn_num(b1, 32, PAD_DEG[k], 4), NEWTON_EQ, bn_num(b2, 32, x[0], 4),
             bn_num(b3, 32, x[1], 4));
    return 1;
}

/* Initialization Mode: every pad in equilibrium, warm-started (assembly.equilibrate) */
static int equilibrium(Instance *m, const double x[5], double F[2], double J[8], double dw[2]) {
    double a = arm(m);
    for (int k = 0; k < TP_N; k++) {
        Frame f;
        Pad p;
        double d = 0.0, c = PAD_COS[k], s = PAD_SIN[k];
        if (moment_root(m, k, x, m->work.pad_warm[k], &d, &f)) return 1;
        to_bearing(m, k, &f, &p);
        add_pad(&p, F, J, dw);
        m->work.pad_out[k] = d;
        m->work.pad_out[TP_N + k] = 0.0;
        if (BN_N_PAD_REALS > 2 * TP_N) m->work.pad_out[2 * TP_N + k] = p.M / TP_INERTIA;
        /* quasi-static: the tilt follows with M_delta d delta = -M_x dx (quasi_static_jacobian) */
        double Jt[2], tq[2], tv[2], Mdd;
        t_col(c, s, p.Jq, Jt);
        Mdd = a * a * (c * Jt[0] - s * Jt[1]);
        if (Mdd == 0.0) continue;
        double Fd[2] = {a * Jt[0], a * Jt[1]};
        t_row(c, s, p.Jq, tq);
        t_row(c, s, p.Jv, tv);
        double gq[2] = {-a * tq[0], -a * tq[1]}, gv[2] = {-a * tv[0], -a * tv[1]};
        follow(Fd, gq, gv, -a * f.Jw[0], Mdd, J, dw);
    }
    for (int k = 0; k < TP_N; k++) m->work.pad_warm[k] = m->work.pad_out[k];
    return 0;
}

/* the pads at given tilts (and, with inertia, rates): Model Exchange's states, or the committed
 * ones (PadAssembly.derivatives; massless: the rate whose squeeze balances the moment, Newton) */
static int at_state(Instance *m, const double x[5], const double *delta, const double *rate, double F[2], double J[8],
                    double dw[2]) {
    double a = arm(m), CR = m->r[VR_CR];
    for (int k = 0; k < TP_N; k++) {
        double lo, hi, c = PAD_COS[k], s = PAD_SIN[k], w = TP_INERTIA > 0.0 ? rate[k] : 0.0;
        Frame f;
        Pad p;
        tilt_range(m, k, x, &lo, &hi);
        if (!(lo < delta[k] && delta[k] < hi)) return wall_error(m, k, x, lo < hi ? delta[k] : NAN);
        if (pad_frame(m, k, x, delta[k], w, &f)) return 1;
        to_bearing(m, k, &f, &p);
        double Jt[2], dM = 0.0;
        if (TP_INERTIA <= 0.0) {
            for (int it = 0; it < NEWTON_EQ; it++) {
                t_col(c, s, p.Jv, Jt);
                dM = a * a * (c * Jt[0] - s * Jt[1]);
                if (dM >= 0.0) break; /* no squeeze (the pad carries nothing): no rate is determined by it */
                double step = -p.M / dM;
                w += step;
                if (pad_frame(m, k, x, delta[k], w, &f)) return 1;
                to_bearing(m, k, &f, &p);
                if (fabs(step) <= 1e-12 * (fabs(w) + x[4] * CR / a)) break;
            }
        }
        add_pad(&p, F, J, dw);
        m->work.pad_out[k] = delta[k];
        m->work.pad_out[TP_N + k] = w;
        if (BN_N_PAD_REALS > 2 * TP_N) m->work.pad_out[2 * TP_N + k] = p.M / TP_INERTIA;
        if (TP_INERTIA <= 0.0) { /* the rate follows the journal: M_w dw = -M_x dx */
            t_col(c, s, p.Jv, Jt);
            dM = a * a * (c * Jt[0] - s * Jt[1]);
            if (dM >= 0.0) continue;
            double Fw[2] = {a * Jt[0], a * Jt[1]}, tq[2], tv[2];
            t_row(c, s, p.Jq, tq);
            t_row(c, s, p.Jv, tv);
            double gq[2] = {-a * tq[0], -a * tq[1]}, gv[2] = {-a * tv[0], -a * tv[1]};
            follow(Fw, gq, gv, -a * f.Jw[0], dM, J, dw);
        }
    }
    return 0;
}

/* Co-Simulation: the pads at the end of a step of h from the committed state (PadStepper.solve) */
static int step(Instance *m, const double *P, const double x[5], double h, double F[2], double J[8], double dw[2]) {
    double a = arm(m), I = TP_INERTIA, b = h, hd[TP_N], hw[TP_N];
    char b1[32], b2[32], b3[32];
    for (int k = 0; k < TP_N; k++) {
        hd[k] = P[PS_DELTA + k];
        hw[k] = P[PS_RATE + k];
    }
    /* BDF2 with variable steps once there is a step before the committed state (bn_pads_accept
     * keeps stepping.PadStepper's prev: its tilts, rates and the size it holds), else backward Euler */
    if (P[PS_PREV_DT] > 0.0) {
        double rho = h / P[PS_PREV_DT], cc = 1.0 + 2.0 * rho;
        b = h * (1.0 + rho) / cc;
        for (int k = 0; k < TP_N; k++) {
            hd[k] = ((1.0 + rho) * (1.0 + rho) * P[PS_DELTA + k] - rho * rho * P[PS_PREV_DELTA + k]) / cc;
            hw[k] = ((1.0 + rho) * (1.0 + rho) * P[PS_RATE + k] - rho * rho * P[PS_PREV_RATE + k]) / cc;
        }
    }
    for (int k = 0; k < TP_N; k++) {
        double lo, hi, c = PAD_COS[k], s = PAD_SIN[k], d, w = 0.0, dr = 0.0;
        Frame f;
        Pad p;
        int it;
        tilt_range(m, k, x, &lo, &hi);
        if (!(lo < hi)) return wall_error(m, k, x, NAN);
        d = P[PS_DELTA + k] + h * P[PS_RATE + k];
        double span = isfinite(hi - lo) ? hi - lo : 1.0;
        d = fmin(fmax(d, lo + 1e-3 * span), hi - 1e-3 * span);
        double tol = 1e-13 * m->r[VR_CR] / a;
        for (it = 0; it < NEWTON_STEP; it++) {
            w = (d - hd[k]) / b;
            if (pad_frame(m, k, x, d, w, &f)) return 1;
            double M = a * f.F[0], M_d = a * a * f.Jq[0], M_w = a * a * f.Jv[0];
            double r = I * (w - hw[k]) - b * M;
            dr = I / b - b * M_d - M_w;
            if (r == 0.0 && dr == 0.0) lo = d; /* the film carries nothing here: the loaded root is downstream */
            else if (r > 0.0) hi = d;
            else lo = d;
            double stp = dr > 0.0 ? -r / dr : NAN;
            if (fabs(stp) <= tol) break;
            double nxt = d + stp;
            if (!(lo < nxt && nxt < hi)) nxt = 0.5 * (lo + hi);
            if (fabs(nxt - d) <= tol) break;
            d = nxt;
        }
        if (it == NEWTON_STEP) {
            snprintf(m->msg, sizeof m->msg, "tilting pads: the pad pivoted at %s deg found no tilt for the step in %d "
                     "Newton steps (y = %s m, z = %s m)", bn_num(b1, 32, PAD_DEG[k], 4), NEWTON_STEP,
                     bn_num(b2, 32, x[0], 4), bn_num(b3, 32, x[1], 4));
            return 1;
        }
        to_bearing(m, k, &f, &p);
        add_pad(&p, F, J, dw);
        m->work.pad_trial[k] = d;
        m->work.pad_trial[BN_MAX_PADS + k] = (d - hd[k]) / b;
        m->work.pad_out[k] = d;
        m->work.pad_out[TP_N + k] = (d - hd[k]) / b;
        if (BN_N_PAD_REALS > 2 * TP_N) m->work.pad_out[2 * TP_N + k] = p.M / TP_INERTIA;
        if (dr > 0.0) { /* the pad follows the journal: d delta / dx = b M_x / r' */
            double Jtq[2], Jtv[2], tq[2], tv[2];
            t_col(c, s, p.Jq, Jtq);
            t_col(c, s, p.Jv, Jtv);
            t_row(c, s, p.Jq, tq);
            t_row(c, s, p.Jv, tv);
            double Fd[2] = {a * Jtq[0] + a * Jtv[0] / b, a * Jtq[1] + a * Jtv[1] / b};
            double gq[2] = {b * (a * tq[0]), b * (a * tq[1])}, gv[2] = {b * (a * tv[0]), b * (a * tv[1])};
            follow(Fd, gq, gv, b * (a * f.Jw[0]), dr, J, dw);
        }
    }
    return 0;
}

int bn_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2], int *ood) {
    double Jl[8] = {0}, dwl[2] = {0}, tilts[BN_MAX_PADS], rates[BN_MAX_PADS];
    int refused;
    (void)want_jac; /* the Newton iterations need the Jacobians anyway */
    *ood = 0;
    F[0] = F[1] = 0.0;
    if (m->mode == MODE_INIT) {
        refused = equilibrium(m, x, F, Jl, dwl);
        if (!refused && m->model_exchange) { /* the equilibrium is the states' start: the outputs at it as later */
            for (int k = 0; k < TP_N; k++) tilts[k] = m->work.pad_out[k], rates[k] = 0.0;
            F[0] = F[1] = 0.0;
            memset(Jl, 0, sizeof Jl);
            dwl[0] = dwl[1] = 0.0;
            refused = at_state(m, x, tilts, rates, F, Jl, dwl);
        }
    } else if (m->step_h > 0.0) {
        refused = step(m, m->pads, x, m->step_h, F, Jl, dwl);
    } else if (!m->model_exchange && m->pads[PS_DT] > 0.0) {
        /* Co-Simulation after a step (a directional derivative): that step again from its start, so
         * the derivatives are its own, as K and C are */
        refused = step(m, m->pads + BN_PAD_STATE_LEN, x, m->pads[PS_DT], F, Jl, dwl);
    } else {
        for (int k = 0; k < TP_N; k++) { /* Model Exchange's states; Co-Simulation's committed ones */
            tilts[k] = m->model_exchange ? m->r[VR_PAD0 + k] : m->pads[PS_DELTA + k];
            rates[k] = m->model_exchange ? m->r[VR_PAD0 + TP_N + k] : m->pads[PS_RATE + k];
        }
        refused = at_state(m, x, tilts, rates, F, Jl, dwl);
    }
    if (refused) return 1;
    if (want_jac) {
        memcpy(J, Jl, sizeof Jl);
        memcpy(dw, dwl, sizeof dwl);
    }
    return 0;
}

#if BN_FLOWS_TILTING_PAD
/* The film's report at x (TiltingPad.film_report): the massless pads in moment equilibrium
 * (quasi-static, as the Python internal's report also in a step), each pad's partial-arc report
 * (reynolds_film.c) summed, the power the journal's T omega - F . v. */
int bn_film(Instance *m, const double x[5], double out[5]) {
    double F[2] = {0.0, 0.0}, sum[5] = {0.0, 0.0, 0.0, 0.0, 0.0}, a = arm(m);
    for (int k = 0; k < TP_N; k++) {
        Frame f;
        Pad p;
        double d = 0.0, rep[5], c = PAD_COS[k], s = PAD_SIN[k];
        if (moment_root(m, k, x, m->work.pad_warm[k], &d, &f)) return 1;
        m->work.pad_warm[k] = d;
        to_bearing(m, k, &f, &p); /* the last call was at d: its field is the report's */
        rs_film_report((rs_solver *)m->work.pad_solver[k], c * x[0] - s * x[1] + a * d, s * x[0] + c * x[1],
                       c * x[2] - s * x[3], s * x[2] + c * x[3], x[4], rep);
        F[0] += p.F[0];
        F[1] += p.F[1];
        sum[0] += rep[0];
        sum[1] += rep[1];
        sum[3] += rep[3];
        sum[4] += rep[4];
    }
    out[0] = sum[0];
    out[1] = sum[1];
    out[2] = ff_power(sum[0], sum[1], x[4], F, x[2], x[3]);
    out[3] = sum[3];
    out[4] = sum[4];
    return 0;
}
#endif

/* n_theta, n_x and cavitation are no Real options: nothing to differentiate */
void bn_option_derivative(Instance *m, const double x[5], int k, double dF[2], double dJ[8]) {
    (void)m;
    (void)x;
    (void)k;
    dF[0] = dF[1] = 0.0;
    for (int i = 0; i < 8; i++) dJ[i] = 0.0;
}

/* dF along ln(L/D) at a fixed scale (as the Reynolds internal's: L dF/dL less F, central
 * differences of every pad's solver rebuilt in its own memory at L (1 +- 1e-6)) */
int bn_shape_derivative(Instance *m, const double x[5], int want_jac, double dF[2], double dJ[8]) {
    const rs_solver *s = (const rs_solver *)m->work.pad_solver[0];
    int N = s->N, n_x = s->n_x, i, ood, bad = 0;
    double L = m->r[VR_L], h = 1e-6, F0[2], J0[8], Fp[2], Jp[8], Fm[2], Jm[8], dw[2];
    if (bn_eval(m, x, want_jac, F0, J0, dw, &ood)) return 1;
    m->r[VR_L] = L * (1.0 + h);
    bad = build(m, N, n_x) || bn_eval(m, x, want_jac, Fp, Jp, dw, &ood);
    m->r[VR_L] = L * (1.0 - h);
    bad = bad || build(m, N, n_x) || bn_eval(m, x, want_jac, Fm, Jm, dw, &ood);
    m->r[VR_L] = L;
    if (build(m, N, n_x) || bad) return 1;
    for (i = 0; i < 2; i++) dF[i] = (Fp[i] - Fm[i]) / (2.0 * h) - F0[i];
    for (i = 0; want_jac && i < 8; i++) dJ[i] = (Jp[i] - Jm[i]) / (2.0 * h) - J0[i];
    return 0;
}
