"""`pound bench`: run time against error, and stability stress tests.

For each scene (the model files in pounding_cli/bench/scenes/, or any given), a reference run
of the central difference method at a far smaller Δt, its convergence checked by halving Δt
once more, then every integrator setting; each is timed (median of repeats, solver only) and
compared with the reference (see metrics.py).
"""

from .metrics import Errors, compare
from .run import SETTINGS, Setting, bench, scene_files

__all__ = ["Errors", "SETTINGS", "Setting", "bench", "compare", "scene_files"]
