"""The physics of one bearing: its parameters, the finite-volume Reynolds solver (the truth),
the closed-form short bearing, statics.

=================  ============================================================
module             what it holds
=================  ============================================================
params             ``BearingParams`` (D, L, CR, mu, geometry, oil; SI; validated), the bearing
                   file's keys, the paper bearing
oil                ``Oil``: the viscosity law (Walther / ASTM D341, Vogel, ISO VG presets),
                   density, heat capacity; the [oil] keys
geometry           ``Geometry``: the bore (grooves, partial arc, lobes with preload), the
                   [geometry] keys, the lobed film, the solver's circumferential grid
reynolds,          the finite-volume Reynolds solver (also the ``reynolds`` internal),
reynolds_kernels   adjoint Jacobian, warm-started active set; its compiled kernels
geometry_kernels   the same for a bore that is not the full circle (own kernel: the full
                   bore's stays bit for bit)
film               friction (torque, power, coefficient) and flow (inflow, side flow) of the
                   film: ``FilmReport``, from a converged field or, for the full bore, in
                   closed form from the force of any internal
thermal            the effective temperature: heat balance of friction power and oil flow,
                   T_eff = T_supply + k dT, mu_eff = mu(T_eff) by bracketing (quasi-static)
operating          one operating point as one record (equilibrium, K, C, friction, flows,
                   T_eff, mu_eff): what ``bearing-fmu demo`` prints and writes with --json
shortbearing       the closed-form short (Ocvirk) bearing: forces, K, C
statics            ``equilibrium``, ``linearize`` (Lund K, C), ``film_jacobian`` of any
                   internal
=================  ============================================================
"""
