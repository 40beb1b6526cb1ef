"""Compatibility: the scene names that used to live here.

The data model moved to :mod:`lfdkit.scene` (:class:`~lfdkit.scene.Scene`,
:class:`~lfdkit.scene.Obstacle`) and the scene files to
:mod:`lfdkit.io.scenes` (:func:`~lfdkit.io.scenes.load_scenes`,
:func:`~lfdkit.io.scenes.load_scene`, :func:`~lfdkit.io.scenes.save_scenes`
and the ``SCENE_*`` constants). This module re-exports them so that
``from lfdkit.emulate.scene import Scene`` keeps working; new code imports
from the new homes.
"""

from lfdkit.io.scenes import (
    SCENE_JSON_FORMAT,
    SCENE_JSON_VERSION,
    SCENE_SUFFIXES,
    load_scene,
    load_scenes,
    save_scenes,
)
from lfdkit.scene import Capsule, Obstacle, Scene

__all__ = [
    "SCENE_JSON_FORMAT",
    "SCENE_JSON_VERSION",
    "SCENE_SUFFIXES",
    "Capsule",
    "Obstacle",
    "Scene",
    "load_scene",
    "load_scenes",
    "save_scenes",
]
