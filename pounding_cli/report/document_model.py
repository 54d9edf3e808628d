"""The base of the report documents' pydantic models (document.py, force_document.py)."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict


class _Output(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)
