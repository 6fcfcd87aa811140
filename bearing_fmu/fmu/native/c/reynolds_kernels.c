/* The Reynolds solver's kernels (reynolds_solver.h: RS_INTERNAL the ones reynolds_solver.c calls): a
 * line-by-line port of bearing_fmu/physics/solver/reynolds_kernels.py and geometry_kernels.py (their
 * docstrings explain each step), the full bore and the other bores in one path (fixed cells,
 * the centred film H0 and non-uniform cells; the full bore has none, unit film, uniform cells).
 * Arrays: Lb[k (m + 1) + d] = L[k, k - d]; Y[k m + c]; S[a m + c]; db[q N + i]; wring[slot n + k]. */
#include <math.h>

#include "reynolds_solver.h"

/* Face coefficients (scaled by 1/CR^3: H = h / CR) and the per-column source */
void rs_assemble(rs_solver *s, double y, double z, double vy, double vz, double omega) {
    int N = s->N, i;
    double CR = s->CR, mu = s->mu;
    for (i = 0; i < N; i++) {
        double hf = s->H0f[i] + (y * s->sin_f[i] - z * s->cos_f[i]) / CR;
        double hc = s->H0c[i] + (y * s->sin_c[i] - z * s->cos_c[i]) / CR;
        s->at[i] = hf * hf * hf * s->ct[i];
        s->ax[i] = hc * hc * hc * s->cx[i];
    }
    double sc = s->dx / (CR * CR * CR);
    for (i = 0; i < N; i++) {
        /* h_{i+1/2} - h_{i-1/2} = y ds - z dc (+ CR dH0); int dh/dt = -vy dc - vz ds */
        double couette = s->bore ? (y * s->ds[i] - z * s->dc[i] + CR * s->dH0[i]) : (y * s->ds[i] - z * s->dc[i]);
        s->b[i] = -sc * (6.0 * mu * omega * couette + 12.0 * mu * (-vy * s->dc[i] - vz * s->ds[i]));
    }
}

/* out = A p (unmodified operator, half axial domain) */
void rs_apply(const rs_solver *s, const double *at, const double *ax, const double *p, double *out) {
    int N = s->N, m = s->m, i, j;
    const double *rs = s->rs, *tdiag = s->tdiag;
    for (i = 0; i < N; i++) {
        int im = i > 0 ? i - 1 : N - 1, ip = i < N - 1 ? i + 1 : 0;
        double a0 = at[i], a1 = at[im], axi = ax[i];
        for (j = 0; j < m; j++) {
            int k = i * m + j;
            double v = rs[j] * ((a0 + a1) * p[k] - a0 * p[ip * m + j] - a1 * p[im * m + j]);
            double w = tdiag[j] * p[k];
            if (j > 0) w -= p[k - 1];
            if (j < m - 1) w -= p[k + 1];
            out[k] = v + axi * w;
        }
    }
}

/* Entries of A with the rows and columns of active (cavitated, fixed) nodes replaced by identity */
static void rs_modified(rs_solver *s) {
    int N = s->N, m = s->m, i, j;
    const unsigned char *act = s->act;
    for (i = 0; i < N; i++) {
        int im = i > 0 ? i - 1 : N - 1;
        for (j = 0; j < m; j++) {
            int k = i * m + j;
            if (act[k]) {
                s->diag[k] = 1.0;
                s->cxo[k] = 0.0;
                s->cto[k] = 0.0;
                continue;
            }
            s->diag[k] = s->rs[j] * (s->at[i] + s->at[im]) + s->ax[i] * s->tdiag[j];
            s->cxo[k] = (j > 0 && !act[k - 1]) ? -s->ax[i] : 0.0;
            s->cto[k] = !act[im * m + j] ? -s->rs[j] * s->at[im] : 0.0;
        }
    }
}

/* Bordered banded Cholesky of the modified matrix in the block order s0, s0 + 1, ... (mod N):
 * the first N - 1 blocks banded (half-bandwidth m), the last the border (Y = L^-1 E,
 * S = chol(S0 - Y^T Y)). Returns whether the border couples. */
static int rs_factor(rs_solver *s, int s0) {
    int N = s->N, m = s->m, m1 = m + 1, n1 = (N - 1) * m, k, d, t, a, c, j;
    double *Lb = s->Lb, *Y = s->Y, *S = s->S;
    const double *diag = s->diag, *cxo = s->cxo, *cto = s->cto;
    for (k = 0; k < n1; k++) {
        int r = k / m, ib = s0 + r, kp;
        j = k - r * m;
        if (ib >= N) ib -= N;
        kp = ib * m + j;
        double *row = Lb + (size_t)k * m1;
        if (s->act[kp]) {
            for (d = 1; d <= m; d++) row[d] = 0.0;
            row[0] = 1.0;
            continue;
        }
        for (d = m; d >= 1; d--) {
            int cc = k - d;
            if (cc < 0) {
                row[d] = 0.0;
                continue;
            }
            double sum = 0.0;
            if (d == 1 && j > 0) sum = cxo[kp];
            if (d == m && r > 0) sum += cto[kp];
            const double *rc = Lb + (size_t)cc * m1;
            for (t = 1; t <= m - d; t++) {
                if (cc - t < 0) break;
                sum -= row[d + t] * rc[t];
            }
            row[d] = sum / rc[0];
        }
        double sum = diag[kp];
        for (d = 1; d <= m; d++) sum -= row[d] * row[d];
        row[0] = sqrt(sum);
    }
    int ibB = s0 + N - 1;
    if (ibB >= N) ibB -= N;
    int has_border = 0;
    for (j = 0; j < m; j++)
        if (cto[s0 * m + j] != 0.0 || cto[ibB * m + j] != 0.0) has_border = 1;
    /* S0: the border block's own (tridiagonal) entries */
    for (a = 0; a < m; a++) {
        for (c = 0; c < m; c++) S[a * m + c] = 0.0;
        S[a * m + a] = diag[ibB * m + a];
        if (a > 0) {
            S[a * m + a - 1] = cxo[ibB * m + a];
            S[(a - 1) * m + a] = cxo[ibB * m + a];
        }
    }
    if (has_border) {
        /* Y = L^-1 E; E couples block 0 (row j) and block N - 2 (row (N - 2) m + j) to border j */
        for (k = 0; k < n1 * m; k++) Y[k] = 0.0;
        for (j = 0; j < m; j++) {
            Y[j * m + j] = cto[s0 * m + j];
            Y[((N - 2) * m + j) * m + j] += cto[ibB * m + j];
        }
        for (k = 0; k < n1; k++) {
            const double *row = Lb + (size_t)k * m1;
            for (c = 0; c < m; c++) {
                double sum = Y[k * m + c];
                for (d = 1; d <= m; d++) {
                    if (k - d < 0) break;
                    sum -= row[d] * Y[(k - d) * m + c];
                }
                Y[k * m + c] = sum / row[0];
            }
        }
        for (a = 0; a < m; a++)
            for (c = 0; c <= a; c++) {
                double sum = 0.0;
                for (k = 0; k < n1; k++) sum += Y[k * m + a] * Y[k * m + c];
                S[a * m + c] -= sum;
                if (c != a) S[c * m + a] -= sum;
            }
    }
    /* dense Cholesky of S (lower triangle) */
    for (a = 0; a < m; a++)
        for (c = 0; c <= a; c++) {
            double sum = S[a * m + c];
            for (t = 0; t < c; t++) sum -= S[a * m + t] * S[c * m + t];
            if (c == a)
                S[a * m + a] = sqrt(sum);
            else
                S[a * m + c] = sum / S[c * m + c];
        }
    return has_border;
}

/* x = A_mod^-1 rhs with the factors of rs_factor (rhs, x in the physical order) */
void rs_solve(rs_solver *s, int s0, int hb, const double *rhs, double *x) {
    int N = s->N, m = s->m, m1 = m + 1, n1 = (N - 1) * m, k, d, a, t, c;
    const double *Lb = s->Lb, *Y = s->Y, *S = s->S;
    double *zb = s->zb, *z2 = s->z2;
    for (k = 0; k < n1; k++) {
        int r = k / m, j = k - r * m, ib = s0 + r;
        if (ib >= N) ib -= N;
        const double *row = Lb + (size_t)k * m1;
        double sum = rhs[ib * m + j];
        for (d = 1; d <= m; d++) {
            if (k - d < 0) break;
            sum -= row[d] * zb[k - d];
        }
        zb[k] = sum / row[0];
    }
    int ibB = s0 + N - 1;
    if (ibB >= N) ibB -= N;
    for (a = 0; a < m; a++) {
        double sum = rhs[ibB * m + a];
        if (hb)
            for (k = 0; k < n1; k++) sum -= Y[k * m + a] * zb[k];
        for (t = 0; t < a; t++) sum -= S[a * m + t] * z2[t];
        z2[a] = sum / S[a * m + a];
    }
    for (a = m - 1; a >= 0; a--) {
        double sum = z2[a];
        for (t = a + 1; t < m; t++) sum -= S[t * m + a] * z2[t];
        z2[a] = sum / S[a * m + a];
        x[ibB * m + a] = z2[a];
    }
    for (k = n1 - 1; k >= 0; k--) {
        double sum = zb[k];
        if (hb)
            for (c = 0; c < m; c++) sum -= Y[k * m + c] * z2[c];
        for (d = 1; d <= m; d++) {
            if (k + d >= n1) break;
            sum -= Lb[(size_t)(k + d) * m1 + d] * zb[k + d];
        }
        zb[k] = sum / Lb[(size_t)k * m1];
        int r = k / m, j = k - r * m, ib = s0 + r;
        if (ib >= N) ib -= N;
        x[ib * m + j] = zb[k];
    }
}

/* Block order start: right after the first fully active column, else 0 */
static int rs_pick_start(const rs_solver *s) {
    int N = s->N, m = s->m, i, j;
    for (i = 0; i < N; i++) {
        int full = 1;
        for (j = 0; j < m; j++)
            if (!s->act[i * m + j]) {
                full = 0;
                break;
            }
        if (full) return i + 1 < N ? i + 1 : 0;
    }
    return 0;
}

/* rhs0 = rs (b + the fixed neighbours' pressure over the shared face) on film cells, 0 on fixed; plus
 * 2 ax p_in on the inner row of a land fed by a circumferential groove at p_in (geometry_kernels._rhs) */
static void rs_rhs0(rs_solver *s, const double *b) {
    int N = s->N, m = s->m, i, j;
    const unsigned char *fixed = s->fixed;
    for (i = 0; i < N; i++) {
        int im = i > 0 ? i - 1 : N - 1, ip = i < N - 1 ? i + 1 : 0;
        double extra = 0.0;
        if (!fixed[i]) {
            if (fixed[ip]) extra += s->at[i] * s->psup[ip];
            if (fixed[im]) extra += s->at[im] * s->psup[im];
        }
        for (j = 0; j < m; j++) s->rhs0[i * m + j] = fixed[i] ? 0.0 : s->rs[j] * (b[i] + extra);
        if (s->p_in != 0.0 && !fixed[i]) s->rhs0[i * m + m - 1] += 2.0 * s->ax[i] * s->p_in;
    }
}

/* the groove's Dirichlet term on row j of column i (moved to the right-hand side: rs_rhs0) */
static double rs_inner(const rs_solver *s, int i, int j) {
    return j == s->m - 1 ? 2.0 * s->ax[i] * s->p_in : 0.0;
}

/* Pressure p (fixed cells at their value) for the column source b with the cavitation model.
 * Leaves the factorization of the final matrix; *s0, *hb its block start and border; returns
 * the passes, -1 if the active-set loop did not settle within max_iter. warm (reynolds): start
 * from the set already in act. gumbel: pf = the full solution, p = max(pf, 0). */
int rs_film(rs_solver *s, const double *b, int max_iter, int warm, int *s0_out, int *hb_out) {
    int N = s->N, m = s->m, n = N * m, i, j, k, d;
    const unsigned char *fixed = s->fixed;
    unsigned char *act = s->act;
    double *p = s->p, *pf = s->pf, *tmp = s->tmp, *rhs = s->rhs, *rhs0 = s->rhs0;
    rs_rhs0(s, b);
    double bmax = 0.0;
    if (s->bore || s->lands) { /* the geometry kernel's (a land's film is one) */
        for (k = 0; k < n; k++)
            if (fabs(rhs0[k]) > bmax) bmax = fabs(rhs0[k]);
    } else {
        for (i = 0; i < N; i++)
            if (fabs(b[i]) > bmax) bmax = fabs(b[i]);
    }
    if (s->mode == 0) {
        for (i = 0; i < N; i++)
            for (j = 0; j < m; j++) act[i * m + j] = fixed[i];
        rs_modified(s);
        int s0 = rs_pick_start(s), hb = rs_factor(s, s0);
        rs_solve(s, s0, hb, rhs0, pf);
        for (i = 0; i < N; i++)
            for (j = 0; j < m; j++) {
                k = i * m + j;
                if (fixed[i]) pf[k] = s->psup[i];
                p[k] = pf[k] > 0.0 ? pf[k] : 0.0;
            }
        s->info[2] = 0.0;
        *s0_out = s0;
        *hb_out = hb;
        return 1;
    }
    /* Swift-Stieber LCP by the primal-dual active-set method. Cold start: cavitated where the
     * source is not positive, less a margin of grow columns around every positive run */
    if (!warm) {
        for (i = 0; i < N; i++) {
            int free_ = 0;
            for (d = -s->grow; d <= s->grow; d++) {
                int ii = ((i + d) % N + N) % N;
                if (b[ii] > 0.0 || s->psup[ii] > 0.0 || s->p_in > 0.0) {
                    free_ = 1;
                    break;
                }
            }
            for (j = 0; j < m; j++) act[i * m + j] = (unsigned char)!free_;
        }
    }
    for (i = 0; i < N; i++)
        if (fixed[i])
            for (j = 0; j < m; j++) act[i * m + j] = 1;
    int iters = 0, s0 = 0, hb = 0;
    double dmax = 0.0, pmax = 0.0;
    for (;;) {
        if (iters >= max_iter) {
            *s0_out = s0;
            *hb_out = hb;
            return -1;
        }
        iters++;
        rs_modified(s);
        s0 = rs_pick_start(s);
        hb = rs_factor(s, s0);
        for (k = 0; k < n; k++) rhs[k] = act[k] ? 0.0 : rhs0[k];
        rs_solve(s, s0, hb, rhs, p);
        for (i = 0; i < N; i++)
            for (j = 0; j < m; j++) {
                k = i * m + j;
                if (fixed[i])
                    p[k] = s->psup[i];
                else if (act[k])
                    p[k] = 0.0;
            }
        rs_apply(s, s->at, s->ax, p, tmp);
        pmax = 0.0;
        dmax = 0.0;
        for (k = 0; k < n; k++) {
            if (p[k] > pmax) pmax = p[k];
            if (s->diag[k] > dmax) dmax = s->diag[k];
        }
        double tol = 1e-12 * (bmax + 2.0 * dmax * pmax);
        int changed = 0;
        for (i = 0; i < N; i++) {
            if (fixed[i]) continue;
            for (j = 0; j < m; j++) {
                k = i * m + j;
                if (act[k]) {
                    if (tmp[k] - s->rs[j] * b[i] - rs_inner(s, i, j) < -tol) {
                        act[k] = 0;
                        changed = 1;
                    }
                } else if (p[k] < 0.0) {
                    act[k] = 1;
                    changed = 1;
                }
            }
        }
        if (!changed) break;
    }
    /* complementarity residual max |min(p, A p - b)|, scaled */
    double res = 0.0;
    for (i = 0; i < N; i++) {
        if (fixed[i]) continue;
        for (j = 0; j < m; j++) {
            k = i * m + j;
            double lam = tmp[k] - s->rs[j] * b[i] - rs_inner(s, i, j);
            double v = p[k] < lam ? p[k] : lam;
            if (fabs(v) > res) res = fabs(v);
        }
    }
    double scale = bmax + 2.0 * dmax * pmax;
    s->info[2] = scale > 0.0 ? res / scale : 0.0;
    *s0_out = s0;
    *hb_out = hb;
    return iters;
}

/* The warm start's set (1), or 0 for the cold start (the history dropped): the newest
 * remembered set moved by extrapolating w through an earlier call (reynolds_kernels.warm_start_set) */
int rs_warm_set(rs_solver *s, double y, double z, double vy, double vz, double omega) {
    int n = s->N * s->m, k, r;
    if (s->nvalid == 0) return 0;
    int a = s->order[0], bs = a;
    double CR = s->CR, qy = y / CR, qz = z / CR;
    double dy = qy - s->hs[a][0], dz = qz - s->hs[a][1], dd = dy * dy + dz * dz, alpha = 0.0;
    for (r = 1; r < s->nvalid; r++) {
        bs = s->order[r];
        double ey = s->hs[a][0] - s->hs[bs][0], ez = s->hs[a][1] - s->hs[bs][1], ee = ey * ey + ez * ez;
        if (ee > 0.0 && ee >= 0.0625 * dd) {
            alpha = (dy * ey + dz * ez) / ee;
            alpha = alpha > 0.0 ? alpha : 0.0; /* min(max(., 0), 2) */
            alpha = alpha < 2.0 ? alpha : 2.0;
            break;
        }
    }
    double uy = omega * y - 2.0 * vz, uz = omega * z + 2.0 * vy;
    double ey = s->hs[a][2] + alpha * (s->hs[a][2] - s->hs[bs][2]);
    double ez = s->hs[a][3] + alpha * (s->hs[a][3] - s->hs[bs][3]);
    double cu = sqrt(uy * uy + uz * uz), pu = sqrt(ey * ey + ez * ez);
    double eps = sqrt(qy * qy + qz * qz), eps_a = sqrt(s->hs[a][0] * s->hs[a][0] + s->hs[a][1] * s->hs[a][1]);
    if (cu == 0.0 || pu == 0.0 || fabs(log1p(-eps) - log1p(-eps_a)) > s->max_dlog ||
        (uy * ey + uz * ez) < cos(s->max_turn) * cu * pu) {
        s->nvalid = 0;
        return 0;
    }
    if (alpha > 0.0) {
        const double *wa = s->wring + (size_t)a * n, *wb = s->wring + (size_t)bs * n;
        for (k = 0; k < n; k++) s->act[k] = (unsigned char)(wa[k] + alpha * (wa[k] - wb[k]) <= 0.0);
    }
    return 1;
}

/* Store the converged call (tmp = A p of the final pass) as the newest history entry */
void rs_remember(rs_solver *s, double y, double z, double vy, double vz, double omega) {
    int N = s->N, m = s->m, i, j, r, slot = s->order[RS_HISTORY - 1];
    for (r = RS_HISTORY - 1; r > 0; r--) s->order[r] = s->order[r - 1];
    s->order[0] = slot;
    if (s->nvalid < RS_HISTORY) s->nvalid++;
    s->hs[slot][0] = y / s->CR;
    s->hs[slot][1] = z / s->CR;
    s->hs[slot][2] = omega * y - 2.0 * vz;
    s->hs[slot][3] = omega * z + 2.0 * vy;
    double *w = s->wring + (size_t)slot * N * m;
    for (i = 0; i < N; i++)
        for (j = 0; j < m; j++) {
            int k = i * m + j;
            w[k] = s->act[k] ? -(s->tmp[k] - s->rs[j] * s->b[i]) : s->p[k];
        }
}

/* F = F0 + the film's pressure integral (full bore: 2 R dth sum (sin, -cos), as the numba kernel) */
void rs_integrate(const rs_solver *s, double F[2]) {
    int N = s->N, m = s->m, i, j;
    double fy = 0.0, fz = 0.0;
    for (i = 0; i < N; i++) {
        if (s->fixed[i]) continue;
        double sum = 0.0;
        for (j = 0; j < m; j++) sum += s->qw[j] * s->p[i * m + j];
        if (s->bore) {
            fy += sum * s->gy[i];
            fz += sum * s->gz[i];
        } else {
            fy += sum * s->sin_c[i];
            fz -= sum * s->cos_c[i];
        }
    }
    if (s->bore) {
        F[0] = s->F0[0] + fy;
        F[1] = s->F0[1] + fz;
    } else {
        double wr = 2.0 * s->R * s->dth;
        F[0] = fy * wr;
        F[1] = fz * wr;
    }
}
