"""Moved to ``bearing_fmu.internals.taylor`` (the Taylor internal); this module keeps the old import path working."""

from .internals.taylor import *  # noqa: F401,F403
