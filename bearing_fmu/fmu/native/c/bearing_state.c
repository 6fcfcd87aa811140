/* FMU states (the FMI layers' get, set, free, size, serialise and deserialise calls, bearing_calls.h)
 * and the model layer's BnState behind them (bearing_values.h): saved, restored, checked and
 * serialised. Moved here from bearing_calls.c and bearing_model.c unchanged. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bearing_calls.h"

#if BN_FMI3
#include "fmi3_config.h"
#define STATE_TAG "bearing-native3/1"
#define BUILD_ID BN3_TOKEN
#else
#define STATE_TAG "bearing-native/1"
#define BUILD_ID BN_GUID
#endif

/* ------------------------------------------------------------------------------ FMU states */

/* FNV-1a (32 bits) over the state's fields, not its padding */
static unsigned fnv(unsigned h, const void *p, size_t n) {
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 16777619u;
    return h;
}

static unsigned checksum(const BnState *s) {
    unsigned h = 2166136261u;
    h = fnv(h, s->tag, sizeof s->tag);
    h = fnv(h, s->id, sizeof s->id);
    h = fnv(h, &s->t, sizeof s->t);
    h = fnv(h, s->values, sizeof s->values);
    h = fnv(h, s->thermal, sizeof s->thermal);
    h = fnv(h, &s->out_of_domain, sizeof s->out_of_domain);
    h = fnv(h, s->peak, sizeof s->peak);
    h = fnv(h, s->pad_values, sizeof s->pad_values);
    return fnv(h, s->pads, sizeof s->pads);
}

/* ------------------------------------------------------------------------------ the pads' state */

void bn_pads_static(Instance *m) {
    for (int k = 0; k < BN_N_PADS; k++) {
        m->pads[PS_DELTA + k] = m->work.pad_out[k];
        m->pads[PS_RATE + k] = 0.0;
    }
    m->pads[PS_PREV_DT] = 0.0;
    m->pads[PS_DT] = 0.0;
}

void bn_pads_accept(Instance *m, double h) {
    double dt = m->pads[PS_DT];
    memcpy(m->pads + BN_PAD_STATE_LEN, m->pads, BN_PAD_STATE_LEN * sizeof(double)); /* the step's start */
    for (int k = 0; k < BN_N_PADS; k++) {
        m->pads[PS_PREV_DELTA + k] = m->pads[PS_DELTA + k];
        m->pads[PS_PREV_RATE + k] = m->pads[PS_RATE + k];
        m->pads[PS_DELTA + k] = m->work.pad_trial[k];
        m->pads[PS_RATE + k] = m->work.pad_trial[BN_MAX_PADS + k];
    }
    /* the history is the old committed state, h before the new one (after a static state: none, backward Euler) */
    m->pads[PS_PREV_DT] = dt > 0.0 ? h : 0.0;
    m->pads[PS_DT] = h;
}

void bn_state_save(const Instance *m, BnState *s, const char *tag, const char *id) {
    memset(s, 0, sizeof *s);
    snprintf(s->tag, sizeof s->tag, "%s", tag);
    snprintf(s->id, sizeof s->id, "%s", id);
    s->t = m->t;
    memcpy(s->values, m->r, sizeof s->values);
    memcpy(s->thermal, m->r + VR_T_SUPPLY, sizeof s->thermal);
    s->out_of_domain = m->b[B_OUT_OF_DOMAIN];
    memcpy(s->peak, m->r + VR_PEAK, sizeof s->peak);
    memcpy(s->pad_values, m->r + VR_PAD0, BN_N_PAD_REALS * sizeof(double));
    memcpy(s->pads, m->pads, sizeof s->pads);
    s->check = checksum(s);
}

void bn_state_restore(Instance *m, const BnState *s) {
    m->t = s->t;
    memcpy(m->r, s->values, sizeof s->values);
    memcpy(m->r + VR_T_SUPPLY, s->thermal, sizeof s->thermal);
    m->b[B_OUT_OF_DOMAIN] = s->out_of_domain;
    memcpy(m->r + VR_PEAK, s->peak, sizeof s->peak);
    memcpy(m->r + VR_PAD0, s->pad_values, BN_N_PAD_REALS * sizeof(double));
    memcpy(m->pads, s->pads, sizeof m->pads);
    m->terminated = 0;
    m->refused_state = 0;
    m->step_refused = 0;
    m->dirty = 1; /* the outputs follow the inputs restored at the next get */
}

int bn_state_valid(const BnState *s, const char *tag, const char *id) {
    return s && strncmp(s->tag, tag, sizeof s->tag) == 0 && strncmp(s->id, id, sizeof s->id) == 0;
}

int bn_state_sound(const BnState *s, const char *tag, const char *id, char *why, size_t n) {
    char a[32];
    if (!bn_state_valid(s, tag, id)) {
        snprintf(why, n, "not a %s state of this FMU", tag);
        return 1;
    }
    if (s->check != checksum(s)) {
        snprintf(why, n, "a damaged %s state: its checksum does not match its contents", tag);
        return 1;
    }
    /* what the instance itself can hold: finite values (inputs are refused otherwise, outputs
     * computed finite), a distance, a temperature and a viscosity that are not negative */
    const char *bad = NULL;
    double v = 0.0;
    if (!isfinite(s->t)) bad = "time", v = s->t;
    for (int i = 0; !bad && i < VR_D; i++)
        if (!isfinite(s->values[i])) bad = bn_real_name(i), v = s->values[i];
    for (int i = 0; !bad && i < VR_GEOMETRY0 - VR_T_SUPPLY; i++)
        if (!isfinite(s->thermal[i]) || (i != VR_P_LOSS - VR_T_SUPPLY && s->thermal[i] < 0.0))
            bad = bn_real_name(VR_T_SUPPLY + i), v = s->thermal[i];
    if (!bad && !(s->values[VR_ECC] >= 0.0)) bad = "eccentricity", v = s->values[VR_ECC];
    if (!bad && s->out_of_domain != 0 && s->out_of_domain != 1) bad = "out_of_domain", v = s->out_of_domain;
    for (int i = 0; !bad && i < 2; i++) /* a pressure is not negative */
        if (!isfinite(s->peak[i]) || (i == 0 && s->peak[i] < 0.0)) bad = bn_real_name(VR_PEAK + i), v = s->peak[i];
    for (int i = 0; !bad && i < BN_N_PAD_REALS; i++)
        if (!isfinite(s->pad_values[i])) bad = bn_real_name(VR_PAD0 + i), v = s->pad_values[i];
    for (int i = 0; !bad && i < 2 * BN_PAD_STATE_LEN; i++) /* the steps' sizes are >= 0 */
        if (!isfinite(s->pads[i]) || (i % BN_PAD_STATE_LEN >= PS_PREV_DT && s->pads[i] < 0.0))
            bad = "the pads' state", v = s->pads[i];
    if (bad) {
        snprintf(why, n, "a %s state holding %s = %s (not finite or out of range)", tag, bad, bn_num(a, 32, v, 17));
        return 1;
    }
    return 0;
}

/* serialised as it is (the same platform, the same build: the tag and id say so) */
int bn_state_serialize(const BnState *s, unsigned char *bytes, size_t size, const char *tag, const char *id,
                       char *why, size_t n) {
    if (!bn_state_valid(s, tag, id)) {
        snprintf(why, n, "not a %s state of this FMU", tag);
        return 1;
    }
    if (size < sizeof *s) {
        snprintf(why, n, "a buffer of %lu bytes is smaller than the state (%lu bytes)", (unsigned long)size,
                 (unsigned long)sizeof *s);
        return 1;
    }
    memcpy(bytes, s, sizeof *s);
    return 0;
}

int bn_state_deserialize(const unsigned char *bytes, size_t size, BnState *out, const char *tag, const char *id,
                         char *why, size_t n) {
    BnState s;
    if (size == sizeof s) memcpy(&s, bytes, sizeof s); /* a copy: the bytes need not be aligned */
    if (size != sizeof s || !bn_state_valid(&s, tag, id)) {
        snprintf(why, n, "%lu bytes are not a serialised %s state of this FMU", (unsigned long)size, tag);
        return 1;
    }
    char reason[160];
    if (bn_state_sound(&s, tag, id, reason, sizeof reason)) {
        snprintf(why, n, "%s", reason);
        return 1;
    }
    *out = s;
    return 0;
}

/* ------------------------------------------------------------------------------ FMU states */
/* the model layer's BnState (the time, the inputs and outputs, out_of_domain, a few hundred bytes),
 * tagged with this build's GUID (FMI 3.0: instantiation token) so that a state of another build is
 * refused; serialised as it is (same platform, same build). The FMU has no state of its own
 * besides: the internals keep only caches and counts. */

bn_status bn_fmu_state_get(Instance *m, const char *call, void **state) {
    if (!state) return bn_fail(m, "%s: FMUState is NULL", call);
    BnState *s = *state;
    if (!s) {
        s = m->allocate(1, sizeof(BnState));
        if (!s) return bn_fail(m, "%s: out of memory", call);
        *state = s;
    }
    bn_state_save(m, s, STATE_TAG, BUILD_ID);
    return BN_OK;
}

bn_status bn_fmu_state_set(Instance *m, const char *call, const void *state) {
    char why[200];
    if (bn_state_sound(state, STATE_TAG, BUILD_ID, why, sizeof why))
        return bn_fail(m, "%s: %s; the instance keeps its state", call, why);
    bn_state_restore(m, state);
    return BN_OK;
}

bn_status bn_fmu_state_free(Instance *m, const char *call, void **state) {
    if (!state) return bn_fail(m, "%s: FMUState is NULL", call);
    if (*state) {
        /* no tag left: a stale copy of the pointer used soon after is likely refused, not restored
         * (not a guarantee: the memory is freed; the master's own pointer is set to NULL) */
        memset(((BnState *)*state)->tag, 0, sizeof((BnState *)*state)->tag);
        m->release(*state);
    }
    *state = NULL;
    return BN_OK;
}

bn_status bn_fmu_state_size(Instance *m, const char *call, const void *state, size_t *size) {
    if (!size) return bn_fail(m, "%s: size is NULL", call);
    if (!bn_state_valid(state, STATE_TAG, BUILD_ID)) return bn_fail(m, "%s: not a %s state of this FMU", call, STATE_TAG);
    *size = sizeof(BnState);
    return BN_OK;
}

bn_status bn_fmu_state_serialize(Instance *m, const char *call, const void *state, unsigned char *bytes, size_t size) {
    char why[200];
    if (bn_state_serialize(state, bytes, size, STATE_TAG, BUILD_ID, why, sizeof why))
        return bn_fail(m, "%s: %s", call, why);
    return BN_OK;
}

bn_status bn_fmu_state_deserialize(Instance *m, const char *call, const unsigned char *bytes, size_t size,
                                   void **state) {
    BnState s;
    char why[200];
    if (!state) return bn_fail(m, "%s: FMUState is NULL", call);
    if (bn_state_deserialize(bytes, size, &s, STATE_TAG, BUILD_ID, why, sizeof why))
        return bn_fail(m, "%s: %s; the FMU state given keeps its contents", call, why);
    if (!*state && !(*state = m->allocate(1, sizeof(BnState)))) return bn_fail(m, "%s: out of memory", call);
    *(BnState *)*state = s;
    return BN_OK;
}
