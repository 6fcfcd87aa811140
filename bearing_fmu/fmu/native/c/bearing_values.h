/* The model layer of the native bearing FMU, the same code under its FMI 2.0 and its FMI 3.0 layer
 * (as the FMI Reference FMUs share their model code across FMI versions):
 *   bearing_values.c   the variables' names and start values, the parameters' checks alone and
 *                      together, the internal prepared (bn_setup);
 *   bearing_model.c    the evaluation into the outputs (out_of_domain a discrete output, the
 *                      warning at omega = 0), the outputs for a get (a refused state logged once),
 *                      the live instances;
 *   bearing_derivatives.c   the outputs' derivatives along the inputs and the Real parameters;
 *   bearing_thermal.c  the thermal model (the oil of the parameters, the film's temperature);
 *   bearing_calls.c, bearing_log.c  the side of every FMI call (bearing_calls.h), logging;
 *   bearing_state.c    FMU states (BnState: saved, restored, checked, serialised).
 * Each check answers 0, or 1 with the reason in words; statuses are bn_status (FMI 2.0's and
 * 3.0's have the same values), logged through the FMI layer's bn_log. */
#ifndef BEARING_VALUES_H
#define BEARING_VALUES_H

#include "bearing_native.h"

BN_HIDDEN extern const char *const BN_BOOL_NAMES[N_BOOL];

BN_HIDDEN const char *bn_real_name(int vr);          /* a Real variable's name (vr < N_REAL) */
BN_HIDDEN const char *bn_real_unit(int vr);          /* its unit ("" for options without one) */
BN_HIDDEN const char *bn_string_name(int k);         /* a String variable's name (k < N_STRING) */
BN_HIDDEN const char *bn_enum_name(int j);           /* an Integer's name (j < N_INTS: enumeration, option) */
BN_HIDDEN int bn_is_output_real(int vr);

/* every variable at its start value; time 0, not initialised, outputs to compute */
BN_HIDDEN void bn_set_starts(Instance *m);
/* one parameter's value alone (Real vr, String k normalised into out, enumeration j) */
BN_HIDDEN int bn_check_real(int vr, double v, char *why, size_t n);
BN_HIDDEN int bn_check_string(int k, const char *value, char *out, char *why, size_t n);
BN_HIDDEN int bn_check_enum(int j, int v, char *why, size_t n);
/* an Integer parameter's name; its value set (0), or refused as bn_check_* are (1, why; kept refused
 * until a valid value is set: initialisation fails naming it) (k < N_INT) */
BN_HIDDEN const char *bn_int_name(int k);
BN_HIDDEN int bn_set_int(Instance *m, int k, long long v, char *why, size_t n);
/* the parameters together and the internal prepared (bn_setup); the reason in m->init_error */
BN_HIDDEN int bn_prepare(Instance *m);
/* after initialisation: each String and its enumeration show the choice that counted */
BN_HIDDEN void bn_show_choices(Instance *m);

/* the internal at the inputs into the outputs (compute_tangent: K, C too): 0, or 1 with the reason
 * in m->msg, outputs untouched. out_of_domain is a discrete output: in Continuous-Time Mode it
 * keeps its value and the state's own goes to m->ood_now (it takes that at the next event). A
 * force asked at omega = 0 with no squeeze warns once (warn_pending). */
BN_HIDDEN int bn_evaluate(Instance *m);
/* the outputs for a get by `call` of variable `name`: Initialization Mode computes them from the
 * inputs and parameters set so far (BN_ERROR, logged, when it cannot); Event and Continuous-Time
 * Mode when the inputs changed, a refused state BN_DISCARD, logged once (until the inputs change);
 * else BN_OK, or BN_WARNING when a warning was logged since the last call that said so */
BN_HIDDEN bn_status bn_outputs(Instance *m, const char *call, const char *name);
/* BN_WARNING if a warning was logged since the last call that reported one, else BN_OK */
BN_HIDDEN bn_status bn_warned(Instance *m);
/* at termination: how often the state left the surrogate's fitted domain (a warning), if it did */
BN_HIDDEN void bn_log_excursions(Instance *m);

/* a known of a directional derivative: 0 if vr is an input, or a Real parameter in
 * Initialization Mode; else 1 with the reason in why */
BN_HIDDEN int bn_check_known(const Instance *m, unsigned vr, char *why, size_t n);
/* bn_derivative's out: the Real outputs Fy .. Czz (out[vr - VR_FY]), then the thermal ones */
#define D_P_LOSS N_OUTPUTS_REAL
#define D_Q_SIDE (N_OUTPUTS_REAL + 1)
#define D_T_EFF (N_OUTPUTS_REAL + 2)
#define D_MU_EFF (N_OUTPUTS_REAL + 3)
#define D_DER_T_EFF (N_OUTPUTS_REAL + 4)
#define N_DERIVATIVES (N_OUTPUTS_REAL + 5)
/* the derivative of Real output vr along d, out bn_derivative's */
#define BN_OUTPUT_DERIVATIVE(vr, d, out) \
    ((vr) == VR_DER_T_EFF ? (out)[D_DER_T_EFF] : (vr) >= VR_P_LOSS && (vr) <= VR_MU_EFF \
     ? (out)[D_P_LOSS + (int)(vr) - VR_P_LOSS] : (out)[(vr) - VR_FY])
/* the derivatives of the Real outputs (out: BN_OUTPUT_DERIVATIVE) along d (d[vr]: the direction in
 * each input, Real parameter and, in Model Exchange after initialisation, the state T_eff, vr <
 * N_REAL; the outputs' entries unused) at the inputs and parameters set; with_kc: K.., C.. too
 * (else 0). 0, or 1 with the reason in m->msg (the state refused; for K, C: no state next to it).
 * Quiet: no log line, no excursion counted. */
BN_HIDDEN int bn_derivative(Instance *m, const double d[N_REAL], int with_kc, double out[N_DERIVATIVES]);
/* thermal = true: the oil of the parameters into m->oil (bearing_thermal.c): 0, or 1 with the reason in why */
BN_HIDDEN int bn_thermal_setup(Instance *m, char *why, size_t n);
/* thermal = true: the film's temperature at x (bearing_thermal.c): out = factor mu_eff / mu, T_eff,
 * mu_eff, P_loss, Q_side, der(T_eff); 0, or 1 with the reason in m->msg */
BN_HIDDEN int bn_thermal_state(Instance *m, const double x[5], double out[6]);
#if BN_FILM_FLOW
/* thermal = true, for the derivatives: the heat balance at the film report rep (bn_film's, at the
 * parameter mu) and the film temperature T: quasi-static (quasi 1: Initialization Mode) or the one
 * held (m->r[VR_T_EFF]: Model Exchange's state, Co-Simulation's of the last step). out = T [K],
 * mu(T) [Pa s], dmu/dT [Pa s/K], the gain g [K/(Pa s)] of T* = T_supply + shift + g mu(T) (0 when
 * the film dissipates nothing), the balance's denominator rho c_p (inflow - s side flow) + k h A
 * [W/K] (0 then too), the residence time t_res [s], der(T_eff) = (T* - T) / t_res [K/s], the shift
 * [K] (ot_balance_terms). 0, or 1 with the reason in m->msg. */
BN_HIDDEN int bn_heat_balance(Instance *m, const double rep[5], int quasi, double out[8]);
#endif

/* Model Exchange: the continuous states (BN_N_STATES: T_eff, thermal = true), into x (get) or from
 * x (set: the outputs follow at the next get) */
#define BN_ME_THERMAL(m) (BN_N_STATES > 0 && (m)->b[B_THERMAL])
#define BN_IS_ME(m) ((m)->model_exchange)

/* an FMU state: the time, the inputs and Real outputs, out_of_domain; tagged with the layer's
 * tag and the build's GUID (FMI 3.0: instantiation token), so a state of another build is refused,
 * and a checksum (FNV-1a over the fields), so a damaged one is refused too */
typedef struct {
    char tag[24];
    char id[64];
    double t;
    double values[VR_D];
    double thermal[VR_GEOMETRY0 - VR_T_SUPPLY]; /* T_supply and the thermal outputs */
    double peak[2];                     /* peak_pressure, peak_pressure_angle */
    double pad_values[3 * BN_MAX_PADS]; /* tilting pads: their Reals (VR_PAD0 ..: Model Exchange's states) */
    double pads[2 * BN_PAD_STATE_LEN];  /* and their committed state, the last step's start (Instance.pads) */
    int out_of_domain;                  /* the two ints last: no padding (every byte is checked) */
    unsigned check;
} BnState;
/* tilting pads (bearing_state.c): a static evaluation's tilts (pad_out) become the state, rates 0,
 * no history; a Co-Simulation step of h accepted: its end (pad_trial) the state, the one before BDF2's
 * history (stepping.PadStepper.static, accept) */
BN_HIDDEN void bn_pads_static(Instance *m);
BN_HIDDEN void bn_pads_accept(Instance *m, double h);
BN_HIDDEN void bn_state_save(const Instance *m, BnState *s, const char *tag, const char *id);
BN_HIDDEN void bn_state_restore(Instance *m, const BnState *s);
BN_HIDDEN int bn_state_valid(const BnState *s, const char *tag, const char *id);
/* a state of this build whose checksum holds and whose values are finite and in range: 0, or 1
 * with the reason in why */
BN_HIDDEN int bn_state_sound(const BnState *s, const char *tag, const char *id, char *why, size_t n);
/* a state into bytes (size: the buffer's) and back into *out: 0, or 1 with the reason in why */
BN_HIDDEN int bn_state_serialize(const BnState *s, unsigned char *bytes, size_t size, const char *tag, const char *id,
                                 char *why, size_t n);
BN_HIDDEN int bn_state_deserialize(const unsigned char *bytes, size_t size, BnState *out, const char *tag,
                                   const char *id, char *why, size_t n);

#endif
