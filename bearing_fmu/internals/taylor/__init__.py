"""The Taylor-surrogate internal: the fitted polynomial of the film force (paper eq. 6) and
the fitted-domain guard around it (docs/taylor.md). The surrogate file, its basis and its
kernels are ``bearing_fmu.surrogates``; fitting one is ``bearing_fmu.fitting``.

==========  ====================================================================
module      what it holds
==========  ====================================================================
taylor      ``Taylor``: evaluates a surrogate with its analytic Jacobian
guard       ``DomainGuard``: the registered internal, Taylor behind its fitted
            domain (warn, fall back to Reynolds, or refuse outside it)
nearest     the nearest training state and the linear-extrapolation radius
kernels     the guarded surrogate as one compiled-force kernel
==========  ====================================================================

``Taylor`` is importable from here (``bearing_fmu.internals.taylor``, its old path).
"""

from .taylor import OMEGA_RTOL, Taylor

__all__ = ["OMEGA_RTOL", "Taylor"]
