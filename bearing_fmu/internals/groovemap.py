"""Moved to ``bearing_fmu.internals.map.groovemap``; this module keeps the old import path working."""

from .map.groovemap import *  # noqa: F401,F403
