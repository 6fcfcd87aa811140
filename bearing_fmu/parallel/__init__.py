"""Work spread over processes or a Dask cluster: the bearing side's long builds and the host's sweeps.

=========  ====================================================================
module     what it holds
=========  ====================================================================
cluster    the Dask client: a checked scheduler (``--scheduler``, a cluster left running) or a local
           cluster, closed at once on an interrupt
rows       a table's rows solved as tasks (serially, on a process pool or on
           Dask), streamed into a partial file and resumed from it
=========  ====================================================================
"""
