"""Scenes: one simulation case from its file to its result files.

=============  ================================================================
module         what it holds
=============  ================================================================
scene          the scene file's keys, ``Scene``, ``load_scene``
run            ``run_scene``: bearings, static equilibrium, integration, result files,
               checkpoints, interrupts
file_formats   the tables of docs/file-formats.md, made from the key lists
=============  ================================================================
"""
