"""The Dask cluster a sweep runs on: an existing scheduler or a local
cluster of worker processes, closed at once on an interrupt.

``dask_client`` gives the Client; an interrupt in the runs or in closing the client or the
cluster stops the local workers and closes the cluster in a moment (left to itself, its atexit
close waits 10 s).
"""

from __future__ import annotations

import os
import signal
import threading
from contextlib import contextmanager


@contextmanager
def dask_client(scheduler: str | None, workers: int | None, connect_timeout_s: float = 15.0):
    """A dask.distributed Client: on the scheduler at ``scheduler`` (refused in one line if
    none answers within ``connect_timeout_s`` [s] or it has no worker within 30 s), or on a
    LocalCluster of ``workers`` processes (default: the cores) with one thread each, closed on
    leaving."""
    import logging

    from dask.distributed import Client, LocalCluster

    if scheduler:
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
    _close(cluster)


def _close(cluster, interrupted: bool = False) -> None:
    """Close the local cluster. On an interrupt, then or while closing, stop its workers first
    and give the close 2 s: left to itself, its atexit close waits 10 s for what is gone."""
    if not interrupted:
        try:
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
