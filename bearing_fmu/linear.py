"""Moved to ``bearing_fmu.internals.linear.linear`` (the Linear internal); this module keeps the old import path working."""

from .internals.linear.linear import *  # noqa: F401,F403
