/* FMU states of the FMI 3.0 bearing FMU: the inputs, the outputs, out_of_domain as of the last
 * event and the time (a few hundred bytes), tagged with the instantiation token so that a state
 * of another build is refused; serialised as they are (same platform, same build). The FMU has
 * no state of its own besides: the internals keep only caches and counts. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_layer.h"

#define STATE_TAG "bearing-native3/1"
typedef struct {
    char tag[24];
    char token[64];
    double t;
    double values[VR_D]; /* inputs and Float64 outputs */
    int out_of_domain, ood_event;
} State;

static int valid_state(const State *s) {
    return s && strncmp(s->tag, STATE_TAG, sizeof s->tag) == 0 && strncmp(s->token, BN3_TOKEN, sizeof s->token) == 0;
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetFMUState, BN_ANY_TYPE);
    if (!FMUState) return bn3_fail(m, "fmi3GetFMUState: FMUState is NULL");
    State *s = *FMUState;
    if (!s) {
        s = calloc(1, sizeof(State));
        if (!s) return bn3_fail(m, "fmi3GetFMUState: out of memory");
        *FMUState = s;
    }
    memset(s, 0, sizeof *s);
    snprintf(s->tag, sizeof s->tag, "%s", STATE_TAG);
    snprintf(s->token, sizeof s->token, "%s", BN3_TOKEN);
    s->t = m->t;
    memcpy(s->values, m->r, sizeof s->values);
    s->out_of_domain = m->b[B_OUT_OF_DOMAIN];
    s->ood_event = m->ood_event;
    return fmi3OK;
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
    Instance *m = instance;
    const State *s = FMUState;
    if (!m) return fmi3Error;
    ORDER3(SetFMUState, BN_ANY_TYPE);
    if (!valid_state(s))
        return bn3_fail(m, "fmi3SetFMUState: not a %s state of this FMU; the instance keeps its state", STATE_TAG);
    m->t = s->t;
    memcpy(m->r, s->values, sizeof s->values);
    m->b[B_OUT_OF_DOMAIN] = s->out_of_domain;
    m->ood_event = s->ood_event;
    m->dirty = 1;
    return fmi3OK;
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(FreeFMUState, BN_ANY_TYPE);
    if (!FMUState) return bn3_fail(m, "fmi3FreeFMUState: FMUState is NULL");
    if (*FMUState) {
        /* no tag left: a stale copy of the pointer used soon after is likely refused, not restored
         * (not a guarantee: the memory is freed; the master's own pointer is set to NULL) */
        memset(((State *)*FMUState)->tag, 0, sizeof((State *)*FMUState)->tag);
        free(*FMUState);
    }
    *FMUState = NULL;
    return fmi3OK;
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(SerializedFMUStateSize, BN_ANY_TYPE);
    if (!size) return bn3_fail(m, "fmi3SerializedFMUStateSize: size is NULL");
    if (!valid_state(FMUState)) return bn3_fail(m, "fmi3SerializedFMUStateSize: not a %s state of this FMU", STATE_TAG);
    *size = sizeof(State);
    return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
                                 size_t size) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(SerializeFMUState, BN_ANY_TYPE);
    if (!valid_state(FMUState)) return bn3_fail(m, "fmi3SerializeFMUState: not a %s state of this FMU", STATE_TAG);
    if (size < sizeof(State))
        return bn3_fail(m, "fmi3SerializeFMUState: a buffer of %lu bytes is smaller than the state (%lu bytes)",
                        (unsigned long)size, (unsigned long)sizeof(State));
    memcpy(serializedState, FMUState, sizeof(State));
    return fmi3OK;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState) {
    Instance *m = instance;
    State s;
    if (!m) return fmi3Error;
    ORDER3(DeserializeFMUState, BN_ANY_TYPE);
    if (!FMUState) return bn3_fail(m, "fmi3DeserializeFMUState: FMUState is NULL");
    if (size == sizeof(State)) memcpy(&s, serializedState, sizeof s);
    if (size != sizeof(State) || !valid_state(&s))
        return bn3_fail(m, "fmi3DeserializeFMUState: %lu bytes are not a serialised %s state of this FMU",
                        (unsigned long)size, STATE_TAG);
    if (!*FMUState) {
        *FMUState = calloc(1, sizeof(State));
        if (!*FMUState) return bn3_fail(m, "fmi3DeserializeFMUState: out of memory");
    }
    memcpy(*FMUState, &s, sizeof s);
    return fmi3OK;
}
