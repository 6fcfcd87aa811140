"""The tilting-pad journal bearing's internal (issue: pads free to rotate about their pivots).

==============  ==========================================================================
module          what it holds
==============  ==========================================================================
assembly        the pads around one journal: each pad the partial-arc Reynolds solver in its own
                frame at its tilt, moments, the massless pads' equilibrium, the pads' equations of
                motion, the full (2 + N) x (2 + N) coefficients and their reduction
tilting_pad     the ``tilting_pad`` internal (registered in ``internals.catalogue``)
stepping        the pads' states carried through a transient (the host's step hooks)
operating       one tilting-pad bearing at one operating point (what ``bearing-fmu demo`` prints)
==============  ==========================================================================
"""
