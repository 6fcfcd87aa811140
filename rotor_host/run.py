"""Moved to ``rotor_host.scenes.run`` (run_scene); this module keeps the old import path working."""

from .scenes.run import *  # noqa: F401,F403
