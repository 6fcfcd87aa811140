"""The Dask cluster a long job runs on (``rotor-host sweep``, ``bearing-fmu map --scheduler``): an
existing scheduler, checked before use, or a local cluster of worker processes, closed at once on
an interrupt.

``scheduler_address`` is the command line's type of a scheduler's address (``--scheduler``).
``check_scheduler`` refuses in one line an address where nothing answers, or where something
answers that is not a Dask scheduler (dask.distributed bounds the connection but not its
handshake, so a silent socket or an HTTP server would hold the sweep forever).
``dask_client`` gives the Client; an interrupt in the runs or in closing the client or the
cluster stops the local workers and closes the cluster in a moment (left to itself, its atexit
close waits 10 s).
``running_scheduler`` finds a cluster left running for later commands: Dask's own
``DASK_SCHEDULER_ADDRESS``, or the scheduler file in a known place (``scheduler_file()``: what
``dask scheduler --scheduler-file`` writes), if a scheduler answers there.
"""

from __future__ import annotations

import os
import re
import signal
import threading
import time
from contextlib import contextmanager
from pathlib import Path

from ..io.cliargs import typed

HANDSHAKE_TIMEOUT_S = 5.0  # a scheduler answers the Dask handshake in milliseconds

_ADDRESS = re.compile(r"^(?:[a-z]+://)?[^\s/:]+:\d{1,5}$|^[a-z]+://\S+$")


SCHEDULER_FILE_ENV = "ROTOR_HOST_SCHEDULER_FILE"


def _address(text: str) -> str:
    if Path(text).expanduser().is_file():
        return str(Path(text).expanduser())
    if not _ADDRESS.match(text.strip()):
        raise ValueError(text)
    return text.strip()


# An argparse type: a Dask scheduler address, ``tcp://HOST:PORT`` (or ``HOST:PORT``), or the
# scheduler file ``dask scheduler --scheduler-file`` wrote; that a scheduler answers there is
# checked when the sweep connects.
scheduler_address = typed("a Dask scheduler address such as tcp://10.0.0.5:8786, or a scheduler file", str, _address)


def scheduler_file() -> Path:
    """The known place of a cluster kept running for later commands: ``$ROTOR_HOST_SCHEDULER_FILE``,
    else ``dask-scheduler.json`` in the user's cache folder beside the FMU cache (start one with
    ``dask scheduler --scheduler-file <it>`` and ``dask worker --scheduler-file <it> --nthreads 1``)."""
    from ..io.cache import build_cache

    env = os.environ.get(SCHEDULER_FILE_ENV)
    return Path(env).expanduser() if env else build_cache().parent / "dask-scheduler.json"


def scheduler_in_file(path, option: str = "--scheduler") -> str:
    """The address a Dask scheduler file holds (its key ``address``); a file that is not one is
    refused in one line naming it."""
    import json

    try:
        address = json.loads(Path(path).read_text()).get("address")
    except (OSError, ValueError, AttributeError) as exc:
        raise ValueError(f"{option} {path}: not a Dask scheduler file (JSON with its \"address\", as "
                         f"`dask scheduler --scheduler-file` writes it): {exc}") from None
    if not isinstance(address, str) or not _ADDRESS.match(address):
        raise ValueError(f"{option} {path}: not a Dask scheduler file: no \"address\" such as tcp://HOST:PORT "
                         f"in it (found {address!r})")
    return address


def scheduler_named(text: str) -> str:
    """``--scheduler``'s address: itself, or the address in the scheduler file it names."""
    return scheduler_in_file(text) if Path(text).is_file() else text


def running_scheduler(log=print) -> str | None:
    """The address of a cluster left running for later commands, if a Dask scheduler answers
    there (in about a second): Dask's ``DASK_SCHEDULER_ADDRESS``, else the scheduler file at
    ``scheduler_file()``. A stale one (nothing answers) is said in one line and passed over."""
    where, address = "DASK_SCHEDULER_ADDRESS", os.environ.get("DASK_SCHEDULER_ADDRESS")
    if not address:
        path = scheduler_file()
        if not path.is_file():
            return None
        where = f"the scheduler file {path}"
        try:
            address = scheduler_in_file(path, "scheduler file")
        except ValueError as exc:
            log(f"({exc}; running here)")
            return None
    try:
        check_scheduler(address, connect_timeout_s=0.5, handshake_timeout_s=2.0)
    except ValueError:
        log(f"({where} names {address}, where no Dask scheduler answers now: running on this machine)")
        return None
    return address


def check_scheduler(address: str, connect_timeout_s: float = 15.0, handshake_timeout_s: float = HANDSHAKE_TIMEOUT_S):
    """Refuse in one line an address where nothing accepts a connection within
    ``connect_timeout_s`` [s], or where something does but does not answer Dask's handshake
    within ``handshake_timeout_s`` (an HTTP server, a silent socket): dask.distributed bounds
    only the connection and would wait for that answer forever."""
    import asyncio
    import socket

    from distributed.comm import connect, parse_address, parse_host_port
    from distributed.security import Security

    scheme, loc = parse_address(address)
    if scheme in ("tcp", "tls"):  # first the connection alone, retried as Dask does (a scheduler starting up)
        host, port = parse_host_port(loc)
        deadline = time.monotonic() + connect_timeout_s
        while True:
            try:
                socket.create_connection((host, port), timeout=max(0.1, deadline - time.monotonic())).close()
                break
            except OSError as exc:
                if time.monotonic() >= deadline:
                    raise ValueError(f"--scheduler {address}: no Dask scheduler answered there ({exc.strerror or exc}; "
                                     f"waited {connect_timeout_s:g} s)") from None
                time.sleep(0.2)
        limit = handshake_timeout_s
    else:
        limit = connect_timeout_s + handshake_timeout_s

    async def hello():  # the scheduler's handshake, with the security a Client would use
        comm = await asyncio.wait_for(connect(address, timeout=limit, **Security().get_connection_args("client")),
                                      limit)
        await comm.close()

    try:
        asyncio.run(hello())
    except Exception as exc:  # noqa: BLE001 - TimeoutError; garbage read as a frame length: MemoryError, ...
        http = _http_answer(address) if scheme == "tcp" else None
        if http:  # a web server (the dashboard's port, any other): its first line says what it is
            raise ValueError(f"--scheduler {address}: an HTTP server answers there ({http}), not a Dask scheduler; "
                             "give the scheduler's own port (tcp://HOST:8786 by default), not its dashboard's "
                             "(8787) or another web server's") from None
        why = ("no answer" if isinstance(exc, TimeoutError)
               else f"{type(exc).__name__}: {' '.join(str(exc).split())[:120]}")
        raise ValueError(f"--scheduler {address}: something accepts connections there but did not answer as a Dask "
                         f"scheduler within {limit:g} s ({why}); give the scheduler's own port (8786 by default), "
                         "not its dashboard's") from None


def _http_answer(address: str, timeout_s: float = 0.3) -> str | None:
    """The status line of an HTTP server at ``address`` (asked ``HEAD /`` on a fresh connection,
    once the Dask handshake has failed there), else None."""
    import socket

    from distributed.comm import parse_address, parse_host_port

    try:
        with socket.create_connection(parse_host_port(parse_address(address)[1]), timeout=timeout_s) as s:
            s.sendall(b"HEAD / HTTP/1.0\r\n\r\n")
            first = s.recv(200)
    except OSError:
        return None
    line = first.split(b"\r\n", 1)[0].decode("latin-1")
    return line if line.startswith("HTTP/") else None


@contextmanager
def dask_client(scheduler: str | None, workers: int | None, connect_timeout_s: float = 15.0,
                handshake_timeout_s: float | None = None):
    """A dask.distributed Client: on the scheduler at ``scheduler`` (refused in one line if
    none answers within ``connect_timeout_s`` [s], something else answers there
    (``check_scheduler``) or it has no worker within 30 s), or on a LocalCluster of ``workers``
    processes (default: the cores) with one thread each, closed on leaving."""
    import logging

    import dask
    from dask.distributed import Client, LocalCluster

    if scheduler:
        check_scheduler(scheduler, connect_timeout_s,
                        HANDSHAKE_TIMEOUT_S if handshake_timeout_s is None else handshake_timeout_s)
        try:
            client = Client(scheduler, timeout=connect_timeout_s)
        except (OSError, TimeoutError) as exc:
            raise ValueError(f"--scheduler {scheduler}: no Dask scheduler answered there "
                             f"({type(exc).__name__}: {' '.join(str(exc).split())[:200]})") from None
        try:
            client.wait_for_workers(1, timeout=30)
        except TimeoutError:
            client.close()
            raise ValueError(f"--scheduler {scheduler}: the cluster has no worker (waited 30 s)") from None
        with client:
            yield client
        return
    n = workers or os.cpu_count() or 1
    # The workers ignore SIGINT (an ignored signal stays ignored in a spawned process): Ctrl-C
    # reaches every process of the terminal's group, and only this one must act on it (cancel,
    # write the summary, close the workers), not print a traceback from each worker.
    # (Python sets signal handlers in the main thread only; from another thread they keep SIGINT.)
    main = threading.current_thread() is threading.main_thread()
    old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        # no statistical profiler in the workers: it samples the run's thread every 10 ms for a
        # dashboard this cluster does not have (3-4 % of a worker's CPU, measured per run)
        with dask.config.set({"distributed.worker.profile.enabled": False}):
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                   silence_logs=logging.CRITICAL)
    finally:
        if main:
            signal.signal(signal.SIGINT, old)
    try:
        with Client(cluster) as client:
            yield client
    except KeyboardInterrupt:  # in the runs, or in closing the client
        _close(cluster, interrupted=True)
        raise
    except BaseException:
        _close(cluster)
        raise
    _close(cluster, idle=True)


def _close(cluster, interrupted: bool = False, idle: bool = False) -> None:
    """Close the local cluster. On an interrupt, then or while closing, stop its workers first
    and give the close 2 s: left to itself, its atexit close waits 10 s for what is gone.
    ``idle``: every task has ended (the caller has its results), so the workers are stopped at
    once too: the close otherwise waits ~1 s for each worker to wind down, after the work."""
    if not interrupted:
        try:
            if idle:
                _stop_workers(cluster)
            cluster.close()
            return
        except KeyboardInterrupt:
            _close(cluster, interrupted=True)
            raise
    _stop_workers(cluster)  # the runs in progress would otherwise hold the close for seconds
    try:
        cluster.close(timeout=2)
    except Exception:  # noqa: BLE001 - a close that times out must not replace the interrupt
        pass


def _stop_workers(cluster) -> None:
    """Terminate the local cluster's worker processes now (their nannies told not to restart
    them): a run in progress holds its worker until it ends, and Ctrl-C must not wait for that.
    A stopped run leaves its last checkpoint (status running), if it had written one."""
    for nanny in list(cluster.workers.values()):
        pid = getattr(nanny, "pid", None)
        if not pid:
            continue
        nanny.close_gracefully()
        try:
            os.kill(pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
