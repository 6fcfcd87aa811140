"""Scenes: one simulation case from its file to its result files.

=============  ================================================================
module         what it holds
=============  ================================================================
scene          the scene file's keys, ``Scene``, ``load_scene``
run            ``run_scene``: bearings, static equilibrium, integration, result files,
               checkpoints, interrupts
sanity         physical sanity before any solve: dt against the shaft period, the surface
               speed against the material, an unbalance against the rotor's mass, the
               native FMU against the bearings' bore
thermal        a supply temperature: the films at their effective temperature at the start,
               the internal that follows it, what a run records of it over time
file_formats   the tables of docs/file-formats.md, made from the key lists
=============  ================================================================
"""
