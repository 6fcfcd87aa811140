"""The system around the bearings: FE rotor, Newmark-Newton integrator, fmpy co-simulation."""

__version__ = "0.1.0"
