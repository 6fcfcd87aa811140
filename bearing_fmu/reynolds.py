"""Moved to ``bearing_fmu.physics.reynolds`` (the Reynolds solver); this module keeps the old import path working."""

from .physics.reynolds import *  # noqa: F401,F403
