/* The oil's viscosity laws and the film's effective temperature (oil_thermal.h). */
#include "oil_thermal.h"

#include <math.h>
#include <stdio.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define OT_KELVIN 273.15
#define OT_WALTHER_MIN_CST 2.0 /* oil.WALTHER_MIN_CST */

/* mu [Pa s] at T [K] (no range check: Oil._mu) */
OT_API double ot_mu(const ot_oil *oil, double T) {
    if (oil->law == OT_WALTHER)
        return (pow(10.0, pow(10.0, oil->c[0] - oil->c[1] * log10(T))) - 0.7) * 1e-6 * oil->density;
    return oil->c[0] * exp(oil->c[1] / (T - oil->c[2]));
}

/* The oil of the FMU parameters (ports.oil_of): law (OT_*), Walther's two points nu [m^2/s] at
 * T [K], Vogel's a [Pa s], b, c [K], the range, density, heat capacity, rise factor, and the heat
 * balance's outflow share s (0.5 or 0), ambient loss h A [W/K] and ambient temperature [K] (0: the
 * supply's). 0, or 1 with the reason (Oil's checks, in the parameters' names) in why. */
OT_API int ot_oil_of(ot_oil *oil, int law, double nu1, double T1, double nu2, double T2, double va, double vb,
                     double vc, double T_min, double T_max, double density, double heat_capacity, double rise_factor,
                     double outflow_share, double ambient_W_K, double T_ambient, char *why, size_t n) {
    oil->law = law;
    oil->T_min = T_min;
    oil->T_max = T_max;
    oil->density = density;
    oil->heat_capacity = heat_capacity;
    oil->rise_factor = rise_factor;
    oil->outflow_share = outflow_share;
    oil->ambient_W_K = ambient_W_K;
    oil->T_ambient = T_ambient;
    if (!(outflow_share == 0.5 || outflow_share == 0.0)) {
        snprintf(why, n, "oil_outflow_share = %.17g must be 0.5 (the side flow leaves at half the rise: outflow_rise "
                 "'half') or 0 (all the oil at the full rise: 'full')", outflow_share);
        return 1;
    }
    if (!(isfinite(ambient_W_K) && ambient_W_K >= 0.0 && isfinite(T_ambient) && T_ambient >= 0.0)) {
        snprintf(why, n, "oil_ambient_loss = %g W/K and oil_T_ambient = %g K must be finite and >= 0 (oil_T_ambient 0: "
                 "the supply temperature)", ambient_W_K, T_ambient);
        return 1;
    }
    if (!(isfinite(T_min) && isfinite(T_max) && 0.0 < T_min && T_min < T_max)) {
        snprintf(why, n, "the range oil_T_min .. oil_T_max = %.6g .. %.6g K must have 0 K < low < high", T_min, T_max);
        return 1;
    }
    if (law == OT_VOGEL) {
        oil->c[0] = va;
        oil->c[1] = vb;
        oil->c[2] = vc;
        if (!(va > 0.0 && vb > 0.0 && vc >= 0.0)) {
            snprintf(why, n, "the Vogel law needs oil_vogel_a > 0, oil_vogel_b > 0, oil_vogel_c >= 0, got %g, %g, %g",
                     va, vb, vc);
            return 1;
        }
        if (!(T_min > vc)) {
            snprintf(why, n, "the Vogel law diverges at T = oil_vogel_c = %g K; its range must start above it, not "
                     "at oil_T_min = %g K", vc, T_min);
            return 1;
        }
        return 0;
    }
    /* Walther through two points (Oil.walther: sorted by temperature, in cSt) */
    double n1 = nu1 * 1e6, t1 = T1, n2 = nu2 * 1e6, t2 = T2;
    if (t2 < t1) {
        double a = n1, b = t1;
        n1 = n2; t1 = t2; n2 = a; t2 = b;
    }
    if (!(n1 > 0.0 && n2 > 0.0 && t1 > 0.0)) {
        snprintf(why, n, "viscosities must be > 0 and temperatures > 0 K (oil_nu_1, oil_T_1, oil_nu_2, oil_T_2), got "
                 "%g, %g cSt at %g, %g K", n1, n2, t1, t2);
        return 1;
    }
    if (t1 == t2) {
        snprintf(why, n, "the two temperatures oil_T_1, oil_T_2 must differ, got %g K twice", t1);
        return 1;
    }
    if (!(n1 > n2)) {
        snprintf(why, n, "the viscosity must fall as the temperature rises (oil_nu_1 .. oil_T_2): %g cSt at %g K, "
                 "%g cSt at %g K", n1, t1, n2, t2);
        return 1;
    }
    if ((n1 < n2 ? n1 : n2) < OT_WALTHER_MIN_CST) {
        snprintf(why, n, "%g cSt is below the %g cSt where ASTM D341's simple form holds (oil_nu_1, oil_nu_2)",
                 n1 < n2 ? n1 : n2, OT_WALTHER_MIN_CST);
        return 1;
    }
    double w1 = log10(log10(n1 + 0.7)), w2 = log10(log10(n2 + 0.7));
    oil->c[1] = (w1 - w2) / (log10(t2) - log10(t1));
    oil->c[0] = w1 + oil->c[1] * log10(t1);
    double nu_top = ot_mu(oil, T_max) / density * 1e6;
    if (nu_top < OT_WALTHER_MIN_CST) {
        snprintf(why, n, "at oil_T_max = %g K the Walther law gives %.3g cSt, below the %g cSt where ASTM D341's "
                 "simple form holds: lower oil_T_max", T_max, nu_top, OT_WALTHER_MIN_CST);
        return 1;
    }
    return 0;
}

#if defined(RS_EXPORT) || BN_FILM_FLOW /* the heat balance: only where an internal has the film's flows */
/* dmu/dT [Pa s/K] at T [K], analytic (the directional derivatives: bearing_derivatives.c). Walther:
 * with w = 10^(A - B log10 T) = log10(nu + 0.7), d(nu + 0.7)/dT = -(nu + 0.7) ln(10) B w / T;
 * Vogel: -mu b / (T - c)^2 */
OT_API double ot_dmu_dT(const ot_oil *oil, double T) {
    if (oil->law == OT_WALTHER) {
        double w = pow(10.0, oil->c[0] - oil->c[1] * log10(T));
        return -pow(10.0, w) * log(10.0) * oil->c[1] * w / T * 1e-6 * oil->density;
    }
    return -ot_mu(oil, T) * oil->c[1] / ((T - oil->c[2]) * (T - oil->c[2]));
}

/* The heat balance (thermal.heat_balance_rise): P = rho c_p (Q - s Qs) dT + h A (T_eff - T_amb),
 * T_eff = T_supply + k dT, P = per_mu mu(T), so the target T* = T_supply + shift + gain mu(T) with
 * den = rho c_p carried + k h A [W/K], gain = k per_mu / den [K/(Pa s)] and shift = -k h A (T_supply
 * - T_amb) / den [K] (the loss at the supply temperature); carried = inflow - s side flow [m^3/s] (> 0),
 * per_mu the friction power per viscosity [W/(Pa s)]. out = gain, shift, den. */
OT_API void ot_balance_terms(const ot_oil *oil, double per_mu, double carried, double T_supply, double out[3]) {
    double hA = oil->ambient_W_K, T_amb = oil->T_ambient > 0.0 ? oil->T_ambient : T_supply;
    double den = oil->density * oil->heat_capacity * carried + oil->rise_factor * hA;
    out[0] = oil->rise_factor * per_mu / den;
    out[1] = -oil->rise_factor * hA * (T_supply - T_amb) / den;
    out[2] = den;
}

/* the heat balance's residual at T (thermal.film_temperature's g) */
typedef struct {
    const ot_oil *oil;
    double a, T_s, shift, gain, T_old;
} ot_balance;

static double ot_g(const ot_balance *b, double T) {
    return (1.0 - b->a) * (b->T_s + b->shift + b->gain * ot_mu(b->oil, T)) + b->a * b->T_old - T;
}

/* scipy.optimize.brentq (scipy/optimize/Zeros/brentq.c, Brent 1973), maxiter 100: the same
 * iterates, so the same root to round-off; f(xa), f(xb) of opposite signs (the caller's bracket) */
static double ot_brentq(const ot_balance *bal, double xa, double xb, double xtol, double rtol) {
    double xpre = xa, xcur = xb, xblk = 0.0, fpre, fcur, fblk = 0.0, spre = 0.0, scur = 0.0, sbis, delta, stry, dpre,
           dblk;
    fpre = ot_g(bal, xpre);
    fcur = ot_g(bal, xcur);
    if (fpre == 0.0) return xpre;
    if (fcur == 0.0) return xcur;
    for (int i = 0; i < 100; i++) {
        if (fpre != 0.0 && fcur != 0.0 && (signbit(fpre) != signbit(fcur))) {
            xblk = xpre;
            fblk = fpre;
            spre = scur = xcur - xpre;
        }
        if (fabs(fblk) < fabs(fcur)) {
            xpre = xcur; xcur = xblk; xblk = xpre;
            fpre = fcur; fcur = fblk; fblk = fpre;
        }
        delta = (xtol + rtol * fabs(xcur)) / 2.0;
        sbis = (xblk - xcur) / 2.0;
        if (fcur == 0.0 || fabs(sbis) < delta) return xcur;
        if (fabs(spre) > delta && fabs(fcur) < fabs(fpre)) {
            if (xpre == xblk) { /* interpolate */
                stry = -fcur * (xcur - xpre) / (fcur - fpre);
            } else { /* extrapolate */
                dpre = (fpre - fcur) / (xpre - xcur);
                dblk = (fblk - fcur) / (xblk - xcur);
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre));
            }
            double lim = 3.0 * fabs(sbis) - delta;
            if (2.0 * fabs(stry) < (fabs(spre) < lim ? fabs(spre) : lim)) { /* good short step */
                spre = scur;
                scur = stry;
            } else {
                spre = sbis;
                scur = sbis;
            }
        } else {
            spre = sbis;
            scur = sbis;
        }
        xpre = xcur;
        fpre = fcur;
        xcur += fabs(scur) > delta ? scur : (sbis > 0.0 ? delta : -delta);
        fcur = ot_g(bal, xcur);
    }
    return xcur;
}

static int ot_range(const ot_oil *oil, double T, const char *what, char *why, size_t n) {
    if (isfinite(T) && oil->T_min <= T && T <= oil->T_max) return 0;
    snprintf(why, n, "%s = %.6g K (%.6g C) is outside the viscosity law's range %.6g C .. %.6g C (the parameters "
             "oil_T_min .. oil_T_max)", what, T, T - OT_KELVIN, oil->T_min - OT_KELVIN, oil->T_max - OT_KELVIN);
    return 1;
}

/* Model Exchange's form of the lag (thermal.py, "At a fixed journal state"): at the film temperature
 * T [K] (a state), out = mu(T) [Pa s], the residence time [s] and dT/dt = (T*(T) - T) / t_res [K/s],
 * T* = T_supply + k dT(mu(T)) the heat balance's target (ot_balance_terms) (0 when the film dissipates nothing or takes
 * in no oil: its temperature holds). 0, or 1 with the reason in why. */
OT_API int ot_film_rate(const ot_oil *oil, double mu_ref, double R, double CR, double L, double power, double inflow,
                        double side_flow, double T_supply, double T, double out[3], char *why, size_t n) {
    if (ot_range(oil, T_supply, "T_supply", why, n) || ot_range(oil, T, "the film temperature (T_eff)", why, n))
        return 1;
    double tau = inflow > 0.0 ? 2.0 * M_PI * R * CR * L / inflow : INFINITY, per_mu = power / mu_ref;
    out[0] = ot_mu(oil, T);
    out[1] = tau;
    out[2] = 0.0;
    if (per_mu <= 0.0 || !(tau < INFINITY)) return 0;
    double carried = inflow - oil->outflow_share * side_flow, terms[3];
    if (!(carried > 0.0)) {
        snprintf(why, n, "film temperature: the film carries no oil away (inflow %.4g m^3/s, side flow %.4g m^3/s) "
                 "while it dissipates %.4g W", inflow, side_flow, power);
        return 1;
    }
    ot_balance_terms(oil, per_mu, carried, T_supply, terms);
    out[2] = (T_supply + terms[1] + terms[0] * out[0] - T) / tau;
    return 0;
}

/* film_temperature: out = T [K], mu(T) [Pa s], residence time [s] from the film report at the
 * viscosity mu_ref (power [W], inflow, side flow [m^3/s]) of a bearing R, CR, L [m], oil supplied
 * at T_supply [K]; quasi-static (lagged 0) or lagged from T_old over dt [s]. 0, or 1 with the
 * reason in why (the oil's range left, no oil carried away). */
OT_API int ot_film_temperature(const ot_oil *oil, double mu_ref, double R, double CR, double L, double power,
                               double inflow, double side_flow, double T_supply, int lagged, double T_old, double dt,
                               double out[3], char *why, size_t n) {
    if (ot_range(oil, T_supply, "T_supply", why, n)) return 1;
    double tau = inflow > 0.0 ? 2.0 * M_PI * R * CR * L / inflow : INFINITY; /* thermal.residence_time_s */
    double a = lagged ? exp(-dt / tau) : 0.0;
    if (lagged) {
        if (ot_range(oil, T_old, "the film temperature (T_eff)", why, n)) return 1;
    } else {
        T_old = T_supply;
    }
    double per_mu = power / mu_ref, T;
    out[2] = tau;
    if (per_mu <= 0.0 || a == 1.0) {
        T = lagged ? T_old : T_supply;
        out[0] = T;
        out[1] = ot_mu(oil, T);
        return 0;
    }
    double carried = inflow - oil->outflow_share * side_flow, terms[3];
    if (!(carried > 0.0)) {
        snprintf(why, n, "film temperature: the film carries no oil away (inflow %.4g m^3/s, side flow %.4g m^3/s) "
                 "while it dissipates %.4g W", inflow, side_flow, power);
        return 1;
    }
    ot_balance_terms(oil, per_mu, carried, T_supply, terms);
    ot_balance bal = {oil, a, T_supply, terms[1], terms[0], T_old};
    /* thermal.film_temperature's bracket: a loss (shift < 0) may put the root below the supply */
    double lo = T_supply + (bal.shift < 0.0 ? bal.shift : 0.0);
    if (T_old < lo) lo = T_old;
    if (lo < oil->T_min) lo = oil->T_min;
    double hi = T_supply + (bal.shift > 0.0 ? bal.shift : 0.0) + bal.gain * ot_mu(oil, lo);
    if (T_old > hi) hi = T_old;
    if (hi > oil->T_max) hi = oil->T_max;
    if (ot_g(&bal, lo) < 0.0) {
        snprintf(why, n, "film temperature: below the oil's range (from %.4g C): the heat lost to the ambient "
                 "(oil_ambient_loss, oil_T_ambient) cools the film further", oil->T_min - OT_KELVIN);
        return 1;
    }
    if (ot_g(&bal, hi) > 0.0) {
        snprintf(why, n, "film temperature: above the oil's range (up to %.4g C): the heat balance at %.4g C still "
                 "heats the film (dissipation %.4g W); cool the supply or widen the oil's range",
                 oil->T_max - OT_KELVIN, oil->T_max - OT_KELVIN, power * ot_mu(oil, hi) / mu_ref);
        return 1;
    }
    if (ot_g(&bal, lo) <= 0.0)
        T = lo;
    else if (ot_g(&bal, hi) == 0.0)
        T = hi;
    else
        T = ot_brentq(&bal, lo, hi, 1e-10, 1e-15);
    if (ot_range(oil, T, "the film temperature (T_eff)", why, n)) return 1;
    out[0] = T;
    out[1] = ot_mu(oil, T);
    return 0;
}
#endif
