/* The finite-volume Reynolds solver in C (a port of bearing_fmu/physics/solver/reynolds.py,
 * reynolds_kernels.py and geometry_kernels.py, whose docstrings explain the discretisation,
 * the cavitation problem, the active-set method with its warm start and the adjoint Jacobian).
 * One code path serves every bore: the full bore is the bore without fixed cells, with unit
 * centred film and uniform cells (its results equal the full-bore numba kernel's to rounding).
 *
 * Memory: rs_bytes(n_theta, n_x) bytes, handed to rs_create once; nothing is allocated after.
 * Four units: reynolds_solver.c (the grid, one call), reynolds_kernels.c (the kernels it calls:
 * RS_INTERNAL), reynolds_film.c (the film report), reynolds_peak.c (the peak pressure). In an FMU their shared names carry the FMU's
 * model identifier (model_config.h BN_ID, as bearing_native.h's) and are hidden; compiled alone
 * with RS_EXPORT, RS_API (what internal_reynolds.c calls) is exported for the ctypes comparison
 * with the Python solver (tests/test_native_reynolds.py, fmu/native/solver_lib.py). */
#ifndef REYNOLDS_SOLVER_H
#define REYNOLDS_SOLVER_H

#include <stddef.h>

#if (defined(__GNUC__) || defined(__clang__)) && !defined(_WIN32)
#define RS_INTERNAL __attribute__((visibility("hidden")))
#else
#define RS_INTERNAL
#endif
#if defined(RS_EXPORT)
#if defined(_WIN32)
#define RS_API __declspec(dllexport)
#else
#define RS_API __attribute__((visibility("default")))
#endif
#else /* in an FMU: the FMU's names (model_config.h BN_ID), hidden */
#include "model_config.h"
#define RS_PASTE(a, b) a##_##b
#define RS_NAME(a, b) RS_PASTE(a, b)
#define rs_bytes RS_NAME(BN_ID, rs_bytes)
#define rs_create RS_NAME(BN_ID, rs_create)
#define rs_call RS_NAME(BN_ID, rs_call)
#define rs_film_report RS_NAME(BN_ID, rs_film_report)
#define rs_peak_pressure RS_NAME(BN_ID, rs_peak_pressure)
#define rs_set_lands RS_NAME(BN_ID, rs_set_lands)
#define rs_np_sum RS_NAME(BN_ID, rs_np_sum)
#define rs_assemble RS_NAME(BN_ID, rs_assemble)
#define rs_apply RS_NAME(BN_ID, rs_apply)
#define rs_solve RS_NAME(BN_ID, rs_solve)
#define rs_film RS_NAME(BN_ID, rs_film)
#define rs_warm_set RS_NAME(BN_ID, rs_warm_set)
#define rs_remember RS_NAME(BN_ID, rs_remember)
#define rs_integrate RS_NAME(BN_ID, rs_integrate)
#define RS_API RS_INTERNAL
#endif
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define RS_TWO_PI (2.0 * M_PI)

#include "py_mod.h"

/* The geometry's lobe index of angle t (geometry.lobe_of): the grid (reynolds_solver.c) and the
 * film report's inflow lines (reynolds_film.c) both ask it */
static inline int rs_lobe_of(int lobes, double lobe_angle, double t) {
    if (lobes < 2) return 0;
    double step = RS_TWO_PI / lobes;
    int k = (int)floor(py_mod(t - lobe_angle + 0.5 * step, RS_TWO_PI) / step);
    return ((k % lobes) + lobes) % lobes;
}

#define RS_HISTORY 4           /* converged calls remembered for the warm start (WARM_HISTORY) */
#define RS_MAX_TURN_CELLS 2.0  /* WARM_MAX_TURN_CELLS */
#define RS_MAX_DLOG 1.0        /* WARM_MAX_DLOG */
#define RS_MAX_LOBES 8         /* geometry.MAX_LOBES */
#define RS_MAX_CELLS 100000    /* n_theta and n_x at most (reynolds._check_grid) */

/* rs_call's outcome */
enum { RS_OK = 0, RS_NOT_CONVERGED = 1, RS_OVERFLOW = 2 };

typedef struct rs_solver {
    int N, m, n_x, mode, warm_on, bore;  /* mode 0 gumbel, 1 reynolds; bore: not the full circle */
    double R, L, CR, mu, dth, dx;
    int max_iter, grow, warm_cap;
    double max_turn, max_dlog;
    /* the grid: per theta cell (centres c, right faces f) */
    double *sin_c, *cos_c, *sin_f, *cos_f, *ds, *dc, *H0f, *H0c, *dH0, *ct, *cx, *gy, *gz, *psup;
    /* and for the film report (reynolds_film.c; geometry.ThetaGrid's): cell widths, centres,
     * right and left faces [rad], the distance across each right face [rad], h / CR of the
     * centred journal at the left face on the cell's own lobe */
    double *wd, *cen, *rt, *lf, *dst, *hl0;
    int lobes;
    double preload, lobe_angle; /* lobe_angle [rad]: the film report's lobe of a cell */
    int lands;   /* a circumferential groove: the axial cells are one land (physics/solver/lands.py) */
    double p_in; /* its supply pressure on the land's inner edge [Pa] (0: none) */
    double groove; /* its width [m] (0: none) */
    int p_stale; /* the last call's Jacobian without a source overwrote p (its field: 0) */
    unsigned char *fixed;
    double F0[2];
    double *tdiag, *rs, *qw;  /* the axial stencil and quadrature (m) */
    /* work */
    double *at, *ax, *b, *db, *dat, *dax, *diag, *cxo, *cto;
    unsigned char *act;
    double *Lb, *Y, *S, *zb, *z2, *p, *pf, *rhs0, *rhs, *tmp, *mu_y, *mu_z;
    /* the warm start's history */
    double hs[RS_HISTORY][4];
    int order[RS_HISTORY];
    int nvalid;
    double *wring;
    /* results of the last call */
    double F[2], dFq[4], dFv[4], dFw[2], Ft[2]; /* dFw = dF/domega */
    double info[6]; /* as the numba kernel's: passes, cavitated fraction, residual, factorizations,
                       warm, cold fallback */
    double counts[4]; /* calls, factorizations, warm starts, cold fallbacks */
} rs_solver;

/* ------------------------------------------------------------------------------ reynolds_solver.c */
/* the memory a solver of this grid needs [bytes] */
RS_API size_t rs_bytes(int n_theta, int n_x);
/* the solver built in mem (rs_bytes long) for the bore's segments: NULL with the reason in why */
RS_API rs_solver *rs_create(void *mem, int n_theta, int n_x, int mode, int warm, double D, double L, double CR,
                            double mu, int nseg, const double *edge, const int *seg_fixed, const double *seg_supply,
                            int lobes, double preload, double offset, double lobe_angle, char *why, size_t n);
/* a circumferential groove (width [m], supply pressure [Pa]): the film two lands, after rs_create (0, or 1
 * with the reason in msg) */
RS_API int rs_set_lands(rs_solver *s, double width, double p_in, char *msg, size_t msglen);
/* one call at the state: RS_OK, RS_NOT_CONVERGED or RS_OVERFLOW; the results in s */
RS_API int rs_call(rs_solver *s, double y, double z, double vy, double vz, double omega, int want_jac);
/* the peak pressure (p [Pa], theta [rad]) of the field rs_call just solved (Reynolds.peak_pressure) */
RS_API void rs_peak_pressure(rs_solver *s, double out[2]);
/* numpy's sum of x (pairwise, as np.sum) */
RS_INTERNAL double rs_np_sum(const double *x, int n);

/* ------------------------------------------------------------------------------ reynolds_film.c */
/* the film report of the field rs_call just solved at the state: out as bn_film's */
RS_API void rs_film_report(rs_solver *s, double y, double z, double vy, double vz, double omega, double out[5]);

/* ------------------------------------------------------------------------------ reynolds_kernels.c */
RS_INTERNAL void rs_assemble(rs_solver *s, double y, double z, double vy, double vz, double omega);
RS_INTERNAL void rs_apply(const rs_solver *s, const double *at, const double *ax, const double *p, double *out);
RS_INTERNAL void rs_solve(rs_solver *s, int s0, int hb, const double *rhs, double *x);
RS_INTERNAL int rs_film(rs_solver *s, const double *b, int max_iter, int warm, int *s0_out, int *hb_out);
RS_INTERNAL int rs_warm_set(rs_solver *s, double y, double z, double vy, double vz, double omega);
RS_INTERNAL void rs_remember(rs_solver *s, double y, double z, double vy, double vz, double omega);
RS_INTERNAL void rs_integrate(const rs_solver *s, double F[2]);

#endif
