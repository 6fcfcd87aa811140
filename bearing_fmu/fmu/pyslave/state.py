"""The slave's FMU state (fmi2GetFMUstate and the rest): the time and every input and output as
one tuple (``order.FMUState``: recognised once freed); the internal is not part of it (it is
fixed after initialisation), so saving and restoring costs a few microseconds."""

import json
import operator

from ..order import FMUState, is_freed
from ..variables import INPUTS, OUTPUTS
from .calls import FMIError

STATE_TAG = "bearing_fmu.fmu.slave/2"  # /2: values as one tuple
STATE_NAMES = INPUTS + OUTPUTS
STATE_VALUES = operator.attrgetter(*STATE_NAMES)


class StateSaving:
    """The FMU state of ``slave.BearingFMU``."""

    # A host iterating the FMI way saves the state once per step and restores it at every
    # iteration, so both run in C where they can (attrgetter, dict.update): a state this
    # class wrote holds the right types already.
    def _get_fmu_state(self):
        # a new FMUState each time: pythonfmu hands this very object back on fmi2SetFMUstate, and
        # once the master frees it, it stays recognisable (fmi_order.FMUState)
        return FMUState((STATE_TAG, self._t, STATE_VALUES(self)))

    def _set_fmu_state(self, state):
        try:
            if is_freed(state):
                raise ValueError("this FMU state was freed (fmi2FreeFMUstate)")
            if len(state) != 3 or state[0] != STATE_TAG or len(state[2]) != len(STATE_NAMES):
                raise ValueError(f"not a {STATE_TAG} state of this FMU")
            t = float(state[1])
        except Exception as exc:  # noqa: BLE001
            return self._fail(f"setFMUstate: {exc}; the instance keeps its state")
        self._t = t
        self.__dict__.update(zip(STATE_NAMES, state[2]))
        self._discarded = None  # a restored state may be stepped with any inputs

    # pythonfmu calls these on the class (fmi2SerializedFMUstateSize, fmi2SerializeFMUstate,
    # fmi2DeSerializeFMUstate); a refusal raises (fmi2Error)
    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        if is_freed(state):
            raise FMIError("serializing an FMU state: this FMU state was freed (fmi2FreeFMUstate)")
        return json.dumps(list(state)).encode("utf-8")

    @staticmethod
    def _fmu_state_from_bytes(data: bytes):
        return FMUState(json.loads(data.decode("utf-8")))
