/* The model layer's side of every FMI call, the same code under the FMI 2.0 layer (fmi2_*.c) and
 * the FMI 3.0 layer (fmi3_*.c): each FMI function there checks its instance and its place in the
 * calling sequence (bn_order_refused) and makes one call here, as the FMI Reference FMUs'
 * fmi2Functions.c and fmi3Functions.c call their shared model code. So an FMU of either version
 * answers a call, a refusal and a refused state with the same status (docs/fmu.md, "FMI status").
 *
 *   bearing_log.c    logging (bn_log, bn_fail: through the layer's m->emit, the first of each
 *                    status echoed to stderr when nothing received it) and the calling sequence;
 *   bearing_calls.c  the modes, getting and setting values, Co-Simulation's step, Model
 *                    Exchange's events and continuous states, FMU states and derivatives.
 *
 * `call` is the FMI function's name as the layer's messages write it (FMI 2.0: "setReal", FMI 3.0:
 * "fmi3SetFloat64"); every function answers a bn_status and logs what it refuses. */
#ifndef BEARING_CALLS_H
#define BEARING_CALLS_H

#include "bearing_values.h"

#define bn_fail BN_NAME(BN_ID, bn_fail)
#define bn_instance_new BN_NAME(BN_ID, bn_instance_new)
#define bn_instance_free BN_NAME(BN_ID, bn_instance_free)
#define bn_start_time BN_NAME(BN_ID, bn_start_time)
#define bn_enter_init BN_NAME(BN_ID, bn_enter_init)
#define bn_exit_init BN_NAME(BN_ID, bn_exit_init)
#define bn_terminate BN_NAME(BN_ID, bn_terminate)
#define bn_reset BN_NAME(BN_ID, bn_reset)
#define bn_get_reals BN_NAME(BN_ID, bn_get_reals)
#define bn_get_int BN_NAME(BN_ID, bn_get_int)
#define bn_get_bool BN_NAME(BN_ID, bn_get_bool)
#define bn_get_strings BN_NAME(BN_ID, bn_get_strings)
#define bn_set_reals BN_NAME(BN_ID, bn_set_reals)
#define bn_set_integer BN_NAME(BN_ID, bn_set_integer)
#define bn_set_bool BN_NAME(BN_ID, bn_set_bool)
#define bn_set_strings BN_NAME(BN_ID, bn_set_strings)
#define bn_derivatives BN_NAME(BN_ID, bn_derivatives)
#define bn_do_step BN_NAME(BN_ID, bn_do_step)
#define bn_enter_event_mode BN_NAME(BN_ID, bn_enter_event_mode)
#define bn_discrete_states BN_NAME(BN_ID, bn_discrete_states)
#define bn_enter_continuous_mode BN_NAME(BN_ID, bn_enter_continuous_mode)
#define bn_completed_step BN_NAME(BN_ID, bn_completed_step)
#define bn_set_time BN_NAME(BN_ID, bn_set_time)
#define bn_no_states BN_NAME(BN_ID, bn_no_states)
#define bn_set_states BN_NAME(BN_ID, bn_set_states)
#define bn_get_states BN_NAME(BN_ID, bn_get_states)
#define bn_get_state_derivatives BN_NAME(BN_ID, bn_get_state_derivatives)
#define bn_get_nominals BN_NAME(BN_ID, bn_get_nominals)
#define bn_fmu_state_get BN_NAME(BN_ID, bn_fmu_state_get)
#define bn_fmu_state_set BN_NAME(BN_ID, bn_fmu_state_set)
#define bn_fmu_state_free BN_NAME(BN_ID, bn_fmu_state_free)
#define bn_fmu_state_size BN_NAME(BN_ID, bn_fmu_state_size)
#define bn_fmu_state_serialize BN_NAME(BN_ID, bn_fmu_state_serialize)
#define bn_fmu_state_deserialize BN_NAME(BN_ID, bn_fmu_state_deserialize)

/* log an error (printf-style) and answer BN_ERROR */
BN_HIDDEN bn_status bn_fail(Instance *m, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* ------------------------------------------------------------------------------ instances and modes */

/* a new instance at its start values in Instantiated (NULL: out of memory), listed live; `emit`
 * the layer's logger (Instance.emit); `allocate` and `release` the importer's memory functions or NULL (calloc, free) */
BN_HIDDEN Instance *bn_instance_new(const char *name, int model_exchange, int logging_on,
                                    int (*emit)(Instance *, bn_status, char *), void *(*allocate)(size_t, size_t),
                                    void (*release)(void *));
/* free a live instance and what its internal holds; a second free of it is reported and ignored */
BN_HIDDEN void bn_instance_free(Instance *m, const char *call);
/* the experiment's start (and stop) time, each checked */
BN_HIDDEN bn_status bn_start_time(Instance *m, const char *call, double start, int stop_defined, double stop);
BN_HIDDEN bn_status bn_enter_init(Instance *m);
/* the parameters checked together, the internal prepared, the outputs at the start time: BN_ERROR
 * naming the parameter; inputs it refuses leave the outputs at their start values, BN_WARNING */
BN_HIDDEN bn_status bn_exit_init(Instance *m, const char *call);
BN_HIDDEN bn_status bn_terminate(Instance *m);
BN_HIDDEN bn_status bn_reset(Instance *m);

/* ------------------------------------------------------------------------------ values */

/* getters stop at the first unknown value reference (BN_ERROR); an output computes the outputs
 * first (bn_outputs); setters go on past a refused value, answering BN_ERROR at the end */
BN_HIDDEN bn_status bn_get_reals(Instance *m, const char *call, const unsigned vr[], size_t n, double values[]);
BN_HIDDEN bn_status bn_get_int(Instance *m, const char *call, unsigned vr, long long *value);
BN_HIDDEN bn_status bn_get_bool(Instance *m, const char *call, unsigned vr, int *value);
BN_HIDDEN bn_status bn_get_strings(Instance *m, const char *call, const unsigned vr[], size_t n, const char *values[]);
BN_HIDDEN bn_status bn_set_reals(Instance *m, const char *call, const unsigned vr[], size_t n, const double values[]);
BN_HIDDEN bn_status bn_set_integer(Instance *m, const char *call, unsigned vr, long long value);
BN_HIDDEN bn_status bn_set_bool(Instance *m, const char *call, unsigned vr, int value);
BN_HIDDEN bn_status bn_set_strings(Instance *m, const char *call, const unsigned vr[], size_t n,
                                   const char *const values[]);

/* directional (adjoint 0) or adjoint derivatives of Real outputs along the knowns: a refused
 * state BN_DISCARD */
BN_HIDDEN bn_status bn_derivatives(Instance *m, const char *call, int adjoint, const unsigned unknowns[],
                                   size_t n_unknowns, const unsigned knowns[], size_t n_knowns, const double seed[],
                                   size_t n_seed, double sensitivity[], size_t n_sensitivity);

/* ------------------------------------------------------------------------------ Co-Simulation */

/* a step from t0 by h: BN_DISCARD for a state the internal refuses (the instance as before), a
 * retry with the inputs unchanged BN_ERROR; *t_done the time reached (the instance's) */
BN_HIDDEN bn_status bn_do_step(Instance *m, const char *call, unsigned allowed, double t0, double h, double *t_done);

/* ------------------------------------------------------------------------------ Model Exchange */

/* out_of_domain, a discrete output, takes the state's value at events only. A refused state is
 * logged once and answered BN_DISCARD by the get of an output; the mode calls answer BN_OK. */
BN_HIDDEN bn_status bn_enter_event_mode(Instance *m);
BN_HIDDEN bn_status bn_discrete_states(Instance *m, const char *call);
BN_HIDDEN bn_status bn_enter_continuous_mode(Instance *m, const char *call);
/* *enter_event: the state crossed the fitted domain's edge since the last event */
BN_HIDDEN bn_status bn_completed_step(Instance *m, const char *call, int *enter_event);
BN_HIDDEN bn_status bn_set_time(Instance *m, const char *call, double time);
/* a call about what this FMU has none of (event indicators): n must be 0 */
BN_HIDDEN bn_status bn_no_states(Instance *m, const char *call, size_t n, const char *what);
/* the continuous states (BN_N_STATES: T_eff with thermal = true): n must be their number */
BN_HIDDEN bn_status bn_set_states(Instance *m, const char *call, const double x[], size_t n);
BN_HIDDEN bn_status bn_get_states(Instance *m, const char *call, double x[], size_t n);
BN_HIDDEN bn_status bn_get_state_derivatives(Instance *m, const char *call, double dx[], size_t n);
BN_HIDDEN bn_status bn_get_nominals(Instance *m, const char *call, double x[], size_t n);

/* ------------------------------------------------------------------------------ FMU states */

/* BnState (bearing_values.h) tagged with the layer's tag and the build's GUID / token */
BN_HIDDEN bn_status bn_fmu_state_get(Instance *m, const char *call, void **state);
BN_HIDDEN bn_status bn_fmu_state_set(Instance *m, const char *call, const void *state);
BN_HIDDEN bn_status bn_fmu_state_free(Instance *m, const char *call, void **state);
BN_HIDDEN bn_status bn_fmu_state_size(Instance *m, const char *call, const void *state, size_t *size);
BN_HIDDEN bn_status bn_fmu_state_serialize(Instance *m, const char *call, const void *state, unsigned char *bytes,
                                           size_t size);
BN_HIDDEN bn_status bn_fmu_state_deserialize(Instance *m, const char *call, const unsigned char *bytes, size_t size,
                                             void **state);

#endif
