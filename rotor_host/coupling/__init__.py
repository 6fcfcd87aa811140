"""The bearings as one nodal force for the integrator.

=========  ====================================================================
module     what it holds
=========  ====================================================================
bearings   ``BearingSet``; ``DirectBearings`` (internals called in-process)
cosim      ``FMUBearings``: the fmpy master, one FMU instance per bearing,
           conformant iteration
init_statics  its static evaluations in Initialization Mode, for FMUs with states of
           their own over a step (tilting pads)
=========  ====================================================================
"""
