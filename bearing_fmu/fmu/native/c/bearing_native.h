/* The native bearing FMU: what its three layers share, as the FMI Reference FMUs share their
 * model code across FMI versions: the FMI layer (FMI 2.0: fmi2_*.c; FMI 3.0, compiled with
 * BN_FMI_VERSION=3: fmi3_*.c), the model layer of either (bearing_values.h: the variables, the
 * parameters' checks, the evaluation and its derivatives) and the internal (internal_<name>.c).
 * Generated per build: model_config.h (the internal's name, its options and value references,
 * start values, the GUID) and model_data.h (the internal's data as static arrays). Units are SI
 * throughout (m, m/s, rad/s, N, Pa s).
 *
 * Value references: Reals 0..; Booleans from 1000; Strings from 2000; Integers (the enumerations,
 * each the same choice as a String parameter, then the internal's Integer options) from 3000. */
#ifndef BEARING_NATIVE_H
#define BEARING_NATIVE_H

#include <stddef.h>
#if defined(BN_FMI_VERSION) && BN_FMI_VERSION == 3
#define BN_FMI3 1
#else
#define BN_FMI3 0
#endif
#if BN_FMI3
#include "fmi3Functions.h"
typedef fmi3Status bn_status; /* FMI 2's and FMI 3's statuses have the same values */
#define BN_OK fmi3OK
#define BN_WARNING fmi3Warning
#define BN_DISCARD fmi3Discard
#define BN_ERROR fmi3Error
#define BN_FMI_TEXT "FMI 3.0"
#define BN_REAL_TYPE "Float64"
#define BN_INT_TYPE "Int64 or Enumeration"
#define BN_TRUE_TEXT "true"
#define BN_FALSE_TEXT "false"
/* the FMI functions' names as the messages write them, and what the standard calls them */
#define BN_CALL(fmi2_name, fmi3_name) "fmi3" #fmi3_name
#define BN_CALL_WORD "function"
#else
#include "fmi2Functions.h"
typedef fmi2Status bn_status;
#define BN_OK fmi2OK
#define BN_WARNING fmi2Warning
#define BN_DISCARD fmi2Discard
#define BN_ERROR fmi2Error
#define BN_FMI_TEXT "FMI 2.0"
#define BN_REAL_TYPE "Real"
#define BN_INT_TYPE "Integer"
#define BN_TRUE_TEXT "True"
#define BN_FALSE_TEXT "False"
#define BN_CALL(fmi2_name, fmi3_name) #fmi2_name
#define BN_CALL_WORD "call"
#endif
#include "model_config.h"
#include "oil_thermal.h"
#ifndef BN_THERMAL_START
#define BN_THERMAL_START 0 /* the parameter thermal's start (build_native_fmu(thermal=True): 1) */
#endif

/* FMI2_FUNCTION_PREFIX (FMI 2.0, 2.1.1): the FMI functions named "<prefix>fmi2GetReal" ..., to link
 * the sources of several FMUs into one program. fmpy's copy of fmi2Functions.h ignores it (its
 * fmi2FullName adds no prefix), the standard's honours it: applied here for either. */
#if defined(FMI2_FUNCTION_PREFIX)
#undef fmi2FullName
#define BN_FMI_PASTE(a, b) a##b
#define BN_FMI_NAME(a, b) BN_FMI_PASTE(a, b)
#define fmi2FullName(name) BN_FMI_NAME(FMI2_FUNCTION_PREFIX, name)
#endif

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* No fused multiply-add, so the sums round alike on every platform (the build passes
 * -ffp-contract=off as well; gcc in ISO C mode and MSVC's /fp:precise do not contract). */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

/* Vector kernels (internal_taylor.c): 2-lane doubles through gcc's and clang's vector extension
 * (SSE2, NEON), and on x86-64 a 4-lane AVX2 version chosen at run time when the CPU has it;
 * plain C with other compilers. */
#if defined(__GNUC__) || defined(__clang__)
#define BN_ALIGN32 __attribute__((aligned(32)))
#define BN_VEC 1
typedef double bn_v2 __attribute__((vector_size(16), may_alias));
#if defined(__x86_64__) && !defined(BN_NO_AVX)
#define BN_AVX 1
typedef double bn_v4 __attribute__((vector_size(32), may_alias));
#else
#define BN_AVX 0
#endif
#else
#define BN_ALIGN32
#define BN_VEC 0
#define BN_AVX 0
#endif

enum {
    VR_Y, VR_Z, VR_VY, VR_VZ, VR_OMEGA,                  /* inputs: journal state */
    VR_FY, VR_FZ, VR_ECC, VR_HMIN,                       /* outputs */
    VR_KYY, VR_KYZ, VR_KZY, VR_KZZ, VR_CYY, VR_CYZ, VR_CZY, VR_CZZ,
    VR_D, VR_L, VR_CR, VR_MU,                            /* parameters: the bearing */
    VR_REAL_OPTIONS                                      /* the internal's Real options follow */
};
#define N_INPUTS 5
#define N_OUTPUTS_REAL (VR_D - VR_FY)
/* the thermal ports (bearing_fmu/fmu/ports.py) after the internal's Real options: the input
 * T_supply, the outputs P_loss, Q_side, T_eff, mu_eff; the parameter thermal (a Boolean) */
#define VR_T_SUPPLY (VR_REAL_OPTIONS + BN_N_REAL_OPTIONS)
#define VR_P_LOSS (VR_T_SUPPLY + 1)
#define VR_Q_SIDE (VR_T_SUPPLY + 2)
#define VR_T_EFF (VR_T_SUPPLY + 3)
#define VR_MU_EFF (VR_T_SUPPLY + 4)
/* the bore (ports.py's geometry parameters): this FMU's data hold one; its values are the starts
 * and another is refused at initialisation (bn_prepare), naming the parameters. The Reals
 * groove_1 .. groove_8, groove_width, supply_pressure, arc_start, arc_end, preload, lobe_offset,
 * lobe_angle, circumferential_groove follow the thermal ports; the Integers groove_count, lobes the enumerations; the
 * Boolean partial_arc the others */
#define VR_GEOMETRY0 (VR_T_SUPPLY + 5)
#define N_GEOMETRY_REALS 16
/* the oil's Reals (ports.OIL_ROWS: oil_nu_1 .. oil_rise_factor; ports.BALANCE_ROWS: oil_outflow_share,
 * oil_ambient_loss, oil_T_ambient) after the bore's; its law is the build's (BN_OIL_LAW) */
#define VR_OIL0 (VR_GEOMETRY0 + N_GEOMETRY_REALS)
#define N_OIL_REALS 15
/* der(T_eff), a local: in Model Exchange T_eff is the one continuous state of a build whose
 * internal has the film's flows and whose bearing an oil law (BN_N_STATES 1), this its derivative */
#define VR_DER_T_EFF (VR_OIL0 + N_OIL_REALS)
/* tilting pads (internal_tilting_pad.c; generators/tilting_pad.py): N pads' Reals after the peak pressure's, the
 * tilts pad_tilt_k (outputs), then massless der(pad_tilt_k) (locals), with inertia pad_rate_k
 * (outputs) and der(pad_rate_k) (locals); Model Exchange's continuous states are the first
 * BN_N_PAD_STATES of them (after T_eff's, if any), their derivatives the next BN_N_PAD_STATES */
#ifndef BN_N_PADS
#define BN_N_PADS 0
#define BN_N_PAD_REALS 0
#define BN_N_PAD_STATES 0
#define BN_N_PAD_OUTPUTS 0
#endif
#define BN_MAX_PADS 12
/* the film's peak pressure and its angle (outputs; the Reynolds internal's field, else 0) after der(T_eff) */
#define VR_PEAK (VR_DER_T_EFF + 1)
#define VR_PEAK_ANGLE (VR_PEAK + 1)
#define BN_IS_PEAK(vr) ((vr) == VR_PEAK || (vr) == VR_PEAK_ANGLE)
#define VR_PAD0 (VR_PEAK + 2)
#define N_REAL (VR_PAD0 + BN_N_PAD_REALS)
#define BN_IS_PAD_REAL(vr) ((vr) >= VR_PAD0 && (vr) < N_REAL)
/* Model Exchange's continuous states: T_eff (BN_N_STATES), then the pads' */
#define BN_NX (BN_N_STATES + BN_N_PAD_STATES)
/* the pads' committed state (Instance.pads, part of the FMU state): tilts, rates, the step before
 * (BDF2's history) and its size (0: none), the size of the step that led to it (0: a static one) */
enum { PS_DELTA = 0, PS_RATE = BN_MAX_PADS, PS_PREV_DELTA = 2 * BN_MAX_PADS, PS_PREV_RATE = 3 * BN_MAX_PADS,
       PS_PREV_DT = 4 * BN_MAX_PADS, PS_DT, BN_PAD_STATE_LEN };
#define BN_IS_INPUT(vr) ((vr) < N_INPUTS || (vr) == VR_T_SUPPLY)
#define BN_IS_THERMAL_OUTPUT(vr) (((vr) >= VR_P_LOSS && (vr) <= VR_MU_EFF) || (vr) == VR_DER_T_EFF)
#define VR_BOOL0 1000
enum { B_OUT_OF_DOMAIN, B_COMPUTE_TANGENT, B_THERMAL, B_PARTIAL_ARC, N_BOOL };
#define VR_STRING0 2000
#define S_INTERNAL 0                                     /* then the internal's String options */
#define N_STRING (1 + BN_N_STRING_OPTIONS)
#define STRING_MAX 256
#define VR_INT0 3000
#define N_ENUM BN_N_ENUMS                                /* internal_enum, then the String options' */
#define N_INTS (N_ENUM + BN_N_INT_OPTIONS)               /* the enumerations, then the internal's Integer
                                                            options (reynolds: n_theta, n_x) */
#define N_INT 2                                          /* then the Integers groove_count, lobes */
#define VR_INT_PARAM0 (VR_INT0 + N_INTS)
#define N_PARAM_SLOTS (N_REAL + N_BOOL + N_STRING + N_INTS + N_INT)
/* an Integer option's value (model_config.h I_OPT_<NAME>) */
#define BN_INT_OPTION(m, name) ((m)->e[N_ENUM + I_OPT_##name])

/* the FMI 2.0 modes (bearing_fmu/fmi_order.py: MODES; which call is allowed in which: BN_ALLOW_<call>) */
typedef enum { BN_MODE_ENUM } Mode;

/* what an internal keeps between calls (not part of the FMU state: caches and counts) */
typedef struct {
    int last_nn;      /* taylor: index of the stored training state nearest to the last state queried, -1: none */
    int excursions;   /* taylor: excursions out of the fitted domain warned so far (one warning each) */
    double excursion_t[2]; /* taylor: the time of the first and of the last one [s] */
    double scale;     /* map: S = mu R L (R / CR)^2 [N s] */
    int avx;          /* taylor: the CPU runs the AVX2 kernels */
    int quiet;        /* evaluations for a derivative: no excursion warning (internal_taylor.c) */
    void *block;      /* reynolds: the solver's memory (the FMI callbacks'), block_bytes long; freed by bn_release */
    void *solver;     /* reynolds: the solver inside it */
    size_t block_bytes;
    void *pad_solver[BN_MAX_PADS]; /* tilting pads: each pad's solver (one warm start each), in block */
    double pad_warm[BN_MAX_PADS];  /* tilting pads: the last equilibrium's tilts (the Newton's start) */
    double pad_out[3 * BN_MAX_PADS]; /* tilting pads: the last evaluation's pad Reals (VR_PAD0 ..) */
    double pad_trial[2 * BN_MAX_PADS]; /* tilting pads: the tilts and rates at the end of the step evaluated */
} Work;

typedef struct Instance {
    double r[N_REAL];
    int b[N_BOOL];
    char s[N_STRING][STRING_MAX];
    int e[N_INTS];              /* the enumerations as set, then the Integer options */
    int n[N_INT];               /* the Integer parameters (groove_count, lobes) as set */
    char eff[N_STRING][STRING_MAX]; /* the String choices as they count (a String, or its enumeration): setup() */
    double t;
    Mode mode;
    int terminated;             /* fmi2Terminated: never set (every refused state can be retried with another) */
    int dirty;                  /* ME: inputs changed since the outputs were computed */
    int refused_state;          /* ME: the inputs as set were refused (logged once, until they change) */
    int step_refused;           /* CS: the last doStep was discarded (no good step or restore since) */
    double refused_inputs[N_INPUTS + 1]; /* its inputs (and T_supply): a retry with these unchanged is an error
                                   (the same state is refused whatever the step; fmpy's simulate_fmu re-sets them) */
    double refused_t;           /* and its currentCommunicationPoint [s] */
    int ood_now;                /* out_of_domain of the last evaluated state (ME: out_of_domain takes it at events) */
    int still;                  /* the force was asked at omega = 0 with no squeeze (warned once, until it moves) */
    int warn_pending;           /* a warning was logged: the FMI call returns a warning status */
    int mute;                   /* no log lines (the states a derivative's differences evaluate) */
    int refused[N_PARAM_SLOTS]; /* a parameter whose last set was refused */
    char refused_msg[N_PARAM_SLOTS][512];
    char init_error[2400];
    char msg[2048];             /* the internal's reason for a refused state */
    int logging_on;
    int echoed;                 /* bit mask of statuses already echoed to stderr (logging off) */
    char name[STRING_MAX];
    int model_exchange;         /* the interface it was instantiated for (else Co-Simulation) */
    double stop_time;           /* FMI 3.0: fmi3EnterInitializationMode's; INFINITY when not defined (FMI 2.0: always) */
    /* the FMI layer's: give one log line to the importer's logger (1), or 0 when it did not reach
     * one (bn_log then echoes the first of each status to stderr); may rewrite text in place */
    int (*emit)(struct Instance *m, bn_status status, char *text);
    void *(*allocate)(size_t n, size_t size); /* the importer's memory functions (FMI 2.0), else calloc, free */
    void (*release)(void *p);
#if BN_FMI3
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log_message;
    unsigned log_off;           /* bit k: log category of status k switched off (fmi3SetDebugLogging) */
#else
    fmi2CallbackFunctions cb;
#endif
    Work work;
    double step_h;              /* Co-Simulation: the step an evaluation ends [s] (0: none; bn_do_step) */
    double pads[2 * BN_PAD_STATE_LEN]; /* tilting pads: the committed state (PS_*), then the one the last
                                   Co-Simulation step started from (its derivatives); saved in the FMU state */
    ot_oil oil;                 /* thermal = true: the oil of the parameters (bn_thermal_setup) */
    int thermal_lagged;         /* the next evaluation lags T_eff from its value over thermal_dt (a step), */
    double thermal_dt;          /* else (Initialization Mode) it is quasi-static */
    struct Instance *next_live; /* the list of live instances (fmi2FreeInstance) */
} Instance;

/* Every name shared between this FMU's files carries its model identifier (BN_ID, model_config.h),
 * so the sources of two native FMUs link into one program (with FMI2_FUNCTION_PREFIX set to
 * each one's "<modelIdentifier>_" for the FMI functions). */
#define BN_PASTE(a, b) a##_##b
#define BN_NAME(a, b) BN_PASTE(a, b)
/* An FMU of several internals (BN_PARTS > 1): each internal_<name>.c (which sets BN_PART to its
 * name) defines <id>_<name>_bn_setup ..., and bn_parts.c the plain ones, dispatching on the
 * parameter internal. One internal: the internal's file defines the plain ones. */
#if BN_PARTS > 1 && defined(BN_PART)
#define BN_FN(name) BN_NAME(BN_ID, BN_NAME(BN_PART, name))
#else
#define BN_FN(name) BN_NAME(BN_ID, name)
#endif
#define bn_setup BN_FN(bn_setup)
#define bn_eval BN_FN(bn_eval)
#define bn_option_derivative BN_FN(bn_option_derivative)
#define bn_release BN_FN(bn_release)
#define bn_shape_derivative BN_FN(bn_shape_derivative)
#define bn_film BN_FN(bn_film)
#define bn_peak BN_FN(bn_peak)
#define bn_fallback_eval BN_NAME(BN_ID, bn_fallback_eval)
#define bn_fallback_film BN_NAME(BN_ID, bn_fallback_film)
#define bn_fallback_set BN_NAME(BN_ID, bn_fallback_set)
#define bn_log BN_NAME(BN_ID, bn_log)
#define bn_num BN_NAME(BN_ID, bn_num)
#define bn_order_refused BN_NAME(BN_ID, bn_order_refused)
#define bn_live_add BN_NAME(BN_ID, bn_live_add)
#define bn_live_remove BN_NAME(BN_ID, bn_live_remove)
/* the model layer (bearing_values.h) */
#define BN_BOOL_NAMES BN_NAME(BN_ID, BN_BOOL_NAMES)
#define bn_real_name BN_NAME(BN_ID, bn_real_name)
#define bn_real_unit BN_NAME(BN_ID, bn_real_unit)
#define bn_string_name BN_NAME(BN_ID, bn_string_name)
#define bn_enum_name BN_NAME(BN_ID, bn_enum_name)
#define bn_is_output_real BN_NAME(BN_ID, bn_is_output_real)
#define bn_set_starts BN_NAME(BN_ID, bn_set_starts)
#define bn_check_real BN_NAME(BN_ID, bn_check_real)
#define bn_check_string BN_NAME(BN_ID, bn_check_string)
#define bn_check_enum BN_NAME(BN_ID, bn_check_enum)
#define bn_set_int BN_NAME(BN_ID, bn_set_int)
#define bn_int_name BN_NAME(BN_ID, bn_int_name)
#define bn_prepare BN_NAME(BN_ID, bn_prepare)
#define bn_show_choices BN_NAME(BN_ID, bn_show_choices)
#define bn_evaluate BN_NAME(BN_ID, bn_evaluate)
#define bn_outputs BN_NAME(BN_ID, bn_outputs)
#define bn_warned BN_NAME(BN_ID, bn_warned)
#define bn_log_excursions BN_NAME(BN_ID, bn_log_excursions)
#define bn_check_known BN_NAME(BN_ID, bn_check_known)
#define bn_derivative BN_NAME(BN_ID, bn_derivative)
#define bn_heat_balance BN_NAME(BN_ID, bn_heat_balance)
#define bn_thermal_setup BN_NAME(BN_ID, bn_thermal_setup)
#define bn_thermal_state BN_NAME(BN_ID, bn_thermal_state)
#define bn_state_save BN_NAME(BN_ID, bn_state_save)
#define bn_state_restore BN_NAME(BN_ID, bn_state_restore)
#define bn_state_valid BN_NAME(BN_ID, bn_state_valid)
#define bn_state_sound BN_NAME(BN_ID, bn_state_sound)
#define bn_state_serialize BN_NAME(BN_ID, bn_state_serialize)
#define bn_state_deserialize BN_NAME(BN_ID, bn_state_deserialize)
#define bn_pads_static BN_NAME(BN_ID, bn_pads_static)
#define bn_pads_accept BN_NAME(BN_ID, bn_pads_accept)

/* Shared between this FMU's files, never exported: only the FMI functions are (a binary built
 * by any CMake project too; Windows exports only what fmi2Functions.h marks dllexport). */
#if (defined(__GNUC__) || defined(__clang__)) && !defined(_WIN32)
#define BN_HIDDEN __attribute__((visibility("hidden")))
#else
#define BN_HIDDEN
#endif

/* the internal (internal_<name>.c) */
/* Check the parameters together and prepare; 0, or 1 with the reason in m->msg. */
BN_HIDDEN int bn_setup(Instance *m);
/* Film force F [N] at x = (y, z, vy, vz, omega) and, with want_jac, J = dF/d(y, z, vy, vz)
 * row-major (2 x 4) and dw = dF/domega (2). 0, or 1 with the reason in m->msg (state refused).
 * *ood: the state lies outside the fitted domain (taylor). */
BN_HIDDEN int bn_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2], int *ood);
/* dF and dJ (as in bn_eval) with respect to the internal's k-th Real option (model_config.h
 * BN_REAL_OPTION_TABLE), at x: linear's coefficients; 0 for options the force does not depend on. */
BN_HIDDEN void bn_option_derivative(Instance *m, const double x[5], int k, double dF[2], double dJ[8]);
/* Free what bn_setup allocated (the instance is being freed; nothing for most internals). */
BN_HIDDEN void bn_release(Instance *m);
/* BN_BEARING_IN_FORCE 2 (reynolds: F = mu R L (R / CR)^2 G(L/D, q/CR, v/CR, omega)): dF and, with
 * want_jac, dJ along ln(L/D) at a fixed scale, at x. 0, or 1 with the reason in m->msg. */
BN_HIDDEN int bn_shape_derivative(Instance *m, const double x[5], int want_jac, double dF[2], double dJ[8]);
#if BN_FILM_FLOW
/* The film's report at x, right after bn_eval there (an internal with the film's flows:
 * BN_FLOWS_<NAME>, its registry capability film_flow and its data's): Couette and pressure torque
 * [N m], friction power [W], inflow, side flow [m^3/s]. 0, or 1 with the reason in m->msg. */
BN_HIDDEN int bn_film(Instance *m, const double x[5], double out[5]);
#endif
#if BN_HOLDS_REYNOLDS
/* The film's peak pressure [Pa] and its angle [rad] at the state bn_eval just solved (the Reynolds
 * internal's field; in an FMU of several, 0 and 0 for an internal set without one: bn_parts.c). */
BN_HIDDEN void bn_peak(Instance *m, double out[2]);
#endif
/* Why the internal as set has no film report ("" when it has one: thermal = true can run). One
 * internal: BN_FILM_FLOW_WHY; several: the one set's (bn_parts.c, model_config.h BN_FLOW_WHY_<name>). */
#if BN_PARTS > 1
#define bn_film_why BN_NAME(BN_ID, bn_film_why)
BN_HIDDEN const char *bn_film_why(const Instance *m);
#else
#define bn_film_why(m) ((void)(m), BN_FILM_FLOW ? "" : BN_FILM_FLOW_WHY)
#endif
/* Does the force of the internal as set depend on the bearing (0 no, 1 by the scale law, 2 and on
 * L/D) and on the speed? One internal: BN_BEARING_IN_FORCE, BN_SPEED_IN_FORCE; several: its own. */
#if BN_PARTS > 1
#define bn_force_depends BN_NAME(BN_ID, bn_force_depends)
BN_HIDDEN void bn_force_depends(const Instance *m, int *bearing, int *speed);
#else
#define bn_force_depends(m, bearing, speed) (*(bearing) = BN_BEARING_IN_FORCE, *(speed) = BN_SPEED_IN_FORCE)
#endif
/* Taylor's domain_action = fallback in an FMU that holds the Reynolds internal too (bn_fallback.c):
 * the Reynolds force at x, as bn_eval */
BN_HIDDEN int bn_fallback_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2]);
/* and its film report at x, right after bn_fallback_eval there (Taylor's film report, fallback) */
BN_HIDDEN int bn_fallback_film(Instance *m, const double x[5], double out[5]);
/* Taylor as set with domain_action = fallback in an FMU that holds Reynolds too (bn_fallback.c) */
BN_HIDDEN int bn_fallback_set(const Instance *m);

/* log one line (printf-style) with a status (bearing_log.c, through the FMI layer's emit) */
BN_HIDDEN void bn_log(Instance *m, bn_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* a double the way Python's %.{digits}g writes it, into buf */
BN_HIDDEN const char *bn_num(char *buf, size_t n, double x, int digits);

/* the calling sequence (bearing_log.c): 0 if `call` (the FMI function's name as the messages write
 * it) is allowed in the instance's mode (`allowed`: its BN_ALLOW_ / BN3_ALLOW_ mask) for an
 * instance of `kind`, else 1 with an error logged naming it, the mode and what to do, in the words
 * of bearing_fmu/fmu/order.py's refusal */
enum { BN_ANY_TYPE, BN_CS_ONLY, BN_ME_ONLY };
BN_HIDDEN int bn_order_refused(Instance *m, const char *call, unsigned allowed, int kind);
/* the live instances (bearing_model.c): add one; remove one (1, or 0 if it was not live) */
BN_HIDDEN void bn_live_add(Instance *m);
BN_HIDDEN int bn_live_remove(Instance *m);

#endif
