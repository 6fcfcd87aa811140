"""Run a command line with one function paused, so a test acts at a known moment (not by timing).

    python tests/pause_at.py MODULE:ATTR[.ATTR] rotor-host|bearing-fmu ARGS...

The $PAUSE_CALL-th call (default 1st) of MODULE.ATTR (e.g. ``distributed:LocalCluster.close``)
whose keyword arguments include those of $PAUSE_KWARGS (JSON, optional) writes the file
$PAUSE_MARKER, then waits until the file $PAUSE_GO exists (without $PAUSE_GO: until a signal
ends the wait) and calls the original. A test sends its signal, remounts a folder read-only,
... once the marker is there. Worker processes forked by the command inherit the pause.
"""

import importlib
import json
import os
import sys
import time
from pathlib import Path


def pause(target: str) -> None:
    module, _, attrs = target.partition(":")
    *path, name = attrs.split(".")
    owner = importlib.import_module(module)
    for a in path:
        owner = getattr(owner, a)
    original = getattr(owner, name)
    marker, go = Path(os.environ["PAUSE_MARKER"]), os.environ.get("PAUSE_GO")
    want = json.loads(os.environ.get("PAUSE_KWARGS", "{}"))
    nth = int(os.environ.get("PAUSE_CALL", "1"))
    calls = []

    def paused(*args, **kwargs):
        if len(calls) < nth and all(kwargs.get(k, None) == v for k, v in want.items()):
            calls.append(True)
            if len(calls) < nth:
                return original(*args, **kwargs)
            marker.write_text(str(os.getpid()))
            while go is None or not Path(go).exists():
                time.sleep(0.02)  # a signal's handler raises here
        return original(*args, **kwargs)

    setattr(owner, name, paused)


if __name__ == "__main__":  # a spawned worker process imports this file again: nothing to do there
    pause(sys.argv[1])
    prog, argv = sys.argv[2], sys.argv[3:]
    main = importlib.import_module({"rotor-host": "rotor_host.cli", "bearing-fmu": "bearing_fmu.cli"}[prog]).main
    sys.exit(main(argv))
