"""The columns of a sweep's summary table, and the JSON Schema of one row.

A summary has one row per case and these columns, in this order (docs/sweep.md, "Summary"):

- ``study``, ``case``, ``hash``, ``status``, ``file``: which case, and what became of it;
- one column per swept path, named by the path as the sweep file writes it
  (``excitation.angle``): the value the case's model resolved to there;
- ``impacts``, ``peak_impact_force_N``, ``energy_balance_error``;
- per building B: ``peak_isd_x_m[B]``, ``peak_isd_y_m[B]``, ``peak_isd_theta_rad[B]``, the
  largest peak interstorey deflection over its columns and storeys, per direction; and
  ``peak_base_shear_x_N[B]``, ``peak_base_shear_y_N[B]``, ``peak_base_torque_Nm[B]`` (building
  axes, about the mass centre of its first floor), ``max_column_shear_N[B]`` (the largest peak
  column shear over its columns, storeys and local axes): results/forces.py;
- per building B with yielding members (in some case): ``max_ductility[B]``, the largest peak
  ductility over its inelastic columns, either local axis, and
  ``max_residual_deflection_m[B]``, the largest resultant residual deflection over them
  (both only if it has inelastic columns), and ``peak_isolator_displacement_m[B]``, the largest peak resultant displacement of its
  isolators (only if it is base-isolated); NaN/null in a case where it has none;
- per column C of building B named in ``[summary] columns``, per storey s (1 = ground
  storey): ``peak_isd_x_m[B/C/s]``, ``peak_isd_y_m[B/C/s]``, ``peak_isd_theta_rad[B/C/s]``.
  Names cannot hold brackets or slashes, so these names are unambiguous;
- ``solver_time_s``, ``wall_time_s``.

Result columns are empty (CSV), NaN or −1 (HDF5) and null (JSON) where a case has no
results. The same row is what ``pound sweep --json`` prints, one JSON object per line.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

DIRECTIONS = (("x_m", "m", "Δu_x along the building's x axis"), ("y_m", "m", "Δu_y along the building's y axis"),
              ("theta_rad", "rad", "Δθ, the storey's twist"))  # fmt: skip
"""Suffix, unit and meaning of the three components of an interstorey deflection."""


@dataclass(frozen=True)
class Column:
    """One column of the summary: its name, kind ("case", "parameter" or "result"), value
    type ("str", "int", "float", "bool" or "json"), unit and meaning."""

    name: str
    kind: str
    dtype: str
    units: str
    description: str

    def as_dict(self) -> dict[str, str]:
        return {"name": self.name, "kind": self.kind, "dtype": self.dtype, "units": self.units,
                "description": self.description}  # fmt: skip


CASE_COLUMNS = [
    Column("study", "case", "str", "-", 'The study the case belongs to ("" for a sweep of one study).'),
    Column("case", "case", "str", "-", "The case's name within its study: the named case and/or its parameter values."),
    Column("hash", "case", "str", "-", "12 hex digits: the start of the case's input_sha256; names its file."),
    Column("status", "case", "str", "-", '"complete", "failed: …" (with the reason) or "pending" (not run yet).'),
    Column("file", "case", "str", "-", "The case's HDF5 file, relative to the sweep folder: cases/<hash>.h5."),
]
RESULT_COLUMNS = [
    Column("impacts", "result", "int", "-", "Number of contact episodes (impacts) in the run."),
    Column("peak_impact_force_N", "result", "float", "N", "Largest normal impact force of the run (0 without impacts)."),
    Column("energy_balance_error", "result", "float", "-",
           "max |E_input − (E_kinetic + E_strain + E_damping + E_hysteretic + E_contact)| / max E_input "
           "over the run."),  # fmt: skip
]
TIME_COLUMNS = [
    Column("solver_time_s", "result", "float", "s", "Wall time of the time loop (diagnostics wall_time_s)."),
    Column("wall_time_s", "result", "float", "s",
           "Wall time of the analysis: compiling or loading the kernels, the time loop and collecting "
           "the results (diagnostics run_time_s); reading the record and writing the file are not included."),  # fmt: skip
]


FORCES = (("peak_base_shear_x_N", "N", "Peak base shear along the building's x axis"),
          ("peak_base_shear_y_N", "N", "Peak base shear along the building's y axis"),
          ("peak_base_torque_Nm", "N·m", "Peak base torque about the mass centre of the first floor"),
          ("max_column_shear_N", "N", "Largest peak column shear over all columns, storeys and local axes"))  # fmt: skip
"""Name, unit and meaning of a building's force columns (results/forces.py: signs and axes)."""


def building_columns(building: str) -> list[Column]:
    """The three largest-peak deflection columns and the force columns of one building."""
    return [
        Column(f"peak_isd_{suffix}[{building}]", "result", "float", unit,
               f"Largest peak interstorey deflection {meaning} over all columns and storeys of building {building}.")
        for suffix, unit, meaning in DIRECTIONS
    ] + [
        Column(f"{name}[{building}]", "result", "float", unit,
               f"{meaning} of building {building} (NaN in a file written before pound stored forces).")
        for name, unit, meaning in FORCES
    ]  # fmt: skip


def yielding_columns(building: str, columns: bool, isolated: bool) -> list[Column]:
    """The yielding-member columns of one building: with inelastic `columns`, its largest peak
    ductility and largest residual deflection; if `isolated`, its largest peak isolator
    displacement."""
    out = []
    if columns:
        out.append(Column(f"max_ductility[{building}]", "result", "float", "-",
                          f"Largest peak ductility |δ|/δ_y over the inelastic columns of building {building} and "
                          "both their local axes (below 1: none yielded; NaN in a case where it has none)."))  # fmt: skip
        out.append(Column(f"max_residual_deflection_m[{building}]", "result", "float", "m",
                          f"Largest residual deflection over the inelastic columns of building {building}: the "
                          "resultant √(δ_x² + δ_y²) of a column's deflection at rest after the run (NaN in a case "
                          "where it has none)."))  # fmt: skip
    if isolated:
        out.append(Column(f"peak_isolator_displacement_m[{building}]", "result", "float", "m",
                          f"Largest peak resultant isolator displacement of building {building} "
                          "(NaN in a case where it is not isolated)."))  # fmt: skip
    return out


def storey_columns(building: str, column: str, storeys: int) -> list[Column]:
    """The per-storey columns of one named column line, storey 1 (ground) upwards."""
    return [
        Column(f"peak_isd_{suffix}[{building}/{column}/{s}]", "result", "float", unit,
               f"Peak interstorey deflection {meaning} of column {column} of building {building} in storey {s} "
               "(NaN where the column line is absent from that storey).")
        for s in range(1, storeys + 1)
        for suffix, unit, meaning in DIRECTIONS
    ]  # fmt: skip


def parameter_column(path: str, values: list[Any]) -> Column:
    """The column of one swept path; its type from the values it takes."""
    return Column(path, "parameter", _dtype(values), "",
                  f"The value of the model's {path} in the case (as resolved: defaults filled in).")  # fmt: skip


def _dtype(values: list[Any]) -> str:
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return "bool"
    if present and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
        return "float"
    if present and all(isinstance(v, str) for v in present):
        return "str"
    return "json"


def row_schema() -> dict[str, Any]:
    """JSON Schema of one summary row (a `pound sweep --json` line)."""
    number = {"type": ["number", "null"]}
    props: dict[str, Any] = {}
    for c in CASE_COLUMNS:
        props[c.name] = {"type": "string", "description": c.description}
    props["hash"]["pattern"] = "^[0-9a-f]{12}$"
    props["status"]["pattern"] = "^(complete|pending|failed: .*)$"
    props["impacts"] = {"type": ["integer", "null"], "minimum": 0, "description": RESULT_COLUMNS[0].description}
    for c in RESULT_COLUMNS[1:] + TIME_COLUMNS:
        props[c.name] = {**number, "minimum": 0, "description": f"{c.description} Unit: {c.units}."}
    deflection = {
        f"^peak_isd_{suffix}\\[[^/\\]]+\\]$": {**number, "minimum": 0, "description":
            f"Largest peak interstorey deflection {meaning} of the building named in brackets, {unit}."}
        for suffix, unit, meaning in DIRECTIONS
    }  # fmt: skip
    deflection |= {
        f"^peak_isd_{suffix}\\[[^/\\]]+/[^/\\]]+/[1-9][0-9]*\\]$": {**number, "minimum": 0, "description":
            f"Peak interstorey deflection {meaning} of [building/column/storey], {unit}."}
        for suffix, unit, meaning in DIRECTIONS
    }  # fmt: skip
    deflection |= {
        f"^{name}\\[[^/\\]]+\\]$": {**number, "minimum": 0, "description":
            f"{meaning} of the building named in brackets, {unit}."}
        for name, unit, meaning in FORCES
    }  # fmt: skip
    yielding = {
        "^max_ductility\\[[^/\\]]+\\]$": {**number, "minimum": 0, "description":
            "Largest peak ductility over the inelastic columns of the building named in brackets, either local "
            "axis; null where it has none."},
        "^max_residual_deflection_m\\[[^/\\]]+\\]$": {**number, "minimum": 0, "description":
            "Largest resultant residual deflection over the inelastic columns of the building named in brackets, "
            "m; null where it has none."},
        "^peak_isolator_displacement_m\\[[^/\\]]+\\]$": {**number, "minimum": 0, "description":
            "Largest peak resultant isolator displacement of the building named in brackets, m; null where it "
            "is not isolated."},
    }  # fmt: skip
    return {
        "title": "One row of a pound sweep summary",
        "description": "One case of a sweep: summary.csv and the /cases table of summary.h5 have one column per "
        "key, and `pound sweep --json` prints one such object per line. Keys other than those listed "
        "are the swept paths into the model (e.g. excitation.angle), with the value the case resolved to.",
        "type": "object",
        "required": [c.name for c in CASE_COLUMNS + RESULT_COLUMNS + TIME_COLUMNS],
        "properties": props,
        "patternProperties": deflection | yielding,
        "additionalProperties": True,
    }
