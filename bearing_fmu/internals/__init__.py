"""The bearing internals: one protocol, one registry (options and capabilities), one module
per internal. Everything a caller needs is importable from here (``bearing_fmu.internals``).

==============  ================================================================
module          what it holds
==============  ================================================================
registry        the ``Internal`` protocol, state checks, ``Option``, ``Context``,
                ``Capabilities``, ``InternalSpec`` and ``REGISTRY`` with the built-in
                internals, and the "how to add an internal" checklist
cases           the built-in internals' contract cases (``ContractCase``): what the
                contract tests build each with
linear          the linear internal: 8 Lund coefficients (order-1 model)
taylor, guard   the Taylor-surrogate internal and the fitted-domain guard around it
forcemap,       the force map: the Reynolds force as a 2-D table per L/D, its file,
map_kernels     and its compiled spline, force and Jacobian
scaled          ``ViscosityScaled``: any internal at an effective viscosity (force and
                Jacobian times mu_eff / mu: exact, F ~ mu; docs/thermal.md)
warmup          compiled kernels loaded from numba's disk cache before a run's clocks
                start (an internal's, by its registry entry's ``kernels``; the host's)
==============  ================================================================

The Reynolds solver, the truth, is an internal too; it lives with the physics
(``bearing_fmu.physics.reynolds``). Only the chosen internal's module is imported.
"""

from .registry import (DEFAULT_DOMAIN_LIMIT, DEFAULT_LOAD_Z, DEFAULT_OMEGA_LIN, DOMAIN_ACTIONS, REGISTRY,
                       STATE_NAMES, BearingStateError, Capabilities, Context, DifferentiableInternal, Internal,
                       InternalSpec, Option, all_options, check_finite, check_state, create, file_format, get,
                       names, having, option_for_file, register, unregister, wall_error)

__all__ = ["DEFAULT_DOMAIN_LIMIT", "DEFAULT_LOAD_Z", "DEFAULT_OMEGA_LIN", "DOMAIN_ACTIONS", "REGISTRY",
           "STATE_NAMES", "BearingStateError", "Capabilities", "Context", "DifferentiableInternal", "Internal", "InternalSpec",
           "Option", "all_options", "check_finite", "check_state", "create", "file_format", "get", "names",
           "having", "option_for_file", "register", "unregister",
           "wall_error"]
