/* The oil's viscosity laws and the film's effective temperature in C (ports of
 * bearing_fmu/physics/oil.py: Walther through two points, Vogel; and physics/thermal.py
 * film_temperature: the heat balance at a fixed journal state, quasi-static or lagged by the
 * residence time, solved by Brent's method as scipy's brentq). The model layer's, for the native
 * FMU's thermal ports; compiled alone with RS_EXPORT for the ctypes comparison with Python
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
#elif defined(__GNUC__) || defined(__clang__)
#define OT_API __attribute__((visibility("hidden")))
#else
#define OT_API
#endif

enum { OT_NONE = 0, OT_WALTHER = 1, OT_VOGEL = 2 }; /* ports.OIL_LAWS' order */

typedef struct {
    int law;
    double c[3];            /* walther: A, B of log10(log10(nu [cSt] + 0.7)) = A - B log10(T); vogel: a [Pa s], b, c [K] */
    double T_min, T_max;    /* the range the law may be used in [K] */
    double density;         /* [kg/m^3] */
    double heat_capacity;   /* [J/(kg K)] */
    double rise_factor;     /* k of T_eff = T_supply + k dT */
} ot_oil;

/* The oil of the FMU parameters (ports.oil_of): law (OT_*), Walther's two points nu [m^2/s] at
 * T [K], Vogel's a [Pa s], b, c [K], the range, density, heat capacity, rise factor. 0, or 1 with
 * the reason (Oil's checks, in the parameters' names) in why. */
OT_API int ot_oil_of(ot_oil *oil, int law, double nu1, double T1, double nu2, double T2, double va, double vb,
                     double vc, double T_min, double T_max, double density, double heat_capacity, double rise_factor,
                     char *why, size_t n);
/* mu [Pa s] at T [K] (no range check: Oil._mu) */
OT_API double ot_mu(const ot_oil *oil, double T);
/* film_temperature: out = T [K], mu(T) [Pa s], residence time [s] from the film report at the
 * viscosity mu_ref (power [W], inflow, side flow [m^3/s]) of a bearing R, CR, L [m], oil supplied
 * at T_supply [K]; quasi-static (lagged 0) or lagged from T_old over dt [s]. 0, or 1 with the
 * reason in why (the oil's range left, no oil carried away). */
OT_API int ot_film_temperature(const ot_oil *oil, double mu_ref, double R, double CR, double L, double power,
                               double inflow, double side_flow, double T_supply, int lagged, double T_old, double dt,
                               double out[3], char *why, size_t n);

#endif
