"""Moved to ``bearing_fmu.internals.taylor.taylor`` (the Taylor internal); this module keeps the old import path working."""

from .internals.taylor.taylor import *  # noqa: F401,F403
