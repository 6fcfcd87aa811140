"""Moved to ``bearing_fmu.internals.forcemap`` (ForceMap and its file); this module keeps the old import path working."""

from .internals.forcemap import *  # noqa: F401,F403
