"""How a command ends, for both command lines: its exit code and its last line.

Exit codes (``run_command``): 0 done, 1 the run failed (its results say why; also a result
written to a rescue folder, or a write the machine refused: a full disk, a read-only file
system), 2 bad input (a file, key or option named in one line), 130 / 143 interrupted by SIGINT /
SIGTERM (128 + the signal: ``interrupts.Interrupted``). No traceback unless ``--debug``. The
interrupt's last line says what was kept (``interrupts.note_kept``), or what had been computed
and could not be kept (``interrupts.note_lost``). The names the command still holds are freed at
its end (``outputs.release_held``).
"""

from __future__ import annotations

import errno
import signal
import sys
from pathlib import Path

from .interrupts import as_interrupted, handled
from .outputs import release_held, take_rescued, take_written

EXIT_FAILED, EXIT_BAD_INPUT = 1, 2
# what a user can fix by changing a file or an option: one line, exit 2
BAD_INPUT = (ValueError, KeyError, OSError)
# ... but an OSError with one of these is the machine refusing a write mid-run: exit 1
MACHINE_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EIO, errno.EFBIG})


EXIT_CODES = """exit codes: 0 done; 1 the run failed (its json says why), or a result could not be written where
asked (a full disk, a read-only folder: it is in the rescue folder named); 2 bad input (the file, key or
option is named); 130 / 143 interrupted by SIGINT / SIGTERM (what was computed is written,
status "interrupted"). Add --debug for the Python traceback of an error."""


def run_command(prog: str, args) -> int:
    """Run ``args.func(args)`` under ``handled()``; map its end to an exit code and one line
    on stderr (see the module docstring). ``args.debug`` re-raises with the traceback. A
    result written to a rescue folder (``outputs``: the place asked refused it) makes a run
    that went well exit 1, with one line naming the path, why and where the files are."""
    name = f"{prog} {getattr(args, 'command', '')}".strip()
    take_rescued(), take_written()  # a command's files are its own (several commands may run in one process)
    try:
        code = _run(name, args)
    finally:  # a signal between a run's last write and its own release: its name is freed here
        release_held()
    take_written()
    rescued = take_rescued()
    if rescued:
        first = rescued[0]
        where = ", ".join(dict.fromkeys(str(Path(r.to).parent) for r in rescued))
        print(f"{name}: error: {len(rescued)} result file(s) could not be written where asked ({first.path}: "
              f"{first.reason}); they are in {where}", file=sys.stderr)
        if code == 0:
            code = EXIT_FAILED
    return code


def _run(name: str, args) -> int:
    debug = getattr(args, "debug", False)
    try:
        with handled():
            return args.func(args)
    except KeyboardInterrupt as exc:
        sig = as_interrupted(exc)
        print(f"{name}: interrupted by {sig.signal_name}; {_kept_line(exc)}", file=sys.stderr)
        return sig.exit_code
    except BrokenPipeError:  # the reader went away (`... | head`): no message, the shell's SIGPIPE code
        import os

        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except OSError:
            pass
        return 128 + signal.SIGPIPE
    except BAD_INPUT as exc:
        if debug:
            raise
        print(f"{name}: error: {_one_line(exc)}", file=sys.stderr)
        # the machine refused a write (a full disk, a read-only file system): the run failed, its input was fine
        return EXIT_FAILED if isinstance(exc, OSError) and exc.errno in MACHINE_ERRNOS else EXIT_BAD_INPUT
    except RuntimeError as exc:  # a failure this code diagnosed (no equilibrium, an FMU error): exit 1
        if debug:
            raise
        print(f"{name}: error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_FAILED
    except Exception as exc:  # noqa: BLE001 - unforeseen, most likely a bug: one line and how to see more
        if debug:
            raise
        print(f"{name}: error: {type(exc).__name__}: {_one_line(exc)} (run with --debug for the traceback)",
              file=sys.stderr)
        return EXIT_FAILED


def _kept_line(exc: BaseException) -> str:
    """What an interrupted command kept, or what it had computed and could not keep."""
    kept, lost = getattr(exc, "kept", None), getattr(exc, "lost", None)
    if kept:
        return f"kept: {'; '.join(kept)}"
    if lost:
        return f"nothing kept: {'; '.join(lost)}"
    written = take_written()  # an interrupt after the command wrote its results (in printing them)
    if written:
        return (f"kept: the {len(written)} file(s) written before it" + (", the last: " if len(written) > 3 else ": ")
                + ", ".join(str(p) for p in written[-3:]))
    return "nothing had been computed yet"


def _one_line(exc: BaseException) -> str:
    if isinstance(exc, KeyError) and exc.args:
        return str(exc.args[0])  # str(KeyError) adds quotes
    if isinstance(exc, OSError) and exc.filename is not None and exc.strerror:
        return f"{exc.filename}: {exc.strerror}"
    return str(exc)
