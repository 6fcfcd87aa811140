"""One hydrodynamic journal bearing, as a library and as an FMU.

============  =================================================================
folder        what it holds
============  =================================================================
physics/      BearingParams, the finite-volume Reynolds solver (the truth) and its
              kernels, the closed-form short bearing, statics (equilibrium, Lund K, C)
internals/    the Internal protocol and the one registry of internals (options,
              capabilities, contract cases); one folder per family: linear/,
              taylor/ (+ guard), map/ (the force map, grooved maps, map files)
surrogates/   the Taylor surrogate file, its domain, basis and compiled kernels
fitting/      fitting a surrogate (never bundled into the FMU)
fmu/          the pythonfmu slave, the FMU build and its metadata, the native C FMU
io/           file keys, command-line values, exits, result files (both CLIs)
cli           the ``bearing-fmu`` command: every option of its subcommands
============  =================================================================

Import what you need from its modules: this package file imports nothing heavy, so an FMU
whose internal is the surrogate never loads or compiles the Reynolds solver. This package
never imports the host (the package behind ``rotor-host``). The modules ``params``,
``reynolds``, ``statics``, ``forcemap``, ``linear``, ``taylor`` and ``guard`` keep the old
import paths. Layout and data flow: docs/architecture.md; from Python: docs/api.md.
"""

__version__ = "0.1.0"
