"""The pythonfmu slave's parts, by responsibility; ``bearing_fmu/fmu/slave.py`` joins them into
``BearingFMU`` (the module pythonfmu runs; the build bundles this folder with it).

calls      the FMI 2.0 calling sequence, honest statuses (``FMIError``: fmi2Error), logging
access     the variables: registration from the one table, getters and setters, parameter checks
stepping   the internal built from the parameters, doStep, the outputs (with the thermal ports)
state      the FMU state: get, set, serialise
"""
