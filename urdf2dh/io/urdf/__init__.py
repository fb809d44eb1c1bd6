"""URDF -> kinematic tree -> serial chain -> POE model; the only package that reads URDF XML.

:mod:`.parse` reads the text once (lxml) and hands the element tree to :mod:`.validate`'s strict
check and then to yourdfpy; :mod:`.tree` holds the kinematic tree; :mod:`.chain` walks from a
base link to a tip link and builds the POE model.
"""

from __future__ import annotations

from .chain import tree_to_poe
from .parse import load_tree, parse_tree, read_source, urdf_source
from .tree import UrdfJoint, UrdfTree

__all__ = [
    "UrdfJoint",
    "UrdfTree",
    "load_tree",
    "parse_tree",
    "read_source",
    "tree_to_poe",
    "urdf_source",
]
