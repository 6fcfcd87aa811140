"""The bearing internals: one protocol, one registry (options and capabilities), one folder per
family of internals. Everything a caller needs is importable from here (``bearing_fmu.internals``).

==============  ================================================================
module          what it holds
==============  ================================================================
registry        what callers import: ``REGISTRY``, ``get``, ``having``, ``register``...;
                the table of internals and the "how to add an internal" checklist
base            the ``Internal`` protocol, ``BearingStateError`` and the state checks,
                ``Option``, ``Context``, ``Capabilities``, ``InternalSpec`` and the
                register/get/having functions (no internal in it)
catalogue       the built-in internals' ``InternalSpec`` entries (reynolds, linear,
                taylor, map), registered in that order
cases           the built-in internals' contract cases (``ContractCase``): what the
                contract tests build each with
compiled        ``CompiledForce``: an internal's force and Jacobian as a compiled kernel
                of one signature, for a host's compiled loop
scaled          ``ViscosityScaled``: any internal at an effective viscosity (force and
                Jacobian times mu_eff / mu: exact, F ~ mu; docs/thermal.md)
warmup          compiled kernels loaded from numba's disk cache before a run's clocks
                start (an internal's, by its registry entry's ``kernels``; the host's)
forcemap,       the old import paths of the force map, the grooved map, the map file
groovemap,      and the guard (one-line modules re-exporting their new homes in
mapfile, guard  ``map/`` and ``taylor/``)
==============  ================================================================

==============  ================================================================
folder          the family of internals it holds
==============  ================================================================
linear/         the linear internal: 8 Lund coefficients (order-1 model), its kernel
taylor/         the Taylor-surrogate internal, the fitted-domain guard around it, the
                nearest-training-state search, the guarded kernel
map/            the force map: its table (full bore), its file, its internal, the
                grooved bore's 3-D map, either file, the compiled splines
==============  ================================================================

A new family (a tilting-pad bearing) is a new folder beside these, its spec one entry in
``catalogue`` (checklist: ``registry``). The Reynolds solver, the truth, is an internal too; it
lives with the physics (``bearing_fmu.physics.solver.reynolds``): the solver is the internal, and the
maps, the fitting and the statics use it as physics. Only the chosen internal's module is
imported.
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
