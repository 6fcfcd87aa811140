/* The values of a native bearing FMU whatever its FMI version (bearing_values.c): the variables'
 * names, start values, the parameters' checks alone and together, the internal's preparation and
 * its evaluation into the outputs. Each check answers 0, or 1 with the reason in words.
 *
 * Used by the FMI 3.0 layer (fmi3_*.c). fmi2_bearing.c still has its own copy of the checks and
 * the option tables (static; the same code to the letter, kept so by hand until the FMI 2 layer
 * calls this file: its setup and evaluation have since gained the FMI rules' additions, which
 * this file's bn_prepare and bn_evaluate must take over first). */
#ifndef BEARING_VALUES_H
#define BEARING_VALUES_H

#include "bearing_native.h"

extern const char *const BN_BOOL_NAMES[N_BOOL];

const char *bn_real_name(int vr);          /* a Real variable's name (vr < N_REAL) */
const char *bn_real_unit(int vr);          /* its unit ("" for options without one) */
const char *bn_string_name(int k);         /* a String variable's name (k < N_STRING) */
const char *bn_enum_name(int j);           /* an enumeration's name (j < N_ENUM) */
int bn_is_output_real(int vr);

/* every variable at its start value; time 0, not initialised, outputs to compute */
void bn_set_starts(Instance *m);
/* one parameter's value alone (Real vr, String k normalised into out, enumeration j) */
int bn_check_real(int vr, double v, char *why, size_t n);
int bn_check_string(int k, const char *value, char *out, char *why, size_t n);
int bn_check_enum(int j, int v, char *why, size_t n);
/* the parameters together and the internal prepared (bn_setup); the reason in m->init_error */
int bn_prepare(Instance *m);
/* after initialisation: each String and its enumeration show the choice that counted */
void bn_show_choices(Instance *m);
/* the internal at the inputs into the outputs (compute_tangent: K, C too); the reason in m->msg,
 * outputs untouched */
int bn_evaluate(Instance *m);

#endif
