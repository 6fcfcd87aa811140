"""What an engineer runs on scenes and rotors.

====================  =========================================================
module                what it holds
====================  =========================================================
compare, report       error against run time; error measures, tables, plots
stability, campbell   damped modes over speed and the threshold; the figures
waterfall             response spectra of a run-up against speed
sweep                 a scene at many speeds or unbalances on Dask
limit_cycle           the whirl's envelope
dt_study              the time-step convergence study
training              scene-trained Taylor surrogates (``rotor-host fit``)
====================  =========================================================
"""
