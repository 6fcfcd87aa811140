/* The Reynolds solver in C: its grid (bearing_fmu/physics/solver/reynolds.py Reynolds.__init__ and
 * _bore, geometry.py theta_grid and ThetaGrid), one call (reynolds_kernels.py reynolds_kernel,
 * geometry_kernels.py geometry_kernel) and the memory layout. The kernels are
 * reynolds_kernels.c, the film report reynolds_film.c; reynolds_solver.h says how the memory is
 * handed over.
 *
 * The bore comes as its segments (geometry.Geometry.segments, computed once when the FMU is
 * built): the stretches between edges (groove and arc edges, lobe boundaries), whether each has
 * a prescribed pressure and which; this file divides them into cells for the n_theta set. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "py_mod.h"
#include "reynolds_solver.h"

/* Python's round() of a positive double: half to even */
static double rs_round_even(double x) {
    double r = floor(x + 0.5);
    if (r - x == 0.5 && fmod(r, 2.0) != 0.0) r -= 1.0;
    return r;
}

static size_t rs_align(size_t x) { return (x + 15) / 16 * 16; }

/* doubles of a solver of n_theta x n_x cells */
static size_t rs_doubles(size_t N, size_t m) {
    size_t n = N * m;
    return 30 * N /* sin_c .. dax, wd .. hl0, db (5 N) */ + 3 * m + 3 * n + (N - 1) * m * (m + 1) + (N - 1) * m * m + m * m +
           (N - 1) * m + m + 7 * n + RS_HISTORY * n;
}

/* Bytes of memory a solver of n_theta x n_x cells needs (its struct included) */
RS_API size_t rs_bytes(int n_theta, int n_x) {
    size_t N = (size_t)n_theta, m = (size_t)(n_x / 2);
    return rs_align(sizeof(rs_solver)) + rs_align(rs_doubles(N, m) * sizeof(double)) + rs_align(2 * N + N * m);
}

/* h / CR of the centred journal at t on lobe k (geometry.base_film) */
static double rs_base_film(int lobes, double preload, double offset, double lobe_angle, double t, int k) {
    if (lobes < 2 || preload == 0.0) return 1.0;
    double step = RS_TWO_PI / lobes;
    double tp = lobe_angle + ((double)k - 0.5 + offset) * step;
    return (1.0 - preload * cos(t - tp)) / (1.0 - preload);
}

/* numpy's sum of a short float array (pairwise: 8 partial sums from 8 values on) */
double rs_np_sum(const double *x, int n) {
    int i;
    if (n < 8) {
        double s = 0.0;
        for (i = 0; i < n; i++) s += x[i];
        return s;
    }
    double r[8];
    for (i = 0; i < 8; i++) r[i] = x[i];
    for (i = 8; i + 8 <= n; i += 8) {
        int k;
        for (k = 0; k < 8; k++) r[k] += x[i + k];
    }
    double s = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for (; i < n; i++) s += x[i];
    return s;
}

/* Cells of the bore (geometry.theta_grid): one per fixed segment, the rest spread over the film
 * segments by length (largest remainder, at least 2 each): the cells' left edges and widths
 * into left and width, and the solver's fixed and psup. */
static int rs_cells(rs_solver *s, int nseg, const double *edge, const int *seg_fixed, const double *seg_supply,
                    double *left, double *width, char *msg, size_t msglen) {
    int N = s->N, k, i, nfilm_seg = 0, cell = 0;
    double *len = s->rhs, *ideal = s->tmp, *cells = s->p; /* scratch, n >= N >= nseg */
    for (k = 0; k < nseg; k++)
        if (!seg_fixed[k]) nfilm_seg++;
    int n_film = N - (nseg - nfilm_seg);
    if (nfilm_seg == 0 || n_film < 2 * nfilm_seg) {
        snprintf(msg, msglen, "n_theta = %d is too few cells for this bore: it needs at least %d", N,
                 2 * nfilm_seg + nseg - nfilm_seg);
        return 1;
    }
    for (k = 0, i = 0; k < nseg; k++) {
        double b = k + 1 < nseg ? edge[k + 1] : edge[0] + RS_TWO_PI;
        if (!seg_fixed[k]) len[i++] = b - edge[k];
    }
    double total = rs_np_sum(len, nfilm_seg), sum = 0.0;
    for (i = 0; i < nfilm_seg; i++) {
        ideal[i] = (double)n_film * len[i] / total;
        cells[i] = floor(ideal[i]) > 2.0 ? floor(ideal[i]) : 2.0;
        sum += cells[i];
    }
    while (sum < n_film) { /* largest remainder first */
        int best = 0;
        for (i = 1; i < nfilm_seg; i++)
            if (ideal[i] - cells[i] > ideal[best] - cells[best]) best = i;
        cells[best] += 1.0;
        sum += 1.0;
    }
    while (sum > n_film) {
        int best = -1;
        for (i = 0; i < nfilm_seg; i++)
            if (cells[i] > 2.0 && (best < 0 || cells[i] - ideal[i] > cells[best] - ideal[best])) best = i;
        cells[best] -= 1.0;
        sum -= 1.0;
    }
    for (k = 0, i = 0; k < nseg; k++) {
        double a = edge[k], b = k + 1 < nseg ? edge[k + 1] : edge[0] + RS_TWO_PI;
        int nc = seg_fixed[k] ? 1 : (int)cells[i++], c;
        for (c = 0; c < nc; c++, cell++) {
            left[cell] = a + (b - a) * c / nc;
            width[cell] = (b - a) / nc;
            s->fixed[cell] = (unsigned char)(seg_fixed[k] != 0);
            s->psup[cell] = seg_supply[k];
        }
    }
    return 0;
}

/* The bore's grid (ThetaGrid and Reynolds._bore) from the cells' left edges and widths */
static void rs_grid_bore(rs_solver *s, int lobes, double preload, double offset, double angle, const double *left,
                         const double *width) {
    int N = s->N, i;
    double R = s->R, fy = 0.0, fz = 0.0;
    for (i = 0; i < N; i++) {
        int nx = i + 1 < N ? i + 1 : 0;
        double centre = left[i] + 0.5 * width[i], right = left[i] + width[i];
        double cn = left[nx] + 0.5 * width[nx];
        int lobe = rs_lobe_of(lobes, angle, centre), lobe_n = rs_lobe_of(lobes, angle, cn);
        int film = !s->fixed[i], film_n = !s->fixed[nx];
        s->H0f[i] = rs_base_film(lobes, preload, offset, angle, right, film ? lobe : lobe_n);
        s->H0c[i] = rs_base_film(lobes, preload, offset, angle, centre, lobe);
        s->dH0[i] = film ? rs_base_film(lobes, preload, offset, angle, right, lobe) -
                               rs_base_film(lobes, preload, offset, angle, left[i], lobe)
                         : 0.0;
        double dist = film && film_n ? py_mod(cn - centre, RS_TWO_PI)
                                     : (film ? 0.5 * width[i] : (film_n ? 0.5 * width[nx] : 0.0));
        s->wd[i] = width[i];
        s->cen[i] = centre;
        s->rt[i] = right;
        s->lf[i] = left[i];
        s->dst[i] = dist;
        s->hl0[i] = rs_base_film(lobes, preload, offset, angle, left[i], lobe);
        s->ct[i] = dist > 0.0 ? s->dx / (R * R * dist) : 0.0;
        s->cx[i] = width[i] / s->dx;
        s->sin_f[i] = sin(right);
        s->cos_f[i] = cos(right);
        /* the supply force: p (sin, -cos) over the fixed cells, the whole length */
        fy += s->psup[i] * (cos(left[i]) - cos(right));
        fz += s->psup[i] * (sin(right) - sin(left[i]));
        s->dat[i] = centre; /* for the loop below */
    }
    s->F0[0] = fy * R * s->L;
    s->F0[1] = -fz * R * s->L;
    for (i = 0; i < N; i++) {
        s->sin_c[i] = sin(s->dat[i]);
        s->cos_c[i] = cos(s->dat[i]);
        s->gy[i] = 2.0 * R * width[i] * s->sin_c[i];
        s->gz[i] = -2.0 * R * width[i] * s->cos_c[i];
    }
}

/* A solver in mem (rs_bytes(n_theta, n_x) bytes, 16-byte aligned). mode: 0 gumbel, 1 reynolds;
 * D, L, CR [m], mu [Pa s]; nseg = 0: the full bore, else its segments (edge: each one's start
 * [rad], sorted; seg_fixed, seg_supply [Pa]) and lobes. NULL with the reason in msg. */
RS_API rs_solver *rs_create(void *mem, int n_theta, int n_x, int mode, int warm, double D, double L, double CR,
                            double mu, int nseg, const double *edge, const int *seg_fixed, const double *seg_supply,
                            int lobes, double preload, double lobe_offset, double lobe_angle, char *msg,
                            size_t msglen) {
    int N = n_theta, m = n_x / 2, n = N * m, i;
    if (N < 8 || N > RS_MAX_CELLS || n_x < 2 || n_x % 2 || n_x > RS_MAX_CELLS) {
        snprintf(msg, msglen, "the grid n_theta = %d, n_x = %d: n_theta an integer >= 8, n_x an even integer >= 2, "
                 "both at most %d", n_theta, n_x, RS_MAX_CELLS);
        return NULL;
    }
    if (lobes > RS_MAX_LOBES) {
        snprintf(msg, msglen, "lobes = %d: at most %d", lobes, RS_MAX_LOBES);
        return NULL;
    }
    rs_solver *s = (rs_solver *)mem;
    memset(s, 0, sizeof *s);
    double *d = (double *)((char *)mem + rs_align(sizeof(rs_solver)));
    double **arrays[] = {&s->sin_c, &s->cos_c, &s->sin_f, &s->cos_f, &s->ds, &s->dc, &s->H0f, &s->H0c, &s->dH0,
                         &s->ct, &s->cx, &s->gy, &s->gz, &s->psup, &s->at, &s->ax, &s->b, &s->dat, &s->dax,
                         &s->wd, &s->cen, &s->rt, &s->lf, &s->dst, &s->hl0};
    for (i = 0; i < (int)(sizeof arrays / sizeof arrays[0]); i++, d += N) *arrays[i] = d;
    s->db = d; d += 5 * N;
    s->tdiag = d; d += m;
    s->rs = d; d += m;
    s->qw = d; d += m;
    s->diag = d; d += n;
    s->cxo = d; d += n;
    s->cto = d; d += n;
    s->Lb = d; d += (size_t)(N - 1) * m * (m + 1);
    s->Y = d; d += (size_t)(N - 1) * m * m;
    s->S = d; d += (size_t)m * m;
    s->zb = d; d += (size_t)(N - 1) * m;
    s->z2 = d; d += m;
    double **work[] = {&s->p, &s->pf, &s->rhs0, &s->rhs, &s->tmp, &s->mu_y, &s->mu_z};
    for (i = 0; i < 7; i++, d += n) *work[i] = d;
    s->wring = d;
    unsigned char *u = (unsigned char *)mem + rs_align(sizeof(rs_solver)) +
                       rs_align(rs_doubles((size_t)N, (size_t)m) * sizeof(double));
    s->fixed = u;
    s->act = u + 2 * (size_t)N;
    s->N = N;
    s->m = m;
    s->n_x = n_x;
    s->mode = mode ? 1 : 0;
    s->warm_on = warm ? 1 : 0;
    s->R = 0.5 * D;
    s->L = L;
    s->CR = CR;
    s->mu = mu;
    s->dth = 2.0 * M_PI / N;
    s->dx = L / n_x;
    s->bore = nseg > 0;
    s->lobes = lobes;
    s->preload = preload;
    s->lobe_angle = lobe_angle;
    for (i = 0; i < N; i++) {
        s->fixed[i] = 0;
        s->psup[i] = 0.0;
    }
    if (s->bore) {
        /* left edges and widths into dax and db (free until the first call) */
        if (rs_cells(s, nseg, edge, seg_fixed, seg_supply, s->dax, s->db, msg, msglen)) return NULL;
        rs_grid_bore(s, lobes, preload, lobe_offset, lobe_angle, s->dax, s->db);
    } else {
        for (i = 0; i < N; i++) {
            double th = i * s->dth, thf = th + 0.5 * s->dth;
            s->sin_c[i] = sin(th);
            s->cos_c[i] = cos(th);
            s->sin_f[i] = sin(thf);
            s->cos_f[i] = cos(thf);
            s->H0f[i] = s->H0c[i] = 1.0;
            s->dH0[i] = 0.0;
            s->ct[i] = s->dx / (s->R * s->R * s->dth);
            s->cx[i] = s->dth / s->dx;
            s->wd[i] = s->dst[i] = s->dth; /* film.field_report's grid of the full bore */
            s->cen[i] = i * s->dth;
            s->rt[i] = s->cen[i] + 0.5 * s->dth;
            s->lf[i] = s->cen[i] - 0.5 * s->dth;
            s->hl0[i] = 1.0;
        }
    }
    for (i = 0; i < N; i++) { /* differences of face values */
        int im = i > 0 ? i - 1 : N - 1;
        s->ds[i] = s->sin_f[i] - s->sin_f[im];
        s->dc[i] = s->cos_f[i] - s->cos_f[im];
    }
    /* axial stencil and quadrature (reynolds.py: end face second order, row 0 scaled by 3/4) */
    for (i = 0; i < m; i++) {
        s->tdiag[i] = 2.0;
        s->rs[i] = 1.0;
        s->qw[i] = s->dx;
    }
    if (m == 1) {
        s->tdiag[0] = 8.0 / 3.0;
        s->qw[0] = 8.0 / 9.0 * s->dx;
    } else {
        s->tdiag[0] = 3.0;
        s->tdiag[m - 1] = 1.0;
        s->rs[0] = 0.75;
        s->qw[0] -= s->dx / 8.0;
        s->qw[1] += s->dx / 72.0;
    }
    s->max_iter = 4 * n + 10;
    s->grow = (int)rs_round_even(N / 16.0);
    if (s->grow < 1) s->grow = 1;
    s->max_turn = RS_MAX_TURN_CELLS * s->dth < M_PI ? RS_MAX_TURN_CELLS * s->dth : M_PI;
    s->max_dlog = RS_MAX_DLOG;
    s->warm_cap = s->grow + 4;
    for (i = 0; i < RS_HISTORY; i++) s->order[i] = i;
    s->nvalid = 0;
    for (i = 0; i < n; i++) s->act[i] = 0;
    return s;
}


/* With no source at all p = 0 and the force is only directionally differentiable: the odd part
 * (F(db) - F(-db)) / 2 of the first-order film response (reynolds_kernels.reynolds_kernel) */
static int rs_quiet_jacobian(rs_solver *s) {
    int N = s->N, n = N * s->m, q, i, k, sg, s0, hb;
    for (q = 0; q < 5; q++) {
        double cy = 0.0, cz = 0.0;
        for (sg = 0; sg < 2; sg++) {
            double sgn = sg == 0 ? 1.0 : -1.0;
            for (i = 0; i < N; i++) s->dat[i] = sgn * s->db[q * N + i];
            int it2 = rs_film(s, s->dat, s->max_iter, 0, &s0, &hb);
            if (it2 < 0) return 1;
            s->info[3] += it2;
            rs_integrate(s, s->Ft);
            cy += 0.5 * sgn * (s->Ft[0] - s->F0[0]);
            cz += 0.5 * sgn * (s->Ft[1] - s->F0[1]);
        }
        if (q < 2) {
            s->dFq[q] = cy;
            s->dFq[2 + q] = cz;
        } else if (q < 4) {
            s->dFv[q - 2] = cy;
            s->dFv[q] = cz;
        } else {
            s->dFw[0] = cy;
            s->dFw[1] = cz;
        }
    }
    s->nvalid = 0; /* the state's own (zero) film again; no source to warm-start from */
    for (k = 0; k < n; k++) {
        s->p[k] = 0.0;
        s->pf[k] = 0.0;
        s->act[k] = (unsigned char)(s->mode == 1);
        s->rhs0[k] = 0.0;
    }
    s->info[2] = 0.0;
    return 0;
}

/* dF/d(y, z, vy, vz) by the adjoints mu_a = A_mod^-1 w_a of the converged factorization */
static void rs_jacobian(rs_solver *s, double y, double z, int s0, int hb) {
    int N = s->N, m = s->m, n = N * m, i, j, k, q, a;
    double wr = 2.0 * s->R * s->dth, CR = s->CR;
    for (a = 0; a < 2; a++) {
        double *mu_a = a == 0 ? s->mu_y : s->mu_z;
        for (i = 0; i < N; i++)
            for (j = 0; j < m; j++) {
                k = i * m + j;
                int free_ = !s->fixed[i] && (s->mode == 0 ? s->pf[k] > 0.0 : !s->act[k]);
                double w;
                if (s->bore)
                    w = s->qw[j] * (a == 0 ? s->gy[i] : s->gz[i]);
                else
                    w = a == 0 ? wr * s->qw[j] * s->sin_c[i] : -wr * s->qw[j] * s->cos_c[i];
                s->rhs[k] = free_ ? w : 0.0;
            }
        rs_solve(s, s0, hb, s->rhs, mu_a);
    }
    for (k = 0; k < n; k++)
        if (s->act[k]) s->mu_y[k] = s->mu_z[k] = 0.0;
    const double *pp = s->mode == 0 ? s->pf : s->p;
    for (q = 0; q < 2; q++) {
        /* dF/dq = mu^T (db/dq - dA/dq p); dH/dy = sin / CR, dH/dz = -cos / CR */
        for (i = 0; i < N; i++) {
            double hf = s->H0f[i] + (y * s->sin_f[i] - z * s->cos_f[i]) / CR;
            double hc = s->H0c[i] + (y * s->sin_c[i] - z * s->cos_c[i]) / CR;
            double gf = q == 0 ? s->sin_f[i] : -s->cos_f[i], gc = q == 0 ? s->sin_c[i] : -s->cos_c[i];
            s->dat[i] = 3.0 * hf * hf * gf / CR * s->ct[i];
            s->dax[i] = 3.0 * hc * hc * gc / CR * s->cx[i];
        }
        rs_apply(s, s->dat, s->dax, pp, s->tmp);
        double sy = 0.0, sz = 0.0;
        for (i = 0; i < N; i++)
            for (j = 0; j < m; j++) {
                k = i * m + j;
                double g = s->rs[j] * s->db[q * N + i] - s->tmp[k];
                if (j == m - 1 && s->p_in != 0.0 && !s->fixed[i])
                    g += 2.0 * s->dax[i] * s->p_in; /* the groove's Dirichlet term on the inner row */
                sy += s->mu_y[k] * g;
                sz += s->mu_z[k] * g;
            }
        s->dFq[q] = sy;
        s->dFq[2 + q] = sz;
    }
    for (q = 0; q < 3; q++) { /* dF/dv, dF/domega = mu^T db/d. (A depends on neither) */
        double sy = 0.0, sz = 0.0;
        for (i = 0; i < N; i++) {
            double ty = 0.0, tz = 0.0;
            for (j = 0; j < m; j++) {
                ty += s->rs[j] * s->mu_y[i * m + j];
                tz += s->rs[j] * s->mu_z[i * m + j];
            }
            sy += ty * s->db[(q + 2) * N + i];
            sz += tz * s->db[(q + 2) * N + i];
        }
        if (q < 2) {
            s->dFv[q] = sy;
            s->dFv[2 + q] = sz;
        } else {
            s->dFw[0] = sy;
            s->dFw[1] = sz;
        }
    }
}

/* One call at a checked state (finite, inside the wall): s->F, and with want_jac s->dFq, s->dFv
 * (row-major 2 x 2: dF_i/dq_j) and s->dFw (dF/domega: not in the Python internal; checked
 * against central differences). RS_OK, RS_NOT_CONVERGED (guards against cycling; not observed)
 * or RS_OVERFLOW (finite inputs whose film is beyond the float range). */
RS_API int rs_call(rs_solver *s, double y, double z, double vy, double vz, double omega, int want_jac) {
    int N = s->N, m = s->m, n = N * m, i, k, s0, hb, iters;
    for (i = 0; i < 6; i++) s->info[i] = 0.0;
    s->p_stale = 0;
    rs_assemble(s, y, z, vy, vz, omega);
    int use_warm = s->warm_on && s->mode == 1;
    if (!use_warm) s->nvalid = 0; /* act is overwritten below: nothing remembered stays valid */
    int warm = use_warm && rs_warm_set(s, y, z, vy, vz, omega);
    s->info[4] = warm ? 1.0 : 0.0;
    iters = rs_film(s, s->b, warm ? s->warm_cap : s->max_iter, warm, &s0, &hb);
    if (warm && iters < 0) { /* not settled within warm_cap passes: the cold start */
        s->info[3] += s->warm_cap;
        s->info[5] = 1.0;
        iters = rs_film(s, s->b, s->max_iter, 0, &s0, &hb);
    }
    s->info[0] = iters;
    s->counts[0] += 1.0;
    if (iters < 0) {
        s->nvalid = 0;
        return RS_NOT_CONVERGED;
    }
    s->info[3] += iters;
    if (use_warm) rs_remember(s, y, z, vy, vz, omega);
    rs_integrate(s, s->F);
    int nact = 0, nfilm = 0;
    for (i = 0; i < N; i++) {
        if (s->fixed[i]) continue;
        for (k = i * m; k < (i + 1) * m; k++) {
            nfilm++;
            if (s->act[k] || (s->mode == 0 && s->pf[k] <= 0.0)) nact++;
        }
    }
    s->info[1] = (double)nact / nfilm;
    int status = RS_OK;
    if (want_jac) {
        double sc = s->dx / (s->CR * s->CR * s->CR), mu = s->mu;
        for (i = 0; i < N; i++) { /* db/ds per column, s = (y, z, vy, vz) */
            s->db[i] = -sc * 6.0 * mu * omega * s->ds[i];
            s->db[N + i] = sc * 6.0 * mu * omega * s->dc[i];
            s->db[2 * N + i] = sc * 12.0 * mu * s->dc[i];
            s->db[3 * N + i] = sc * 12.0 * mu * s->ds[i];
            s->db[4 * N + i] = -sc * 6.0 * mu * (s->bore ? y * s->ds[i] - z * s->dc[i] + s->CR * s->dH0[i]
                                                          : y * s->ds[i] - z * s->dc[i]);
        }
        int quiet = 1;
        if (s->bore || s->lands) {
            for (k = 0; k < n && quiet; k++)
                if (s->rhs0[k] != 0.0) quiet = 0;
        } else {
            for (i = 0; i < N && quiet; i++)
                if (s->b[i] != 0.0) quiet = 0;
        }
        if (quiet) {
            s->p_stale = 1;
            if (rs_quiet_jacobian(s)) {
                s->info[0] = -1.0;
                status = RS_NOT_CONVERGED;
            }
        } else {
            rs_jacobian(s, y, z, s0, hb);
        }
    }
    s->counts[1] += s->info[3];
    s->counts[2] += s->info[4];
    s->counts[3] += s->info[5];
    if (status != RS_OK) return status;
    int finite = isfinite(s->F[0]) && isfinite(s->F[1]);
    for (i = 0; want_jac && i < 4; i++) finite = finite && isfinite(s->dFq[i]) && isfinite(s->dFv[i]);
    finite = finite && (!want_jac || (isfinite(s->dFw[0]) && isfinite(s->dFw[1])));
    return finite ? RS_OK : RS_OVERFLOW;
}

#if defined(RS_EXPORT) /* what the ctypes comparison calls besides (bearing_fmu/fmu/native/solver_lib.py) */
/* F (2), dFq (4), dFv (4) into out */
static void rs_force_and_jacobian(const rs_solver *s, double *out) {
    int i;
    out[0] = s->F[0];
    out[1] = s->F[1];
    for (i = 0; i < 4; i++) {
        out[2 + i] = s->dFq[i];
        out[6 + i] = s->dFv[i];
    }
}

/* Drop the remembered calls: the next call starts cold (results do not change) */
RS_API void rs_forget(rs_solver *s) { s->nvalid = 0; }

/* The last call's results: F (2), dFq (4), dFv (4), info (6), counts (4), dFw (2) into out (22) */
RS_API void rs_results(const rs_solver *s, double *out) {
    int i;
    rs_force_and_jacobian(s, out);
    for (i = 0; i < 6; i++) out[10 + i] = s->info[i];
    for (i = 0; i < 4; i++) out[16 + i] = s->counts[i];
    out[20] = s->dFw[0];
    out[21] = s->dFw[1];
}

/* The benchmark's floor (benchmarks/bench_native_reynolds.py): n calls at states[5 k ..] in one
 * compiled loop, F and the Jacobian into out[10 k ..]; the number of calls that failed */
RS_API int rs_call_many(rs_solver *s, const double *states, int n, int want_jac, double *out) {
    int k, bad = 0;
    for (k = 0; k < n; k++) {
        const double *x = states + 5 * k;
        bad += rs_call(s, x[0], x[1], x[2], x[3], x[4], want_jac) != RS_OK;
        rs_force_and_jacobian(s, out + 10 * k);
    }
    return bad;
}
#endif

/* The full bore's film as two lands fed by a circumferential groove of the width [m] at mid-length at
 * the supply pressure p_in [Pa] (physics/solver/lands.py: one land of (L - width) / 2, p = 0 at its
 * outer end, p_in on its inner edge; the axial cells and stencil of lands.land_cells and
 * axial_stencil), set after rs_create: 0, or 1 with the reason in msg. */
RS_API int rs_set_lands(rs_solver *s, double width, double p_in, char *msg, size_t msglen) {
    int N = s->N, m = s->m, i;
    if (s->bore) {
        snprintf(msg, msglen, "a circumferential groove is the plain circular bore's feed (no axial grooves, arc or "
                 "lobes)");
        return 1;
    }
    if (m < 2) {
        snprintf(msg, msglen, "n_x = %d: a bore with a circumferential groove needs n_x >= 4 (at least 2 cells per "
                 "land: the land has a Dirichlet face at both ends)", s->n_x);
        return 1;
    }
    if (!(width > 0.0 && width < s->L) || !(p_in >= 0.0 && isfinite(p_in))) {
        snprintf(msg, msglen, "the circumferential groove's width %g m must be > 0 and < L = %g m, its supply "
                 "pressure %g Pa finite and >= 0", width, s->L, p_in);
        return 1;
    }
    s->lands = 1;
    s->p_in = p_in;
    s->groove = width;
    s->dx = 0.5 * (s->L - width) / m;
    for (i = 0; i < N; i++) { /* the cells' coefficients over the land's dx */
        s->ct[i] = s->dx / (s->R * s->R * s->dth);
        s->cx[i] = s->dth / s->dx;
    }
    for (i = 0; i < m; i++) { /* lands.axial_stencil(m, dx, land=True) */
        s->tdiag[i] = 2.0;
        s->rs[i] = 1.0;
        s->qw[i] = s->dx;
    }
    s->tdiag[0] = 3.0;
    s->tdiag[m - 1] = 3.0;
    s->rs[0] = 0.75;
    s->qw[0] -= s->dx / 8.0;
    s->qw[1] += s->dx / 72.0;
    s->rs[m - 1] = 0.75;
    s->qw[m - 1] -= s->dx / 8.0;
    s->qw[m - 2] += s->dx / 72.0;
    s->nvalid = 0;
    return 0;
}
