"""The physics of one bearing: its parameters, the finite-volume Reynolds solver (the truth),
the closed-form short bearing, statics.

=================  ============================================================
module             what it holds
=================  ============================================================
params             ``BearingParams`` (D, L, CR, mu; SI; validated), the bearing file's
                   keys, the paper bearing
reynolds,          the finite-volume Reynolds solver (also the ``reynolds`` internal),
reynolds_kernels   adjoint Jacobian, warm-started active set; its compiled kernels
shortbearing       the closed-form short (Ocvirk) bearing: forces, K, C
statics            ``equilibrium``, ``linearize`` (Lund K, C), ``film_jacobian`` of any
                   internal
=================  ============================================================
"""
