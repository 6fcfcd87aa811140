"""What an engineer runs on scenes and rotors.

====================  =========================================================
module                what it holds
====================  =========================================================
compare, report       error against run time; error measures, plots
tables                markdown tables of the reports
stability, campbell   damped modes over speed and the threshold (at mu_eff with a supply
                      temperature); the figures
stability_report      the stability sweep's markdown table and json
modal                 which modes a report ranks, critical speeds (AF >= 2.5), peaks at them
waterfall, crossings  response spectra of a run-up against speed; the critical speeds it crosses
sweep                 a scene at many speeds or unbalances on Dask
dask_cluster          the sweep's Dask client: a checked scheduler or a local cluster
limit_cycle           the whirl's envelope
dt_study              the time-step convergence study
training              scene-trained Taylor surrogates (``rotor-host fit``)
====================  =========================================================
"""
