"""JSON Schemas of pound's files, generated from the pydantic models that validate them.

- ``model.schema.json``: a model file (TOML or JSON: same structure);
- ``record.schema.json``: a record definition file (``*.record.toml`` / ``.json``), the
  same table a model may hold inline as ``[excitation.record]``;
- ``record-summary.schema.json``: the document ``pound record --json`` prints;
- ``report.schema.json``: the document ``pound report out.h5 --json`` prints;
- ``report-sweep.schema.json``: the document ``pound report SWEEP_DIR/ --json`` prints (its
  rows refer to ``sweep-summary.schema.json``);
- ``sweep.schema.json``: a sweep file (``*.sweep.toml`` / ``.json``, ``pound sweep``);
- ``suite.schema.json``: a record suite file (``*.suite.toml`` / ``.json``, ``pound gap --suite``);
- ``sweep-summary.schema.json``: one row of a sweep's summary table, which is also one line
  of ``pound sweep --json``.
"""

from __future__ import annotations

import json
from typing import Any

SCHEMA_BASE = "https://pound.invalid/schemas/"
DIALECT = "https://json-schema.org/draft/2020-12/schema"


def _published(schema: dict[str, Any], name: str) -> dict[str, Any]:
    schema["$schema"] = DIALECT
    schema["$id"] = SCHEMA_BASE + name
    return schema


def _input_file(schema: dict[str, Any]) -> dict[str, Any]:
    """An input file's schema: it may name the schema it follows under "$schema" (JSON, or a
    TOML key; TOML files may use a `#:schema` comment instead), which pound ignores."""
    schema["properties"] = {"$schema": {
        "type": "string",
        "description": "The JSON Schema this file follows, a URL or a path (for editors: VS Code, taplo); pound "
                       "ignores it.",
    }, **schema["properties"]}  # fmt: skip
    return schema


def model_schema() -> dict:
    """JSON Schema of a model file (TOML or JSON: same structure)."""
    from .model import PoundModel

    return _published(_input_file(PoundModel.model_json_schema(mode="validation")), "model.schema.json")


def record_schema() -> dict:
    """JSON Schema of a record definition file (TOML or JSON: same structure)."""
    from .model.record import Record

    return _published(_input_file(Record.model_json_schema(mode="validation")), "record.schema.json")


def record_summary_schema() -> dict:
    """JSON Schema of the document `pound record --json` prints."""
    from .records.summary import summary_schema

    return _published(summary_schema(), "record-summary.schema.json")


def sweep_schema() -> dict:
    """JSON Schema of a sweep file (TOML or JSON: same structure)."""
    from .model.sweep import SweepFile

    return _published(_input_file(SweepFile.model_json_schema(mode="validation")), "sweep.schema.json")


def suite_schema() -> dict:
    """JSON Schema of a record suite file (TOML or JSON: same structure)."""
    from .model.suite import SuiteFile

    return _published(_input_file(SuiteFile.model_json_schema(mode="validation")), "suite.schema.json")


def sweep_summary_schema() -> dict:
    """JSON Schema of one row of a sweep's summary (one line of `pound sweep --json`)."""
    from .sweep.columns import row_schema

    return _published(row_schema(), "sweep-summary.schema.json")


def report_schema() -> dict:
    """JSON Schema of the document `pound report out.h5 --json` prints."""
    from .report.document import summary_schema as run_report_schema

    return _published(run_report_schema(), "report.schema.json")


def report_sweep_schema() -> dict:
    """JSON Schema of the document `pound report SWEEP_DIR/ --json` prints."""
    from .report.sweep_document import sweep_schema

    return _published(sweep_schema(), "report-sweep.schema.json")


def schema_files() -> dict[str, str]:
    """File name → text of every schema pound publishes."""
    schemas = {
        "model.schema.json": model_schema(),
        "record.schema.json": record_schema(),
        "record-summary.schema.json": record_summary_schema(),
        "report.schema.json": report_schema(),
        "report-sweep.schema.json": report_sweep_schema(),
        "suite.schema.json": suite_schema(),
        "sweep.schema.json": sweep_schema(),
        "sweep-summary.schema.json": sweep_summary_schema(),
    }
    return {name: json.dumps(s, indent=2, ensure_ascii=False) + "\n" for name, s in schemas.items()}
