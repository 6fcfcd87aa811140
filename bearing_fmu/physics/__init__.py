"""The physics of one bearing: its parameters, its bore, the film solved, the oil and its heat
balance, statics.

=================  ============================================================
module / folder    what it holds
=================  ============================================================
params             ``BearingParams`` (D, L, CR, mu, geometry, oil; SI; validated), the bearing
                   file's keys, the paper bearing
bore/              the bore: ``Geometry`` (grooves, arcs, lobes, a circumferential groove),
                   the solver's grid of it, the tilting pads' frame, the feed's place
solver/            the finite-volume Reynolds solver (the truth) and its kernels, the film's
                   friction and flows (``FilmReport``), the closed-form short bearing
oil                ``Oil``: the viscosity law (Walther / ASTM D341, Vogel, ISO VG presets),
                   density, heat capacity; the [oil] keys
thermal            the effective temperature: heat balance of friction power and oil flow,
                   T_eff = T_supply + k dT, mu_eff = mu(T_eff) by bracketing (quasi-static)
operating          one operating point as one record (equilibrium, K, C, friction, flows,
                   T_eff, mu_eff): what ``bearing-fmu demo`` prints and writes with --json
statics            ``equilibrium``, ``linearize`` (Lund K, C), ``film_jacobian`` of any
                   internal
=================  ============================================================
"""
