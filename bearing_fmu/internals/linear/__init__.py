"""The linear internal: 8 Lund coefficients about an equilibrium (order-1 model).

==========  ====================================================================
module      what it holds
==========  ====================================================================
linear      ``Linear``: the force F0 - K (q - q0) - C v, made from a load, a map
            or given coefficients
kernels     the same as one compiled-force kernel
==========  ====================================================================

``Linear`` is importable from here (``bearing_fmu.internals.linear``, its old path).
"""

from .linear import Linear

__all__ = ["Linear"]
