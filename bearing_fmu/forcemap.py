"""Moved to ``bearing_fmu.internals.map`` (ForceMap, its table and its file); this module keeps the old import path working."""

from .internals.map.forcemap import *  # noqa: F401,F403
from .internals.map.tablefile import *  # noqa: F401,F403
from .internals.map.tables import *  # noqa: F401,F403
