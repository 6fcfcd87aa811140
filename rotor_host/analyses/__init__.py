"""What an engineer runs on scenes and rotors.

====================  =========================================================
module                what it holds
====================  =========================================================
compare, report       error against run time; error measures, plots
tables                markdown tables of the reports
computed_for          what a report, figure or summary names as its inputs (rotor, bore, oil, internal)
linear/               the rotor linearised about its equilibrium: stability (damped modes over
                      speed, the threshold), campbell (its figures), stability_report, modal
                      (critical speeds, which modes a report ranks), crossings
waterfall             response spectra of a run-up against speed
sweep/                a scene at many speeds or unbalances on Dask: plan, execute, summary
limit_cycle           the whirl's envelope
dt_study              the time-step convergence study
training              scene-trained Taylor surrogates (``rotor-host fit``)
====================  =========================================================
"""
