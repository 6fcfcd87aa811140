"""The FMI 2.0 calling sequence both bearing FMUs enforce, and FMU states that outlive their free.

``ALLOWED`` is the one table of which call is allowed in which mode (FMI 2.0.4, the tables of
sections 3.2.3 (Model Exchange) and 4.2.4 (Co-Simulation)), over the modes these FMUs have:
Instantiated, Initialization Mode, Step Mode (stepComplete), Event Mode, Continuous-Time Mode
and Terminated. The pythonfmu slave checks it in Python (``refusal``); the native FMU gets it
as bit masks in its generated ``model_config.h`` (``c_defines``) and words its refusals the
same way (fmi2_order.c, ``bn_order_refused``). An out-of-order call is an fmi2Error naming the
call, the mode and what to do; it changes nothing.

Two FMI states are not modes here, on purpose: a discarded doStep (stepFailed) committed
nothing, so the instance stays in Step Mode and takes new inputs and another doStep (FMI 2.0
asks for fmi2SetFMUstate first; the FMUs always allowed this and hosts rely on it); and an
fmi2Error does not end the instance (docs/fmu.md, "FMI status").

``FMUState`` is the pythonfmu slave's FMU state: see there.
"""

from __future__ import annotations

from collections import deque

# (C enumerator, name in messages), in the order of the native FMU's Mode enum
MODES = (("MODE_INSTANTIATED", "Instantiated"), ("MODE_INIT", "Initialization Mode"), ("MODE_STEP", "Step Mode"),
         ("MODE_EVENT", "Event Mode"), ("MODE_CONTINUOUS", "Continuous-Time Mode"), ("MODE_TERMINATED", "Terminated"))
INSTANTIATED, INIT, STEP, EVENT, CONTINUOUS, TERMINATED = (name for _c, name in MODES)
_ALL = frozenset(name for _c, name in MODES)
_OUT_OF_INIT = frozenset({STEP, EVENT, CONTINUOUS})

# call (as in messages: the FMI name without "fmi2", first letter lower) -> modes it is allowed in.
# fmi2FreeInstance, fmi2GetTypesPlatform and fmi2GetVersion are allowed always; fmi2CancelStep
# never (doStep never returns fmi2Pending).
ALLOWED: dict[str, frozenset] = {
    "setDebugLogging": _ALL,
    "setupExperiment": frozenset({INSTANTIATED}),
    "enterInitializationMode": frozenset({INSTANTIATED}),
    "exitInitializationMode": frozenset({INIT}),
    "terminate": _OUT_OF_INIT,
    "reset": _ALL,
    **{f"get{t}": _ALL - {INSTANTIATED} for t in ("Real", "Integer", "Boolean", "String")},
    "setReal": frozenset({INSTANTIATED, INIT, STEP, EVENT, CONTINUOUS}),
    **{f"set{t}": frozenset({INSTANTIATED, INIT, STEP, EVENT}) for t in ("Integer", "Boolean", "String")},
    **{c: _ALL for c in ("getFMUstate", "setFMUstate", "freeFMUstate", "serializedFMUstateSize",
                         "serializeFMUstate", "deSerializeFMUstate")},
    "getDirectionalDerivative": _ALL - {INSTANTIATED},
    # Co-Simulation
    "setRealInputDerivatives": frozenset({INSTANTIATED, INIT, STEP}),
    "getRealOutputDerivatives": frozenset({STEP, TERMINATED}),
    "doStep": frozenset({STEP}),
    **{f"get{t}Status": frozenset({STEP, TERMINATED}) for t in ("", "Real", "Integer", "Boolean", "String")},
    # Model Exchange
    "enterEventMode": frozenset({EVENT, CONTINUOUS}),
    "newDiscreteStates": frozenset({EVENT}),
    "enterContinuousTimeMode": frozenset({EVENT}),
    "completedIntegratorStep": frozenset({CONTINUOUS}),
    "setTime": frozenset({EVENT, CONTINUOUS}),
    "setContinuousStates": frozenset({CONTINUOUS}),
    "getEventIndicators": frozenset({INIT, EVENT, CONTINUOUS, TERMINATED}),
    "getContinuousStates": frozenset({INIT, EVENT, CONTINUOUS, TERMINATED}),
    "getDerivatives": frozenset({EVENT, CONTINUOUS, TERMINATED}),
    "getNominalsOfContinuousStates": frozenset({INSTANTIATED, EVENT, CONTINUOUS, TERMINATED}),
}
CO_SIMULATION_ONLY = frozenset({"setRealInputDerivatives", "getRealOutputDerivatives", "doStep",
                                *(f"get{t}Status" for t in ("", "Real", "Integer", "Boolean", "String"))})
MODEL_EXCHANGE_ONLY = frozenset({"enterEventMode", "newDiscreteStates", "enterContinuousTimeMode",
                                 "completedIntegratorStep", "setTime", "setContinuousStates", "getEventIndicators",
                                 "getContinuousStates", "getDerivatives", "getNominalsOfContinuousStates"})
_NOT_MODES = {True: {STEP}, False: {EVENT, CONTINUOUS}}  # model_exchange -> the modes it never is in


def refusal(call: str, mode: str, model_exchange: bool = False) -> str | None:
    """None if ``call`` is allowed in ``mode``, else the one-line reason (fmi2_order.c's
    ``bn_order_refused`` writes the same words)."""
    allowed = ALLOWED[call]
    if mode in allowed:
        return None
    if call in (CO_SIMULATION_ONLY if model_exchange else MODEL_EXCHANGE_ONLY):
        kinds = ("a Co-Simulation", "a Model Exchange") if model_exchange else ("a Model Exchange", "a Co-Simulation")
        return f"{call} in {mode}: {kinds[0]} call; this instance is {kinds[1]} one"
    here = [name for _c, name in MODES if name in allowed and name not in _NOT_MODES[model_exchange]]
    return f"{call} in {mode}: not allowed there (FMI 2.0: in {' or '.join(here)} only); {_hint(call, allowed, mode)}"


_STAGE = {INSTANTIATED: 0, INIT: 1, STEP: 2, EVENT: 2, CONTINUOUS: 2, TERMINATED: 3}


def _hint(call: str, allowed: frozenset, mode: str) -> str:
    """What to do instead, from where the instance is in its life: before, after or beside the
    modes the call is allowed in."""
    stage = _STAGE[mode]
    if call == "terminate" and stage < 2:
        return "nothing to terminate: the instance was never initialised (free it, or fmi2Reset)"
    if stage > max(_STAGE[m] for m in allowed):
        return "too late: the instance is " + ("terminated" if mode == TERMINATED else "initialised" if stage == 2
                                                else "in Initialization Mode") + " (fmi2Reset starts it over)"
    if stage < min(_STAGE[m] for m in allowed):
        return ("call exitInitializationMode first" if stage == 1 else "call enterInitializationMode first"
                if INIT in allowed else "initialise it first (enterInitializationMode, then exitInitializationMode)")
    return {EVENT: "call enterContinuousTimeMode first", CONTINUOUS: "call enterEventMode first"}.get(
        mode, "call exitInitializationMode first")


def c_defines() -> list[str]:
    """The table for the native FMU's model_config.h: the Mode enumerators and their names, and
    per call ``BN_ALLOW_<call>``, a bit mask over the modes (bit k: the k-th of MODES)."""
    lines = [f"#define BN_MODE_ENUM {', '.join(c for c, _n in MODES)}",
             f"#define BN_MODE_NAMES {{{', '.join(chr(34) + n + chr(34) for _c, n in MODES)}}}"]
    for call, allowed in ALLOWED.items():
        mask = sum(1 << k for k, (_c, name) in enumerate(MODES) if name in allowed)
        lines.append(f"#define BN_ALLOW_{call} 0x{mask:02x}u")
    return lines


# ----------------------------------------------------------------------------- FMU states of the Python slave

FREED_KEPT = 4096  # freed FMU states kept recognisable (a few dozen bytes each)
_FREED: deque = deque(maxlen=FREED_KEPT)


class FMUState(list):
    """An FMU state of the pythonfmu slave: the master's fmi2FMUstate is this object's address.

    pythonfmu's fmi2FreeFMUstate only drops the master's reference, so the object would be
    deallocated and a later fmi2SetFMUstate (or serialisation) with the stale pointer would read
    freed memory. Instead, when the master frees it, ``__del__`` keeps it (emptied, marked
    ``freed``, among the last FREED_KEPT freed states): a later use is refused with fmi2Error.
    Python calls a finaliser once per object, so each fmi2GetFMUstate makes a new one."""

    freed = None  # the state itself once the master freed it (a class default: read fast, no exception)

    def __del__(self):
        try:
            self.freed = self  # its own second reference: a repeated fmi2FreeFMUstate drops only that
            self.clear()
            _FREED.append(self)
        except Exception:  # noqa: BLE001 - interpreter shutdown: nothing to keep
            pass


def is_freed(state) -> bool:
    """True for an FMU state the master has freed (fmi2FreeFMUstate)."""
    return getattr(state, "freed", None) is not None


__all__ = ["ALLOWED", "MODES", "FMUState", "c_defines", "is_freed", "refusal"]
