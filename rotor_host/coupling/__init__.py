"""The bearings as one nodal force for the integrator.

=========  ====================================================================
module     what it holds
=========  ====================================================================
bearings   ``BearingSet``; ``DirectBearings`` (internals called in-process)
cosim      ``FMUBearings``: the fmpy master, one FMU instance per bearing,
           conformant iteration
=========  ====================================================================
"""
