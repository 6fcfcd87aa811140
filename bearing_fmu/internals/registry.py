"""The bearing internals' one registry: what callers import (``from bearing_fmu.internals
import registry``; ``registry.get``, ``registry.having``, ``registry.REGISTRY``...).

An internal computes the film force on the journal from its state. ``REGISTRY`` is the one
table of internals: name -> ``InternalSpec`` (its factory, its options with type, default, unit
and allowed range, its capabilities). The FMU declares one parameter per option, the scene
loader reads one sub-table per internal (``[reynolds]``, ``[taylor]``, ...), and the command
lines take their choices from it. Where things are: the protocol, the state checks and the
spec types in ``internals/base.py``, the built-in specs in ``internals/catalogue.py`` (imported
here, so any import of the registry has them), each internal's code in its family folder.

===========  =========================================================  ====================================
name         factory                                                    what it is
===========  =========================================================  ====================================
reynolds     physics.solver.reynolds:Reynolds.from_options                     finite-volume Reynolds solver (the
                                                                        truth)
linear       internals.linear.linear:Linear.from_options                8 Lund coefficients about an
                                                                        equilibrium
taylor       internals.taylor.guard:DomainGuard.from_options            fitted Taylor surrogate behind its
                                                                        guard
map          internals.map.mapfile:from_options                         the Reynolds force as a 2-D (3-D
                                                                        grooved) table per L/D
tilting_pad  internals.tilting_pad.tilting_pad:TiltingPad.from_options  tilting pads, each a partial arc of
                                                                        the Reynolds solver; massless pads
===========  =========================================================  ====================================

(``tests/test_internals.py`` checks this table against ``REGISTRY``: a name and factory per
registered internal, in registration order.) The Reynolds solver stays in ``physics/``: the
internal is the solver itself, which the maps, the fitting and the statics use as physics.

How to add an internal
----------------------
1. Make a family folder ``bearing_fmu/internals/<family>/`` (e.g. ``tilting_pad/``): an
   ``__init__.py`` whose docstring is its module table, and one module ``<family>/<name>.py``
   with a class that has ``params``, ``force(y, z, vy, vz, omega) -> (Fy, Fz)`` [N] and, if it
   can, ``force_and_jacobian`` (raw derivatives, see ``DifferentiableInternal``). Refuse states
   it cannot evaluate with ``BearingStateError`` (``base``: ``check_finite``, ``check_state``;
   ``overflow_error`` for finite inputs whose result overflows), never return NaN or inf. Its
   compiled kernels, if any, go in ``<family>/kernels.py``; if its force and Jacobian are
   compiled code, also give it ``compiled_force()`` (``internals.compiled``: a numba cfunc of
   one signature and its data; set ``Capabilities.compiled``): the host then runs whole chunks
   of time steps without Python. A variant of an existing family goes in that family's folder.
2. Give the class a ``from_options(params, options, context)`` classmethod: ``options`` is a
   dict of its checked option values (and of the internals it ``uses``), ``context`` the
   ``Context`` (static load, speed, where files are, a warning sink).
3. Add one ``register(InternalSpec(...))`` at the end of ``internals/catalogue.py``: name,
   ``"internals.<family>.<name>:<Class>.from_options"`` (imported only when the internal is
   built, so an unused internal costs nothing), its ``Option``s (an option name is also the
   FMU parameter and the scene key; it may share a name with another internal's only if it is
   the same option), and:
   - ``can``: its ``Capabilities`` (valid at any state or one operating point, fixed speed,
     fitted domain, native, compare variant, truth, where it holds, a compiled kernel): stability, sweep,
     compare, the run report, the FMU builds and their documentation ask these, never the name;
   - ``kernels``: the modules of its compiled (numba, cache=True) kernels
     (``"internals.<family>.kernels"``), loaded before a timed run starts (``internals.warmup``),
     so the first step does not count their loading;
   - ``case``: ``"internals.cases:<name>_case"``, a function (data_dir) -> ``ContractCase``
     (``internals/cases.py``): option values that build a working instance for the paper
     bearing at 22 Hz (any data file it needs written into data_dir), a state (y, z, vy, vz)
     it answers for, and whether it "refuses" or "evaluates" past the wall. Without one the
     defaults and a moving state at eccentricity 0.46 are used.
   Add its row to the table above.
4. Tests: ``tests/test_internals.py`` runs the eight contract checks (``CONTRACT``: force and
   Jacobian against central differences, non-finite and huge inputs, the wall, options,
   capabilities, the FMU equal to the direct call) over every registered internal from its
   case; add the checks against something independent of it (a closed form, a published
   table, a convergence study). A native internal also needs its C model
   (``bearing_fmu/fmu/native``). ``tests/test_layout.py`` checks that an internal added this
   way fits the house (folder and module sizes).

A caller outside this package (a test, a plug-in) may also ``register`` a spec whose factory
is a callable.
"""

from __future__ import annotations

from .base import (REGISTRY, STATE_NAMES, BearingStateError, Capabilities, Context, DifferentiableInternal, Internal,
                   InternalSpec, Option, all_options, check_finite, check_state, create, file_format, film_flow_of,
                   get, having, names, option_for_file, overflow_error, register, unregister, wall_error)
# importing the catalogue registers the built-in internals
from .catalogue import DEFAULT_DOMAIN_LIMIT, DEFAULT_LOAD_Z, DEFAULT_OMEGA_LIN, DOMAIN_ACTIONS

__all__ = ["DEFAULT_DOMAIN_LIMIT", "DEFAULT_LOAD_Z", "DEFAULT_OMEGA_LIN", "DOMAIN_ACTIONS", "REGISTRY", "STATE_NAMES",
           "BearingStateError", "Capabilities", "Context", "DifferentiableInternal", "Internal", "InternalSpec",
           "Option", "all_options", "check_finite", "check_state", "create", "file_format", "film_flow_of", "get",
           "having", "names", "option_for_file", "overflow_error", "register", "unregister", "wall_error"]
