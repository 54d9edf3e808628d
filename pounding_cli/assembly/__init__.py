"""Turns a validated model into plain arrays: M, K, C, modes, ground motion, Δt."""

from .building import BuildingArrays, ColumnLine, ColumnInstance
from .contact import ContactArrays, PairInfo, contact_arrays, impact_stiffness
from .ground import GroundMotion, ground_motion
from .system import System, assemble
from .timestep import TimeGrid, time_grid

__all__ = [
    "BuildingArrays",
    "ColumnInstance",
    "ColumnLine",
    "ContactArrays",
    "GroundMotion",
    "PairInfo",
    "System",
    "TimeGrid",
    "assemble",
    "contact_arrays",
    "ground_motion",
    "impact_stiffness",
    "time_grid",
]
