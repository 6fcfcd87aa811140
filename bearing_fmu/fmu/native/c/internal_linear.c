/* The linear internal (bearing_fmu/linear.py): F = F0 - K (q - q0) - C v with Lund's K, C,
 * valid at the speed omega_lin; its 12 coefficients and omega_lin are parameters. Like the
 * Python internal it evaluates beyond the clearance circle (the host reports a crossing, the
 * output out_of_domain flags it); only a speed other than omega_lin is refused. */
#include <math.h>
#include <stdio.h>

#define BN_PART linear /* its functions' names in an FMU of several internals */
#define BN_PART_LINEAR 1 /* its part of model_data.h */
#include "bearing_native.h"

#define P(name) (m->r[VR_OPT_##name])

int bn_setup(Instance *m) {
    (void)m;
    return 0; /* every coefficient was checked finite when set */
}

int bn_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2], int *ood) {
    double omega0 = P(OMEGA_LIN);
    *ood = 0;
    if (fabs(x[4] - omega0) > 1e-9 * fmax(fabs(omega0), 1.0)) {
        char a[32], b[32];
        snprintf(m->msg, sizeof m->msg, "linear internal was linearised at omega = %s rad/s; got omega = %s rad/s",
                 bn_num(a, sizeof a, omega0, 6), bn_num(b, sizeof b, x[4], 6));
        return 1;
    }
    double dy = x[0] - P(LIN_Y0), dz = x[1] - P(LIN_Z0), vy = x[2], vz = x[3];
    *ood = hypot(x[0], x[1]) >= m->r[VR_CR]; /* past the clearance circle: flagged, not refused */
    /* the same order of operations as Linear.force */
    F[0] = P(LIN_FY0) - P(LIN_KYY) * dy - P(LIN_KYZ) * dz - P(LIN_CYY) * vy - P(LIN_CYZ) * vz;
    F[1] = P(LIN_FZ0) - P(LIN_KZY) * dy - P(LIN_KZZ) * dz - P(LIN_CZY) * vy - P(LIN_CZZ) * vz;
    if (want_jac) {
        J[0] = -P(LIN_KYY); J[1] = -P(LIN_KYZ); J[2] = -P(LIN_CYY); J[3] = -P(LIN_CYZ);
        J[4] = -P(LIN_KZY); J[5] = -P(LIN_KZZ); J[6] = -P(LIN_CZY); J[7] = -P(LIN_CZZ);
        dw[0] = dw[1] = 0.0; /* the model has no speed in it (it refuses any other speed) */
    }
    return 0;
}

/* F = F0 - K (q - q0) - C v: the derivatives with respect to omega_lin (0: it only selects the
 * speed), q0, F0 and each coefficient; the K, C outputs are the coefficients themselves */
void bn_option_derivative(Instance *m, const double x[5], int k, double dF[2], double dJ[8]) {
    double d[4] = {x[0] - P(LIN_Y0), x[1] - P(LIN_Z0), x[2], x[3]};
    int vr = VR_REAL_OPTIONS + k;
    dF[0] = dF[1] = 0.0;
    for (int i = 0; i < 8; i++) dJ[i] = 0.0;
    if (vr == VR_OPT_LIN_Y0) { dF[0] = P(LIN_KYY); dF[1] = P(LIN_KZY); }
    else if (vr == VR_OPT_LIN_Z0) { dF[0] = P(LIN_KYZ); dF[1] = P(LIN_KZZ); }
    else if (vr == VR_OPT_LIN_FY0) dF[0] = 1.0;
    else if (vr == VR_OPT_LIN_FZ0) dF[1] = 1.0;
    else {
        /* J row-major (2 x 4) over (y, z, vy, vz): the coefficient of each column, with its sign */
        static const int cols[8] = {VR_OPT_LIN_KYY, VR_OPT_LIN_KYZ, VR_OPT_LIN_CYY, VR_OPT_LIN_CYZ,
                                    VR_OPT_LIN_KZY, VR_OPT_LIN_KZZ, VR_OPT_LIN_CZY, VR_OPT_LIN_CZZ};
        for (int j = 0; j < 8; j++)
            if (cols[j] == vr) {
                dF[j / 4] = -d[j % 4];
                dJ[j] = -1.0;
            }
    }
}

void bn_release(Instance *m) { (void)m; } /* nothing allocated */
