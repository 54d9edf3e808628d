"""Results of a run, per building, in the shapes of the HDF5 contract (docs/user-guide.md, "HDF5 layout")."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..solver.layout import ENERGY_NAMES


HISTORY_DTYPE = {"double": np.dtype(np.float64), "single": np.dtype(np.float32)}
"""The dtype of the buildings' stored histories for each analysis.history_precision (its
itemsize: their bytes a value in the resource limits' file estimate)."""

MEMBER_DTYPE = np.dtype(
    [
        ("name", object),
        ("kind", object),
        ("storey", np.int64),
        ("X", np.float64),
        ("Y", np.float64),
        ("angle", np.float64),
        ("stiffness", np.float64, (2,)),
        ("yield_force", np.float64, (2,)),
        ("post_yield_ratio", np.float64, (2,)),
        ("elliptical", np.bool_),
    ]
)
"""One row per yielding member: name, "column" or "isolator", storey (1-based; storey 1 of an
isolated building is the isolation storey), plan position (global, m), local x axis (degrees
from global X), initial stiffness (N/m), yield force (N) and post-yield ratio along local x, y."""


@dataclass
class YieldingResult:
    """A building's yielding members (inelastic columns, isolators): histories at the output
    interval, peaks over every step. Deflections and forces are along each member's local axes."""

    members: np.ndarray  # (n,) MEMBER_DTYPE
    deflection: np.ndarray  # (nt, n, 2) δ_x, δ_y, m
    force: np.ndarray  # (nt, n, 2) f_x, f_y, N
    peak: np.ndarray  # (n, 6) |δ_x|, |δ_y|, |δ| m, |f_x|, |f_y|, |f| N
    residual_deflection: np.ndarray  # (n, 2) m, at rest after the run

    @property
    def yield_deflection(self) -> np.ndarray:
        """(n, 2) F_y/k, m."""
        return self.members["yield_force"] / self.members["stiffness"]

    @property
    def ductility(self) -> np.ndarray:
        """(n, 2) peak |δ| / δ_y along local x, y (below 1: the member stayed elastic)."""
        return self.peak[:, :2] / self.yield_deflection


@dataclass
class ForceResult:
    """One building's storey shears and column forces (results/forces.py: components and signs).
    Storeys bottom up (an isolated building's isolation storey first); columns as the building's
    column lines, NaN where a line has no column in a storey. Histories at the output interval,
    peaks over every step and between steps."""

    storey_shear: np.ndarray  # (nt, n_storeys, 6) STOREY_COMPONENTS, N and N·m
    base_shear: np.ndarray  # (nt, 6) the same, of the storey on the ground
    # (nt, n_floors, 3) contact forces on the floors: F_x, F_y N, torque N·m about the mass centre
    floor_contact: np.ndarray  # (read back from a file: sparse.SparseColumns, the floors struck)
    peak_storey_shear: np.ndarray  # (n_storeys, 6) running max |·| over every step, N and N·m
    peak_base_shear: np.ndarray  # (6,)
    peak_column_shear: np.ndarray  # (n_columns, n_storeys, 2) local x, y, N
    peak_column_moment: np.ndarray  # (n_columns, n_storeys, 2) N·m
    column_shear: np.ndarray | None = None  # (nt, n_columns, n_storeys, 2) when asked for (analysis.column_force_histories)
    column_moment: np.ndarray | None = None  # (nt, n_columns, n_storeys, 2)


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
    yielding: YieldingResult | None = None  # inelastic columns and isolators, if any
    isolated: bool = False  # floor 1 is a base slab on isolators (storey 1: the isolation storey)
    base_elevation: float = 0.0  # m: the building's ground (elevation is measured from the common datum)
    forces: ForceResult | None = None  # storey shears and column forces

    def column(self, name: str) -> np.ndarray:
        """Peak interstorey deflections (n_storeys, 3) of one column by name."""
        try:
            return self.interstorey_deflection[self.column_names.index(name)]
        except ValueError:
            raise KeyError(f"building {self.name!r} has no column {name!r}") from None


EVENT_DTYPE = np.dtype(
    [
        ("body_a", object),
        ("body_b", object),
        ("level", np.int64),
        ("t_start", np.float64),
        ("t_end", np.float64),
        ("peak_normal_force", np.float64),
        ("normal_impulse", np.float64),
        ("peak_area", np.float64),
        ("peak_depth", np.float64),
        ("x", np.float64),
        ("y", np.float64),
        ("slid", np.bool_),
        ("floor_b", np.int64),
        ("elevation", np.float64),
        ("t_peak", np.float64),
        ("pair", np.int64),
        ("tangential_force_at_peak", np.float64),
        ("normal_x", np.float64),
        ("normal_y", np.float64),
        ("storey_b", np.int64),
        ("xi", np.float64),
        ("t_slip", np.float64),
        ("t_stick", np.float64),
        ("slips", np.int64),
    ]
)
"""One row per contact episode. level / floor_b: 1-based floors of body A's and body B's
buildings (floor_b 0 for an obstacle); t_end NaN if the contact lasted to the end; at the
step of the peak normal force (time t_peak): x, y the action point (global, m),
tangential_force_at_peak the tangential force on B along t = ẑ × n (N, signed) and
normal_x, normal_y the unit normal n from A into B (global). A slab striking a neighbour's
storey between two floors: storey_b is that storey (1-based; floor_b the floor above it) and xi
where along its height, (z − z_below)/h; otherwise 0 and NaN. t_start and t_end are where the
outlines met and parted, t_slip where the contact first slipped (t_start if from the touch),
t_stick where its last slip ended (NaN: it never slipped, or slipped to its end), slips the
number of its slip phases: each located inside its contact step (docs/theory.md, "Events
inside the step"). Files written before a column existed read it back as NaN (0 for an
integer)."""

PAIR_DTYPE = np.dtype(
    [
        ("body_a", object),
        ("floor_a", np.int64),
        ("body_b", object),
        ("floor_b", np.int64),
        ("elevation", np.float64),
        ("k_normal", np.float64),
        ("k_tangential", np.float64),
        ("storey_b", np.int64),
        ("xi", np.float64),
    ]
)
"""One row per contact candidate pair (the columns of the contact histories)."""


CONTACT_HISTORIES = ("normal_force", "tangential_force", "area", "action_point", "depth")
"""The contact histories of ContactResult, (nt, n_pairs[, 2]), by field name."""


@dataclass
class ContactResult:
    """Contact candidates, their force histories at the output interval and the impact log.
    The histories are arrays after a run, and sparse.SparseColumns where read from a file
    (the pairs that touched: indexed [:, p] and [k] as the arrays; np.asarray gives them)."""

    pairs: np.ndarray  # (n_pairs,) PAIR_DTYPE
    normal_force: np.ndarray  # (nt, n_pairs) N
    tangential_force: np.ndarray  # (nt, n_pairs) N, along t = ẑ × n, on body B
    area: np.ndarray  # (nt, n_pairs) m²
    action_point: np.ndarray  # (nt, n_pairs, 2) global, m (0 when apart)
    depth: np.ndarray  # (nt, n_pairs) m
    events: np.ndarray  # (n_events,) EVENT_DTYPE
    column_demand: np.ndarray | None = None  # (n_rows,) column_demand.DEMAND_DTYPE: what slab–storey impacts put into the struck columns

    def __post_init__(self) -> None:
        if self.column_demand is None:
            from .column_demand import DEMAND_DTYPE

            self.column_demand = np.zeros(0, DEMAND_DTYPE)

    @classmethod
    def empty(cls, nt: int) -> "ContactResult":
        z = np.zeros((nt, 0))
        return cls(np.zeros(0, PAIR_DTYPE), z, z, z, np.zeros((nt, 0, 2)), z, np.zeros(0, EVENT_DTYPE))

    @property
    def impact_count(self) -> int:
        return int(self.events.size)

    @property
    def peak_force(self) -> float:
        """Largest normal impact force of the run, N (0 without impacts)."""
        return float(self.events["peak_normal_force"].max(initial=0.0))


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
    contact: ContactResult | None = None
    warnings: list[dict[str, str]] = field(default_factory=list)  # plausibility warnings: {file, field, message}

    def __post_init__(self) -> None:
        if self.contact is None:
            self.contact = ContactResult.empty(self.time.size)

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
