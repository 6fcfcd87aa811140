"""The system around the bearings: a flexible rotor integrated with Newmark + Newton,
co-simulating one bearing per journal (in-process or as FMUs through fmpy).

============  =================================================================
folder        what it holds
============  =================================================================
model/        element matrices, the rotor file and its assembly, speed profiles
integrate/    Newmark / HHT-alpha with Newton, nodal forces, static equilibrium
coupling/     the bearings as one nodal force: in-process, or FMUs (fmpy master)
scenes/       the scene file, its overrides, run_scene, the file-format reference
analyses/     compare and the main job, report, stability and Campbell, waterfall,
              sweep, limit cycle, dt study, scene-trained fits, plotting
cli           the ``rotor-host`` command: every option of every subcommand
============  =================================================================

The modules ``run`` and ``scene`` keep the old import paths (``rotor_host.run.run_scene``,
``rotor_host.scene.load_scene``). Layout and data flow: docs/architecture.md.
"""

__version__ = "0.1.0"
