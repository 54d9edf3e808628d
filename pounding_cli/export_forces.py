"""The forces of a result as tidy tables for `pound export` (export.QUANTITIES): storey shears
and column forces, histories and peaks (results/forces.py: components, signs and axes)."""

from __future__ import annotations

from typing import Any, Iterator

import numpy as np

from .assembly.force_gauges import STOREY_COMPONENTS, STOREY_UNITS

STOREY_COLUMNS = [(name, unit.replace("·", "*")) for name, unit in zip(STOREY_COMPONENTS, STOREY_UNITS)]
COLUMN_COLUMNS = [("shear_x", "N"), ("shear_y", "N"), ("moment_x", "N*m"), ("moment_y", "N*m")]


def listed(a: np.ndarray) -> list[Any]:
    """a.tolist(), but the values of a float32 history (analysis.history_precision = "single")
    kept as numpy scalars, which the CSV gets in their shortest form (1.0312335e-07, not the
    float64 digits of the same number, 1.0312334808304513e-07, which it never had)."""
    if a.dtype != np.float32:
        return a.tolist()
    return [listed(x) for x in a] if a.ndim > 1 else list(a)


def _with_forces(r: Any) -> list[Any]:
    """The buildings that have forces (all but those of files written before pound stored them)."""
    return [b for b in r.buildings.values() if b.forces is not None]


def storey_shear_table(r: Any) -> tuple[list[tuple[str, str]], Iterator[list[Any]]]:
    """One row per time, building and storey: its STOREY_COMPONENTS."""
    columns = [("time", "s"), ("building", ""), ("storey", "")] + STOREY_COLUMNS

    def rows() -> Iterator[list[Any]]:
        buildings = _with_forces(r)
        for k, t in enumerate(r.time.tolist()):
            for b in buildings:
                for s, v in enumerate(listed(b.forces.storey_shear[k]), start=1):
                    yield [t, b.name, s, *v]

    return columns, rows()


def column_force_table(r: Any) -> tuple[list[tuple[str, str]], Iterator[list[Any]]]:
    """One row per time, building, column and storey where the column stands: its shears and
    end moments (none unless the run stored them: analysis.column_force_histories)."""
    columns = [("time", "s"), ("building", ""), ("column", ""), ("storey", "")] + COLUMN_COLUMNS

    def rows() -> Iterator[list[Any]]:
        buildings = [b for b in _with_forces(r) if b.forces.column_shear is not None]
        for k, t in enumerate(r.time.tolist()):
            for b in buildings:
                shear, moment = listed(b.forces.column_shear[k]), listed(b.forces.column_moment[k])
                for c, name in enumerate(b.column_names):
                    for s, v in enumerate(shear[c]):
                        if v[0] == v[0]:  # NaN: the line has no column in this storey
                            yield [t, b.name, name, s + 1, *v, *moment[c][s]]

    return columns, rows()


def storey_shear_peak_table(r: Any) -> tuple[list[tuple[str, str]], Iterator[list[Any]]]:
    """One row per building and storey: the peak |·| of each STOREY_COMPONENT (storey 1's is
    the base shear)."""
    columns = [("building", ""), ("storey", "")] + STOREY_COLUMNS

    def rows() -> Iterator[list[Any]]:
        for b in _with_forces(r):
            for s, v in enumerate(b.forces.peak_storey_shear.tolist(), start=1):
                yield [b.name, s, *v]

    return columns, rows()


def column_force_peak_table(r: Any) -> tuple[list[tuple[str, str]], Iterator[list[Any]]]:
    """One row per building, column and storey where the column stands: peak |shear| and |moment|."""
    columns = [("building", ""), ("column", ""), ("storey", "")] + COLUMN_COLUMNS

    def rows() -> Iterator[list[Any]]:
        for b in _with_forces(r):
            shear, moment = b.forces.peak_column_shear.tolist(), b.forces.peak_column_moment.tolist()
            for c, name in enumerate(b.column_names):
                for s, v in enumerate(shear[c]):
                    if v[0] == v[0]:
                        yield [b.name, name, s + 1, *v, *moment[c][s]]

    return columns, rows()
