/* The oil's viscosity laws and the film's effective temperature in C (ports of
 * bearing_fmu/physics/oil.py: Walther through two points, Vogel; and physics/thermal.py
 * film_temperature: the heat balance at a fixed journal state, quasi-static or lagged by the
 * residence time, solved by Brent's method as scipy's brentq). The model layer's, for the native
 * FMU's thermal ports (bearing_thermal.c); compiled alone with RS_EXPORT for the ctypes comparison with Python
 * (bearing_fmu/fmu/native/solver_lib.py, tests/test_native_thermal.py). */
#ifndef OIL_THERMAL_H
#define OIL_THERMAL_H

#include <stddef.h>

#if defined(RS_EXPORT)
#if defined(_WIN32)
#define OT_API __declspec(dllexport)
#else
#define OT_API __attribute__((visibility("default")))
#endif
#else /* in an FMU: a unit of its own, its names the FMU's (model_config.h BN_ID, as bearing_native.h's) and hidden */
#include "model_config.h"
#define OT_PASTE(a, b) a##_##b
#define OT_NAME(a, b) OT_PASTE(a, b)
#define ot_mu OT_NAME(BN_ID, ot_mu)
#define ot_oil_of OT_NAME(BN_ID, ot_oil_of)
#define ot_dmu_dT OT_NAME(BN_ID, ot_dmu_dT)
#define ot_balance_terms OT_NAME(BN_ID, ot_balance_terms)
#define ot_film_rate OT_NAME(BN_ID, ot_film_rate)
#define ot_film_temperature OT_NAME(BN_ID, ot_film_temperature)
#if (defined(__GNUC__) || defined(__clang__)) && !defined(_WIN32)
#define OT_API __attribute__((visibility("hidden")))
#else
#define OT_API
#endif
#endif

enum { OT_NONE = 0, OT_WALTHER = 1, OT_VOGEL = 2 }; /* ports.OIL_LAWS' order */

typedef struct {
    int law;
    double c[3];            /* walther: A, B of log10(log10(nu [cSt] + 0.7)) = A - B log10(T); vogel: a [Pa s], b, c [K] */
    double T_min, T_max;    /* the range the law may be used in [K] */
    double density;         /* [kg/m^3] */
    double heat_capacity;   /* [J/(kg K)] */
    double rise_factor;     /* k of T_eff = T_supply + k dT */
    double outflow_share;   /* s of the heat carried away, rho c_p (Q - s Qs) dT: 0.5 (outflow_rise half) or 0 (full) */
    double ambient_W_K;     /* h A: heat lost to the ambient per kelvin of T_eff above T_ambient [W/K] */
    double T_ambient;       /* the ambient's temperature [K]; 0: the supply temperature */
} ot_oil;

/* mu [Pa s] at T [K] (no range check) */
OT_API double ot_mu(const ot_oil *oil, double T);
/* the oil of the FMU parameters: 0, or 1 with the reason in why */
OT_API int ot_oil_of(ot_oil *oil, int law, double nu1, double T1, double nu2, double T2, double va, double vb,
                     double vc, double T_min, double T_max, double density, double heat_capacity, double rise_factor,
                     double outflow_share, double ambient_W_K, double T_ambient, char *why, size_t n);
/* dmu/dT [Pa s/K] at T [K] */
OT_API double ot_dmu_dT(const ot_oil *oil, double T);
/* the heat balance's terms of T* = T_supply + shift + gain mu(T): out = gain [K/(Pa s)], shift [K], its
 * denominator rho c_p carried + k h A [W/K] */
OT_API void ot_balance_terms(const ot_oil *oil, double per_mu, double carried, double T_supply, double out[3]);
/* the heat balance's rate at the film temperature T (oil_thermal.c says what out holds): 0, or 1 with why */
OT_API int ot_film_rate(const ot_oil *oil, double mu_ref, double R, double CR, double L, double power, double inflow,
                        double side_flow, double T_supply, double T, double out[3], char *why, size_t n);
/* the film temperature, quasi-static or lagged over dt from T_old: 0, or 1 with why */
OT_API int ot_film_temperature(const ot_oil *oil, double mu_ref, double R, double CR, double L, double power,
                               double inflow, double side_flow, double T_supply, int lagged, double T_old, double dt,
                               double out[3], char *why, size_t n);

#endif
