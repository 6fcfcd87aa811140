"""A table's rows as tasks: solved in this process, on a local process pool or on a Dask
cluster, each row streamed into a partial file as it comes, so that a build that is interrupted
(Ctrl-C, SIGTERM, a worker that dies) resumes from the rows already solved.

A task is ``task(x)`` for one row's input ``x``, returning a tuple of arrays (the row's values);
``task`` is picklable and carries what every row shares (a map's bearing, grid and axes). On
Dask it is scattered once to every worker (``broadcast``) and each row's task names it, so the
bearing and grid cross the network once per worker, not once per row.

The partial file (JSON lines): a header ``{"format": FORMAT, "key": KEY, "rows": N}``, then one
line per solved row ``{"row": i, "values": [[...], ...]}`` (an array or null each); floats as Python writes them (the
shortest repr), so a row read back is the row solved, to the bit. A file of another key (another
bearing, grid, resolution or code) is not resumed: the build starts afresh; a last line cut short
by a kill is ignored.
"""

from __future__ import annotations

import json
import sys
import os
import signal
import time
from pathlib import Path

import numpy as np

FORMAT = "bearing-fmu-partial-table"


class Partial:
    """The partial file of a build at ``path`` for the rows of ``key`` (``n_rows`` of them)."""

    def __init__(self, path, key: str, n_rows: int):
        self.path, self.key, self.n_rows = Path(path), key, n_rows
        self._file = None

    def load(self) -> dict[int, list[np.ndarray]]:
        """The rows the file holds for this key (row -> values), {} when there is none or it is
        another build's."""
        try:
            lines = self.path.read_text().splitlines()
        except (FileNotFoundError, UnicodeDecodeError):
            return {}
        try:
            head = json.loads(lines[0])
        except (IndexError, json.JSONDecodeError):
            return {}
        if not isinstance(head, dict) or head.get("format") != FORMAT or head.get("key") != self.key \
                or head.get("rows") != self.n_rows:
            return {}
        rows = {}
        for line in lines[1:]:
            try:
                rec = json.loads(line)
                i = rec["row"]
                if isinstance(i, int) and 0 <= i < self.n_rows:
                    rows[i] = [None if v is None else np.asarray(v, float) for v in rec["values"]]
            except (json.JSONDecodeError, KeyError, TypeError, ValueError):
                continue  # a line cut short by a kill
        return rows

    def start(self, resumed: bool) -> None:
        """Open for appending; a fresh build (``resumed`` False) writes a new header first."""
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            if resumed:
                self._file = open(self.path, "a", encoding="utf-8")
                return
            self._file = open(self.path, "w", encoding="utf-8")
            self._file.write(json.dumps({"format": FORMAT, "key": self.key, "rows": self.n_rows}) + "\n")
            self._file.flush()
        except OSError as exc:
            self._refused(exc)

    def add(self, i: int, values) -> None:
        """Append row ``i`` (its arrays, or None), flushed: a kill after this keeps it."""
        if self._file is None:  # refused (a full disk): the build goes on without it
            return
        vals = [None if v is None else np.asarray(v, float).tolist() for v in values]
        try:
            self._file.write(json.dumps({"row": i, "values": vals}, allow_nan=False) + "\n")
            self._file.flush()
        except OSError as exc:
            self._refused(exc)

    def _refused(self, exc: OSError) -> None:
        """A partial file the folder refuses (full, read-only): one warning, and the build goes on
        (its result is written, or rescued, at the end); only an interruption would lose its rows."""
        print(f"warning: the partial file {self.path} cannot be written ({exc.strerror or exc}): the build goes on, "
              "but an interruption now loses its rows", file=sys.stderr, flush=True)
        if self._file is not None:
            try:
                self._file.close()
            except OSError:
                pass
        self._file = None
        self.path.unlink(missing_ok=True)

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def remove(self) -> None:
        self.close()
        self.path.unlink(missing_ok=True)


def worker_signals() -> None:
    """A pool worker: Ctrl-C (sent to the whole group) is the parent's to act on; the parent's
    terminate (SIGTERM) ends the worker at once, without a traceback."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def call(task, x):
    """One row on a Dask worker: ``task`` is the scattered shared task (resolved there once)."""
    return task(x)


def solve_rows(task, inputs, *, done: dict | None = None, partial: Partial | None = None, workers: int = 1,
               client=None, progress=None) -> list:
    """The values of ``task(x)`` for every x of ``inputs``, in order. ``done``: rows already solved
    (row -> values, e.g. ``partial.load()``), not solved again. Each row solved is appended to
    ``partial`` (if given) as it comes, then ``progress(n_done)`` is called. On a Dask ``client``
    when given, else on ``workers`` local processes (1: here). An interrupt (or a worker that
    dies) ends the build with what came so far kept in ``partial``: the exception carries
    ``map_rows_done`` (rows solved, those resumed included)."""
    inputs = list(inputs)
    rows = dict(done or {})
    todo = [i for i in range(len(inputs)) if i not in rows]

    def keep(i, values):
        if i in rows:
            return
        rows[i] = list(values)
        if partial is not None:
            partial.add(i, rows[i])
        if progress is not None:
            progress(len(rows))

    try:
        if client is not None:
            _on_dask(client, task, inputs, todo, keep)
        elif workers > 1 and len(todo) > 1:
            _on_pool(workers, task, inputs, todo, keep)
        else:
            for i in todo:
                keep(i, task(inputs[i]))
    except BaseException as exc:
        exc.map_rows_done = len(rows)
        raise
    finally:
        if partial is not None:
            partial.close()
    return [rows[i] for i in range(len(inputs))]


def _on_pool(workers: int, task, inputs, todo, keep) -> None:
    """Rows on a local process pool; a worker that dies ends the build (RuntimeError) with the
    rows that came kept; an interrupt terminates the workers at once."""
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    pool = ProcessPoolExecutor(min(workers, len(todo)), initializer=worker_signals)
    try:
        futures = {pool.submit(task, inputs[i]): i for i in todo}
        for fut in as_completed(futures):
            keep(futures[fut], fut.result())
    except BrokenProcessPool:
        raise RuntimeError("a worker process of the build died (killed, or out of memory)") from None
    finally:
        procs = list(getattr(pool, "_processes", {}).values())  # the stdlib's own: no public terminate before 3.14
        pool.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            if p.is_alive():
                p.terminate()
        for p in procs:
            p.join()


def _on_dask(client, task, inputs, todo, keep) -> None:
    """Rows as Dask tasks, the shared task scattered once to every worker; a row whose workers
    died (dask.distributed retries it on others first) ends the build (RuntimeError)."""
    from dask.distributed import as_completed

    shared = client.scatter(task, broadcast=True, hash=False)
    stamp = f"{os.getpid()}-{time.time_ns()}"
    futures = {client.submit(call, shared, inputs[i], key=f"map-row-{i}-{stamp}", pure=False, priority=-k): i
               for k, i in enumerate(todo)}
    try:
        for fut in as_completed(futures):
            try:
                values = fut.result()
            except Exception as exc:  # noqa: BLE001 - KilledWorker, a task's own error
                raise RuntimeError(f"row {futures[fut]} failed on the cluster ({type(exc).__name__}: "
                                   f"{' '.join(str(exc).split())[:200]})") from None
            keep(futures[fut], values)
    except BaseException:
        for fut, i in futures.items():  # finished but not collected yet: they count
            if fut.status == "finished":
                try:
                    keep(i, fut.result())
                except BaseException:  # noqa: BLE001 - keeping what is there must not hide the interrupt
                    pass
        client.cancel(list(futures))
        raise
