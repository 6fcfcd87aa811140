"""Moved to ``bearing_fmu.internals.guard`` (DomainGuard); this module keeps the old import path working."""

from .internals.guard import *  # noqa: F401,F403
