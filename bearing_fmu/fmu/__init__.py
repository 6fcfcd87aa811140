"""The bearing as an FMU: the pythonfmu slave (FMI 2.0 CS), the build, what the model
description says, the binary patches, and the native C FMU (ME + CS).

==========  ===================================================================
module      what it holds
==========  ===================================================================
slave       the pythonfmu slave: the class and its life cycle (pythonfmu's script)
pyslave/    its parts: calling sequence and honest FMI status, variables, the
            internal and the steps (thermal ports), the FMU state
build       writes the ``.fmu`` (the package bundled under a unique name, model
            description, data files checked, the bearing's defaults)
binary      the checked patches of pythonfmu's binary for honest FMI statuses
order       the FMI 2.0 call order (one table for both FMUs) and its error wording
variables   the FMU's variables and enumerations, the one table both FMUs declare
resources   what the slave reads from the FMU's resources/ (bundled files, the
            built-in bearing, the patch notes) and the master's logging flag
meta, docs  both FMUs' model-description extras (display units, bounds,
            enumerations, build record) and their documentation/index.html
native/     the native FMU: C sources of the internals and the FMI layer, their
            generated data, the C build
==========  ===================================================================
"""
