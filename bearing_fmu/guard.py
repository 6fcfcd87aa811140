"""Moved to ``bearing_fmu.internals.taylor.guard`` (DomainGuard); this module keeps the old import path working."""

from .internals.taylor.guard import *  # noqa: F401,F403
