"""The rotor linearised about its static equilibrium, speed by speed.

====================  =========================================================
module                what it holds
====================  =========================================================
stability, campbell   damped modes over speed and the threshold (at mu_eff with a supply
                      temperature); the figures
stability_report      the stability sweep's markdown table and json
inputs                the rotor file, its loads and speeds checked before any solve
modal                 which modes a report ranks, critical speeds (AF >= 2.5), peaks at them
crossings             the critical speeds a run-up crosses (its waterfall's marks)
====================  =========================================================
"""
