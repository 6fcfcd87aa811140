"""The film solved: the finite-volume Reynolds solver (the truth) and what a solved film gives.

=================  ============================================================
module             what it holds
=================  ============================================================
reynolds,          the finite-volume Reynolds solver (also the ``reynolds`` internal),
reynolds_kernels   adjoint Jacobian, warm-started active set; its compiled kernels
geometry_kernels   the same for a bore that is not the full circle (own kernels: the full
                   bore's stay bit for bit)
lands              a circumferential groove's two lands: the axial stencil with the
                   groove's Dirichlet row
film               friction (torque, power, coefficient) and flow (inflow, side flow) of the
                   film: ``FilmReport``, from a converged field or, for the full bore, in
                   closed form from the force of any internal
shortbearing       the closed-form short (Ocvirk) bearing: forces, K, C
=================  ============================================================
"""
