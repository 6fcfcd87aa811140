"""Moved to ``bearing_fmu.physics.params`` (BearingParams, the paper bearing); this module keeps the old import path working."""

from .physics.params import *  # noqa: F401,F403
