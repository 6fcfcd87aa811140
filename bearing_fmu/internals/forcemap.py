"""Moved to ``bearing_fmu.internals.map`` (tables, tablefile, forcemap); this module keeps the old import path working."""

from .map.forcemap import *  # noqa: F401,F403
from .map.tablefile import *  # noqa: F401,F403
from .map.tables import *  # noqa: F401,F403
