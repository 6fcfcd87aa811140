"""One hydrodynamic journal bearing, as a library and as an FMU.

Import what you need from its modules (``bearing_fmu.reynolds``, ``bearing_fmu.taylor``,
...): this package file imports nothing heavy, so an FMU whose internal is the surrogate
never loads or compiles the Reynolds solver.
"""

__version__ = "0.1.0"
