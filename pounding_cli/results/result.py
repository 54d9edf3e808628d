"""Results of a run, per building, in the shapes of the HDF5 contract (docs/user-guide.md, "HDF5 layout")."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..solver import ENERGY_NAMES


@dataclass
class BuildingResult:
    """One building's histories and peaks. Floors bottom up; storey s is below floor s."""

    name: str
    displacement: np.ndarray  # (nt, n_floors, 3) u_x, u_y [m], θ [rad]; global axes, relative
    velocity: np.ndarray  # (nt, n_floors, 3) relative to the ground, m/s, rad/s
    acceleration: np.ndarray  # (nt, n_floors, 3) absolute, m/s², rad/s²
    column_names: list[str]  # (n_columns,)
    column_local: np.ndarray  # (n_columns, 2) building coordinates, m
    column_plan: np.ndarray  # (n_columns, 2) global coordinates, m
    column_section: np.ndarray  # (n_columns, 2) [b_x, b_y], m
    column_angle: np.ndarray  # (n_columns,) degrees from the building x axis
    interstorey_deflection: np.ndarray  # (n_columns, n_storeys, 3) peak |Δu_x|, |Δu_y| [m] (building axes), |Δθ| [rad]
    peak_displacement: np.ndarray  # (n_floors, 3) peak |u|, global axes
    peak_acceleration: np.ndarray  # (n_floors, 3) peak absolute |a|
    elevation: np.ndarray  # (n_floors,) m
    floor_mass: np.ndarray  # (n_floors, 2) m [kg], J [kg·m²]
    mass_centre: np.ndarray  # (n_floors, 2) global plan position at rest, m
    periods: np.ndarray  # (n_modes,) s
    participation: np.ndarray  # (n_modes, 3) effective modal mass ratios x, y, θ (building axes)
    rayleigh: tuple[float, float]  # (a0 1/s, a1 s)

    def column(self, name: str) -> np.ndarray:
        """Peak interstorey deflections (n_storeys, 3) of one column by name."""
        try:
            return self.interstorey_deflection[self.column_names.index(name)]
        except ValueError:
            raise KeyError(f"building {self.name!r} has no column {name!r}") from None


@dataclass
class RunResult:
    """A whole run: time histories at the output interval, peaks over every step."""

    time: np.ndarray  # (nt,) s
    ground_acceleration: np.ndarray  # (nt, 2) global X, Y, m/s²
    energy: np.ndarray  # (nt, 7) J, columns ENERGY_NAMES
    buildings: dict[str, BuildingResult]
    status: str  # "complete" or "failed: …"
    model_json: str  # the resolved model
    input_sha256: str
    diagnostics: dict[str, Any] = field(default_factory=dict)
    output: Path | None = None  # the HDF5 file, once written

    @property
    def complete(self) -> bool:
        return self.status == "complete"

    def energy_column(self, name: str) -> np.ndarray:
        """One energy history (J) by name, e.g. "input"."""
        return self.energy[:, ENERGY_NAMES.index(name)]

    @property
    def balance_error_ratio(self) -> float:
        """max |E_input − Σ E| / max E_input over the run (0 when nothing was put in)."""
        e_in = np.abs(self.energy_column("input")).max(initial=0.0)
        err = np.abs(self.energy_column("balance_error")).max(initial=0.0)
        return float(err / e_in) if e_in > 0 else 0.0
