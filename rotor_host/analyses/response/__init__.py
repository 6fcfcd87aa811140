"""The rotor's forced response and the checks of a design review (API 617 / API RP 684), on the
rotor linearised about its equilibrium (``analyses.linear``). docs/response.md.

====================  =========================================================
module                what it holds
====================  =========================================================
synchronous           the steady 1x response to unbalances: the solve, amplitude and phase
peaks                 peaks, half-power amplification factor, API separation margins
unbalance             ``rotor-host response``: the sweep over speed, the json, the command
report, figures       its markdown report; its Bode and polar plots
ucs                   ``rotor-host ucs``: undamped critical speed map, bearings overlaid
level1                ``rotor-host level1``: API 617 Level I stability (Q_A, Q_0, verdict)
api_report            ``rotor-host api-report``: all of them and the Campbell diagram in one file
runup                 ``rotor-host linear-vs-runup``: the linear response against a run-up
====================  =========================================================
"""
