"""Moved to ``bearing_fmu.physics.statics`` (equilibrium, linearize, film_jacobian); this module keeps the old import path working."""

from .physics.statics import *  # noqa: F401,F403
