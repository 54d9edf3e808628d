"""Turns a validated model into plain arrays: M, K, Rayleigh C, modes, ground motion, Δt."""

from .building import BuildingArrays, ColumnLine, ColumnInstance
from .ground import GroundMotion, ground_motion
from .system import System, assemble
from .timestep import AUTO_DT_FRACTION, TimeGrid, time_grid

__all__ = [
    "AUTO_DT_FRACTION",
    "BuildingArrays",
    "ColumnInstance",
    "ColumnLine",
    "GroundMotion",
    "System",
    "TimeGrid",
    "assemble",
    "ground_motion",
    "time_grid",
]
