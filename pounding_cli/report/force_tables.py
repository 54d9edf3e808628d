"""The force tables of a run's report (tables.run_tables), from the report document's
`forces` of each building (force_document.py): kN and kN·m for reading."""

from __future__ import annotations

from typing import Any

from .tables import TableSpec


def _k(value: float | None) -> str:
    """N (N·m) as kN (kN·m); below 1 mN (round-off of a force that is zero) as 0."""
    if value is None:
        return "-"
    return "0" if abs(value) < 1e-3 else f"{value / 1e3:.4g}"


def storey_shear_table(name: str, forces: dict[str, Any]) -> TableSpec:
    """Per storey: peak shears and torques in building and global axes, and its largest column shear."""
    rows = [[str(s["storey"]), _k(s["x_N"]), _k(s["y_N"]), _k(s["torque_Nm"]), _k(s["X_N"]), _k(s["Y_N"]),
             _k(s["torque_origin_Nm"]), _k(s["column_shear_N"]), s["column"] or "-"]
            for s in forces["storeys"]]  # fmt: skip
    return TableSpec(
        f"Peak storey shears: {name} (storey 1: the base shear; V_x, V_y building axes, T about the floor above's "
        "mass centre; V_X, V_Y global, T_O about the origin)",
        ["storey", "V_x (kN)", "V_y (kN)", "T (kN·m)", "V_X (kN)", "V_Y (kN)", "T_O (kN·m)", "column |V| (kN)",
         "column"],
        rows, right=set(range(8)),
    )  # fmt: skip


def column_force_table(name: str, column: dict[str, Any]) -> TableSpec:
    """One column line's peak shears and end moments per storey (local axes)."""
    rows = [[str(s + 1), _k(v[0]), _k(v[1]), _k(m[0]), _k(m[1])]
            for s, (v, m) in enumerate(zip(column["shear_N"], column["moment_Nm"])) if v[0] is not None]  # fmt: skip
    return TableSpec(f"Peak column forces: {name}, column {column['name']} (local axes; M = V·h/2, fixed at both ends)",
                     ["storey", "V_x (kN)", "V_y (kN)", "M of V_x (kN·m)", "M of V_y (kN·m)"], rows,
                     right={0, 1, 2, 3, 4})  # fmt: skip


def force_tables(doc: dict[str, Any]) -> list[TableSpec]:
    """Per building with forces: its storey shears; with --column, that column's forces too."""
    out = []
    for b in doc["buildings"]:
        forces = b.get("forces")
        if not forces:
            continue
        out.append(storey_shear_table(b["name"], forces))
        if doc["column"]:
            out += [column_force_table(b["name"], c) for c in forces["columns"]]
    return out
