/* The finite-volume Reynolds solver in C (a port of bearing_fmu/physics/reynolds.py,
 * reynolds_kernels.py and geometry_kernels.py, whose docstrings explain the discretisation,
 * the cavitation problem, the active-set method with its warm start and the adjoint Jacobian).
 * One code path serves every bore: the full bore is the bore without fixed cells, with unit
 * centred film and uniform cells (its results equal the full-bore numba kernel's to rounding).
 *
 * Memory: rs_bytes(n_theta, n_x) bytes, handed to rs_create once; nothing is allocated after.
 * Every function is static (RS_API: the few the FMU's internal_reynolds.c calls) unless the
 * file is compiled alone with RS_EXPORT for the ctypes comparison with the Python solver
 * (tests/test_native_reynolds.py). */
#ifndef REYNOLDS_SOLVER_H
#define REYNOLDS_SOLVER_H

#include <stddef.h>

#if defined(RS_EXPORT)
#if defined(_WIN32)
#define RS_API __declspec(dllexport)
#else
#define RS_API __attribute__((visibility("default")))
#endif
#else
#define RS_API static
#endif

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

#endif
