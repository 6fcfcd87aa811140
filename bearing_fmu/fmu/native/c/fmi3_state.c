/* FMU states of the FMI 3.0 bearing FMU: the model layer's BnState (the inputs, the outputs,
 * out_of_domain and the time, a few hundred bytes), tagged with the instantiation token so that a
 * state of another build is refused; serialised as they are (same platform, same build). The FMU
 * has no state of its own besides: the internals keep only caches and counts. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_layer.h"

#define STATE_TAG "bearing-native3/1"
typedef BnState State;

static int valid_state(const State *s) { return bn_state_valid(s, STATE_TAG, BN3_TOKEN); }

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
    bn_state_save(m, s, STATE_TAG, BN3_TOKEN);
    return fmi3OK;
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
    Instance *m = instance;
    const State *s = FMUState;
    if (!m) return fmi3Error;
    ORDER3(SetFMUState, BN_ANY_TYPE);
    if (!valid_state(s))
        return bn3_fail(m, "fmi3SetFMUState: not a %s state of this FMU; the instance keeps its state", STATE_TAG);
    bn_state_restore(m, s);
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
    char why[200];
    if (!m) return fmi3Error;
    ORDER3(SerializeFMUState, BN_ANY_TYPE);
    if (bn_state_serialize(FMUState, serializedState, size, STATE_TAG, BN3_TOKEN, why, sizeof why))
        return bn3_fail(m, "fmi3SerializeFMUState: %s", why);
    return fmi3OK;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState) {
    Instance *m = instance;
    State s;
    char why[200];
    if (!m) return fmi3Error;
    ORDER3(DeserializeFMUState, BN_ANY_TYPE);
    if (!FMUState) return bn3_fail(m, "fmi3DeserializeFMUState: FMUState is NULL");
    if (bn_state_deserialize(serializedState, size, &s, STATE_TAG, BN3_TOKEN, why, sizeof why))
        return bn3_fail(m, "fmi3DeserializeFMUState: %s", why);
    if (!*FMUState && !(*FMUState = calloc(1, sizeof(State))))
        return bn3_fail(m, "fmi3DeserializeFMUState: out of memory");
    *(State *)*FMUState = s;
    return fmi3OK;
}
