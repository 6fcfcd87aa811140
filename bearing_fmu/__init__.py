"""One hydrodynamic journal bearing, as a library and as an FMU.

=====================  ==============================================================
module                 what it holds
=====================  ==============================================================
params                 BearingParams (D, L, CR, mu; SI; validated), the paper bearing
schema                 the keys of every file as typed data (Key, its Kind, check_table,
                       read_toml): each file checked once, one-line errors
cliargs                typed command-line values (argparse types naming the option)
internals              the Internal protocol, state checks, the registry of internals
                       and its "how to add an internal" checklist
reynolds,              finite-volume Reynolds solver (the truth), its compiled kernels
_reynolds_kernels
forcemap, _map_kernels the force map: the Reynolds force as a 2-D table per L/D
linear                 8 Lund coefficients (the order-1 model)
taylor                 the Taylor-surrogate internal
guard                  the fitted-domain guard around it
surrogate, basis,      the surrogate file, the monomial basis, the compiled kernels
_taylor_kernels
shortbearing           closed-form short (Ocvirk) bearing
statics                equilibrium, Lund linearisation, Jacobians of any internal
fitting/               fitting a surrogate: FitRecipe, ridge, sampling, the fit, report,
                       ``bearing-fmu fit`` (never bundled into the FMU)
slave, build,          the pythonfmu slave, the FMU build, the checked patches of
fmu_binary             pythonfmu's binary for honest FMI statuses
native/                the native (C) FMU of the linear, map and Taylor internals
exits, outputs         how commands end (signals, exit codes); result files written safely
fmu_meta, fmu_docs     both FMUs' model-description extras (display units, bounds,
                       enumerations, build record) and documentation/index.html
cli                    the ``bearing-fmu`` command
=====================  ==============================================================

Import what you need from its modules: this package file imports nothing heavy, so an FMU
whose internal is the surrogate never loads or compiles the Reynolds solver. This package
never imports the host (the package behind ``rotor-host``). Layout and data flow: docs/architecture.md.
"""

__version__ = "0.1.0"
