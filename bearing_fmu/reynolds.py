"""Moved to ``bearing_fmu.physics.solver.reynolds`` (the Reynolds solver); this module keeps the old import path working."""

from .physics.solver.reynolds import *  # noqa: F401,F403
