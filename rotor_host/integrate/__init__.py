"""Time integration and statics of the rotor; knows nothing of bearings' internals or FMI.

================  =============================================================
module            what it holds
================  =============================================================
forces            the ``NodalForce`` protocol the integrator sees, Newton tangent words
loads             external forces the compiled loop evaluates itself (``RotatingLoads``)
banded            band storage, banded LU and products (the FE matrices are banded)
newmark,          implicit Newmark / HHT-alpha with Newton and step cutting; its
newmark_kernels   compiled kernels
newmark_step      one step in Python: predictor, Newton iterations, accept or abandon
newmark_loop      the compiled driver: chunks of whole steps in one numba call
newmark_data      its settings, result and error (NewmarkConfig, NewmarkResult,
                  IntegrationError)
newmark_record    the state of one run, its records and the partial result a
                  checkpoint, an interrupt or a failure keeps
equilibrium       the static equilibrium of the rotor on nonlinear bearings
================  =============================================================
"""
