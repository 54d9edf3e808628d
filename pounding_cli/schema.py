"""JSON Schemas of the input files, generated from the pydantic models."""

from __future__ import annotations

import json

from .model import PoundModel

SCHEMA_BASE = "https://pound.invalid/schemas/"


def model_schema() -> dict:
    """JSON Schema of a model file (TOML or JSON: same structure)."""
    schema = PoundModel.model_json_schema(mode="validation")
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["$id"] = SCHEMA_BASE + "model.schema.json"
    return schema


def schema_files() -> dict[str, str]:
    """File name → text of every schema pound publishes."""
    return {"model.schema.json": json.dumps(model_schema(), indent=2, ensure_ascii=False) + "\n"}
