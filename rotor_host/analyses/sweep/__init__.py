"""Sweeps: one scene run at many shaft speeds (or unbalance masses) in parallel on Dask.

``rotor-host sweep SCENE --speeds-hz 10:60:2.5`` runs the scene once per speed (or, with
``--unbalance-g 0 4 8.5 17``, once per mass of the scene's first ``[[unbalance]]``) as tasks
of a ``dask.distributed`` cluster: a ``LocalCluster`` on this machine by default (one worker
process per core, one thread each: the runs hold the GIL), or an existing cluster whose
scheduler ``--scheduler`` names. Each task is ``run.run_scene`` in a worker process; it
writes its own ``<scene>_<internal>_<speed>hz.npz/.json`` into the output folder and returns
one summary row (small, so nothing large crosses the network). The client collects the rows
as the runs finish (progress bar), and writes

* ``sweep_<scene>_<internal>.md/.json``: per run the speed (and unbalance), the status, per
  bearing the largest and smallest eccentricity ratio after the transient, per disk the
  largest and smallest distance from its static position, and the run time;
* ``sweep_<scene>_<internal>.png``: the bifurcation diagram, those values against speed (or
  unbalance) with the samples taken once per shaft revolution (docs/sweep.md: how to read it).

"After the transient" is the part of each run from ``--settle-s`` to its end (default: the
second half). A run that fails (no static equilibrium, a journal at the wall: status
``failed``) or raises in its worker (status ``error``) is a row of the summary with its
reason; the sweep goes on. Ctrl-C / SIGTERM cancel the runs not yet finished, write the
summary of those that did (status ``interrupted``) and exit 130 / 143.

Workers: each worker process imports the code and loads the compiled kernels once (numba's
on-disk cache beside the package, or the FMU code cache: the first run on each worker pays
it, later runs on it do not). Workers of a remote cluster need this package installed and
the scene's files and the output folder at the same paths (a shared file system).

================  =============================================================
module            what it holds
================  =============================================================
plan              the values swept, one ``Point`` per run, the checks before any run
execute           the runs as Dask tasks, each worker's row, collecting the rows
summary           the summary table and the bifurcation diagram
command           ``rotor-host sweep``: plan, execute, summarise (and on an interrupt)
================  =============================================================
"""

from ..dask_cluster import check_scheduler, dask_client
from .command import command
from .execute import error_fields, finished_on_disk, run_point, settled_metrics, sweep, warm_worker
from .plan import MAX_RUNS, Point, check_fixed_speed, point_scene, points, run_base, swept_values
from .summary import plot_bifurcation, summary_diagram, sweep_title, write_summary

__all__ = ["MAX_RUNS", "Point", "swept_values", "run_base", "points", "point_scene", "settled_metrics",
           "warm_worker", "run_point", "finished_on_disk", "error_fields", "check_fixed_speed", "check_scheduler",
           "dask_client", "sweep", "sweep_title", "write_summary", "summary_diagram", "plot_bifurcation", "command"]
