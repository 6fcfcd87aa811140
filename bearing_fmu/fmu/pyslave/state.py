"""The slave's FMU state (fmi2GetFMUstate and the rest): the time, every input and output, and the
internal's states of its own over a step (``Capabilities.step_states``: a tilting pad's tilts and
rates, its ``step_state()``; empty for every other internal) as one tuple (``order.FMUState``:
recognised once freed); the internal itself is not part of it (it is fixed after initialisation),
so saving and restoring costs a few microseconds.

A serialised state carries a checksum (SHA-256 of its JSON) and is checked when it is read back
(``sound``): its tag and length, the time and every value finite, each in its range
(out_of_domain a Boolean, eccentricity >= 0, mu_eff > 0), the internal's states finite numbers;
fmi2SetFMUstate checks the tag, the length, that it was not freed and that the internal takes its
states (``set_step_state``: their count for this bearing's pads). A state object is the FMU's own,
made by fmi2GetFMUstate or read back checked. A state that fails is refused with fmi2Error and the
instance (or the state given to fmi2DeSerializeFMUstate) keeps what it had."""

import hashlib
import json
import math
import operator

from ..order import FMUState, is_freed
from ..variables import INPUTS, OUTPUTS
from .calls import FMIError

STATE_TAG = "bearing_fmu.fmu.slave/4"  # /3: checked values, a checksum when serialised; /4: the internal's states
STATE_NAMES = INPUTS + OUTPUTS
STATE_VALUES = operator.attrgetter(*STATE_NAMES)
_POSITIVE = ("mu_eff",)  # > 0 (T_supply and T_eff, its copy with thermal off, may be any number then)
_NOT_NEGATIVE = ("eccentricity",)  # >= 0


def sound(state) -> str:
    """Why ``state`` is not a usable state of this FMU ("" when it is)."""
    if is_freed(state):
        return "this FMU state was freed (fmi2FreeFMUstate)"
    try:
        tag, t, values, own = state
        if tag != STATE_TAG or len(values) != len(STATE_NAMES):
            return f"not a {STATE_TAG} state of this FMU"
    except (TypeError, ValueError):
        return f"not a {STATE_TAG} state of this FMU"
    if not all(isinstance(x, float) and math.isfinite(x) for x in own):
        return "the internal's states (a tilting pad's tilts and rates) are not all finite numbers"
    if not isinstance(t, float) or not math.isfinite(t):
        return f"its time {t!r} s is not a finite number"
    for name, value in zip(STATE_NAMES, values):
        if name == "out_of_domain":
            if not isinstance(value, bool):
                return f"out_of_domain = {value!r} is not a Boolean"
            continue
        if not isinstance(value, float) or not math.isfinite(value):
            return f"{name} = {value!r} is not a finite number"
        if (name in _POSITIVE and not value > 0.0) or (name in _NOT_NEGATIVE and value < 0.0):
            return f"{name} = {value!r} is out of its range ({'> 0' if name in _POSITIVE else '>= 0'})"
    return ""


def _checksum(payload: list) -> str:
    return hashlib.sha256(json.dumps(payload).encode("utf-8")).hexdigest()


class StateSaving:
    """The FMU state of ``slave.BearingFMU``."""

    # A host iterating the FMI way saves the state once per step and restores it at every
    # iteration, so both run in C where they can (attrgetter, dict.update): a state this
    # class wrote holds the right types already.
    def _get_fmu_state(self):
        # a new FMUState each time: pythonfmu hands this very object back on fmi2SetFMUstate, and
        # once the master frees it, it stays recognisable (fmi_order.FMUState)
        return FMUState((STATE_TAG, self._t, STATE_VALUES(self),
                         () if self._stepped is None else self._stepped.step_state()))

    def _set_fmu_state(self, state):
        try:
            if is_freed(state):
                raise ValueError("this FMU state was freed (fmi2FreeFMUstate)")
            if len(state) != 4 or state[0] != STATE_TAG or len(state[2]) != len(STATE_NAMES):
                raise ValueError(f"not a {STATE_TAG} state of this FMU")
            if self._stepped is not None:  # checked whole before anything is set
                self._stepped.set_step_state(state[3])
            elif state[3]:
                raise ValueError(f"it carries {len(state[3])} states of an internal (tilting pads), and this "
                                 f"instance's internal ({self._internal_name or 'none built'}) has none")
        except Exception as exc:  # noqa: BLE001
            return self._fail(f"setFMUstate: {exc}; the instance keeps its state")
        self._t = state[1]
        self.__dict__.update(zip(STATE_NAMES, state[2]))
        self._discarded = None  # a restored state may be stepped with any inputs

    # pythonfmu calls these on the class (fmi2SerializedFMUstateSize, fmi2SerializeFMUstate,
    # fmi2DeSerializeFMUstate); a refusal raises (fmi2Error)
    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        if is_freed(state):
            raise FMIError("serializing an FMU state: this FMU state was freed (fmi2FreeFMUstate)")
        payload = [state[0], state[1], list(state[2]), list(state[3])]
        return json.dumps(payload + [_checksum(payload)]).encode("utf-8")

    @staticmethod
    def _fmu_state_from_bytes(data: bytes):
        try:
            *payload, checksum = json.loads(bytes(data).decode("utf-8"))
        except (ValueError, TypeError, UnicodeDecodeError):
            raise FMIError(f"deserializing an FMU state: not a serialised {STATE_TAG} state (unreadable); the FMU "
                           "state given keeps its contents") from None
        if (len(payload) != 4 or not isinstance(payload[2], list) or not isinstance(payload[3], list)
                or checksum != _checksum(payload)):
            raise FMIError(f"deserializing an FMU state: its checksum does not match its contents (damaged or not a "
                           f"{STATE_TAG} state); the FMU state given keeps its contents")
        state = FMUState((payload[0], payload[1], tuple(payload[2]), tuple(payload[3])))
        why = sound(state)
        if why:
            raise FMIError(f"deserializing an FMU state: {why}; the FMU state given keeps its contents")
        return state
