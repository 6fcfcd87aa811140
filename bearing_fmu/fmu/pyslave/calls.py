"""The slave's calls: the FMI 2.0 calling sequence (``order``), refusals as fmi2Error
(``FMIError``, raised where the build patched pythonfmu's binary, else logged), and logging, with
the first message of each status echoed to stderr when the master has logging off."""

from pathlib import Path

from pythonfmu.enums import Fmi2Status

from ..order import INIT, INSTANTIATED, TERMINATED, refusal

ECHO_HINT = ("logging is off, so this FMU instance prints its first warning, discard and error here; "
             "instantiate it with loggingOn (fmpy: simulate_fmu(..., debug_logging=True)) to receive every message")


class FMIError(Exception):
    """Raised out of a pythonfmu entry point so that the call returns fmi2Error (patched binary).

    pythonfmu logs ``repr()`` of the exception after "fmi2Error from the Python slave [call]":
    the repr is the message itself, so that one line says what was refused and why."""

    def __repr__(self) -> str:
        return str(self)


class CallRules:
    """Logging, refusals and the calling sequence of ``slave.BearingFMU`` (a pythonfmu ``Fmi2Slave``)."""

    # ------------------------------------------------------------------ logging and refusals
    def _log(self, msg: str, status: Fmi2Status) -> None:
        try:
            self.log(msg, status)
        except Exception:  # logging must never be the thing that fails
            pass
        self._echo(msg, status)

    def _echo(self, msg: str, status: Fmi2Status) -> None:
        """When the master has logging off, print the first message of each status to stderr."""
        if status == Fmi2Status.ok or status in self._echoed or not self._logging.off():
            return
        import sys

        self._echoed.add(status)
        hint = "" if len(self._echoed) > 1 else f"\n  ({ECHO_HINT})"
        try:
            print(f"bearing FMU {self.instance_name!r} [{status.name}]: {msg}{hint}", file=sys.stderr, flush=True)
        except Exception:  # noqa: BLE001 - no stderr: nothing more to do
            pass

    def _fail(self, msg: str):
        """Refuse the current call with ``msg``: raise FMIError, which the patched binary
        returns as fmi2Error and logs as "fmi2Error from the Python slave [call] ... msg".
        Without the patches, log ``msg`` with status Error and return None: the caller goes on
        the way pythonfmu allows (the call returns fmi2OK)."""
        if not self._raises:
            self._log(msg, Fmi2Status.error)
            return None
        # pythonfmu hands the queued log lines to the master's logger before it fetches the
        # exception: a Python logger (fmpy) would run with the exception pending and lose it.
        # So this call's earlier lines travel in the exception's message instead.
        queued = [f"[{getattr(m.status, 'name', m.status)}] {m.msg}" for m in self.log_queue]
        self.log_queue.clear()  # the very list pythonfmu holds: cleared in place
        self._echo(msg, Fmi2Status.error)
        raise FMIError(msg + (f" (logged before it in this call: {' | '.join(queued)})" if queued else ""))

    # ------------------------------------------------------------------ the FMI 2.0 calling sequence
    def _order(self, call: str) -> None:
        """Refuse ``call`` (fmi_order's name) unless the current mode allows it: FMIError, i.e.
        fmi2Error naming the call. Without the status patches (or driven from Python, as tests and
        benchmarks do) the refusal is logged with status Error and the call goes on as before."""
        why = refusal(call, self._mode)
        if why is not None:
            self._fail(why)

    def _enter(self, mode: str) -> None:
        """Change the mode, and the fast paths with it: getReal's reads no output outside Step Mode
        and Terminated (Initialization Mode computes them first) and nothing in Instantiated;
        setReal's takes no input once terminated. What they skip takes the checked path."""
        self._mode = mode
        self._real_get = ({} if mode is INSTANTIATED else self._real_no_outputs if mode is INIT
                          else self._real_names)
        self._real_inputs = {} if mode is TERMINATED else self._all_inputs
        self._real_getters = {}  # get_real's per value-reference list (access.py), for this mode

    @staticmethod
    def _describe(exc: BaseException) -> str:
        """One line: the message of an expected failure; the type, message and place of anything
        else. Never a traceback: a log line is read in a master's message window."""
        from ...physics.statics import EquilibriumError

        if isinstance(exc, (ValueError, KeyError, FileNotFoundError, ImportError, EquilibriumError)):
            text = str(exc)
        else:
            tb = exc.__traceback__
            while tb is not None and tb.tb_next is not None:
                tb = tb.tb_next
            where = (f" (raised in {Path(tb.tb_frame.f_code.co_filename).name}, line {tb.tb_lineno})"
                     if tb is not None else "")
            text = f"unexpected {type(exc).__name__}: {exc}{where}"
        return " ".join(text.split())
