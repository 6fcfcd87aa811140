"""Sweeps: one scene run at many shaft speeds (or unbalance masses), in parallel.

``rotor-host sweep SCENE --speeds-hz 10:60:2.5`` runs the scene once per speed (or, with
``--unbalance-g 0 4 8.5 17``, once per mass of the scene's first ``[[unbalance]]``) where the
work is best run (``local.choose``): on a Dask cluster already running (``--scheduler``, or one
left running for later commands), in the command's own process (one worker), else in a pool of
worker processes forked once the command has loaded the code and kernels (a LocalCluster,
``--execution cluster``, costs 2-4 s to start and saves nothing on one machine). Each run is
``run.run_scene`` in a worker; it writes its own ``<scene>_<internal>_<speed>hz.npz/.json`` into
the output folder and returns one summary row (small, so nothing large crosses the network).
The client collects the rows as the runs finish (progress bar), prints its fixed costs (imports,
kernels, FMU build, pool or cluster start, the workers' warm-up) apart from the work, and writes

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
on-disk cache beside the package, or the FMU code cache), before its first run: a Dask cluster's
workers side by side, a forked pool's from the command's own process. Workers of a remote cluster need this package installed and
the scene's files and the output folder at the same paths (a shared file system).

================  =============================================================
module            what it holds
================  =============================================================
plan              the values swept, one ``Point`` per run, the checks before any run
execute           each worker's row, the runs as Dask tasks, collecting the rows
local             where the runs run (``choose``), in this process or a pool of processes
summary           the summary table and the bifurcation diagram
command           ``rotor-host sweep``: plan, execute, summarise (and on an interrupt)
================  =============================================================
"""

from bearing_fmu.parallel.cluster import check_scheduler, dask_client
from .command import command
from .execute import error_fields, finished_on_disk, run_point, settled_metrics, sweep, warm_worker
from .local import Execution, choose, run_inline, run_pool
from .plan import MAX_RUNS, Point, check_fixed_speed, point_scene, points, run_base, swept_values
from .summary import plot_bifurcation, summary_diagram, sweep_title, write_summary

__all__ = ["MAX_RUNS", "Point", "swept_values", "run_base", "points", "point_scene", "settled_metrics",
           "warm_worker", "run_point", "finished_on_disk", "error_fields", "check_fixed_speed", "check_scheduler",
           "dask_client", "sweep", "Execution", "choose", "run_inline", "run_pool", "sweep_title", "write_summary", "summary_diagram", "plot_bifurcation", "command"]
