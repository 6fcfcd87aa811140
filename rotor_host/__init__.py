"""The system around the bearings: a flexible rotor integrated with Newmark + Newton,
co-simulating one bearing per journal (in-process or as FMUs through fmpy).

=====================  ==============================================================
module                 what it holds
=====================  ==============================================================
fe, rotor              element matrices; the rotor file and its assembly, loads, modes
forces                 the NodalForce protocol the integrator sees, Newton tangent words
newmark,               Newmark / HHT-alpha with Newton and step cutting; its kernels
_newmark_kernels
equilibrium            static equilibrium of the rotor on nonlinear bearings
bearings, cosim        the bearings as one nodal force: in-process, or FMUs (fmpy master)
speed                  constant speed or a run-up / coast-down profile
scene                  the scene file, load_scene
run                    run_scene: bearings, equilibrium, integration, result files
training               scene-trained Taylor surrogates (``rotor-host fit``)
compare, report        error against run time; error measures, tables, plots
limit_cycle, dt_study  the whirl's envelope; the time-step study
stability, campbell    damped modes over speed and the threshold; the Campbell figures
waterfall              response spectra of a run-up against speed
sweep                  a scene at many speeds or unbalances on Dask; bifurcation diagram
file_formats           the tables of docs/file-formats.md from the key lists
cli                    the ``rotor-host`` command
=====================  ==============================================================

Layout and data flow: docs/architecture.md.
"""

__version__ = "0.1.0"
