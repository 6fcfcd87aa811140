"""Moved to ``bearing_fmu.internals.map.mapfile``; this module keeps the old import path working."""

from .map.mapfile import *  # noqa: F401,F403
