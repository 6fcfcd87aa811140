"""Moved to ``rotor_host.scenes.scene`` (load_scene, Scene); this module keeps the old import path working."""

from .scenes.scene import *  # noqa: F401,F403
