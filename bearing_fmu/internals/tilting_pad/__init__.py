"""The tilting-pad journal bearing's internal (issue: pads free to rotate about their pivots,
and with flexible pivots to move along their pivot lines).

==============  ==========================================================================
module          what it holds
==============  ==========================================================================
assembly        the pads around one journal: each pad the partial-arc Reynolds solver in its own
                frame at its tilt (and radial displacement, flexible pivots), moments, the massless
                pads' equilibrium, the pads' equations of motion
linear          the pads linearised: the full (2 + N) or (2 + 2N) coefficients, Lund's reduction,
                the quasi-static Jacobian
tilting_pad     the ``tilting_pad`` internal (registered in ``internals.catalogue``)
stepping        the pads' states carried through a transient (the host's step hooks)
operating       one tilting-pad bearing at one operating point (what ``bearing-fmu demo`` prints)
==============  ==========================================================================
"""
