"""Materials of columns (and, later, of colliding slabs)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from .base import Strict


class Material(Strict):
    """An isotropic linear-elastic material."""

    elastic_modulus: Annotated[float, Field(gt=0)]
    """Static Young's modulus E, Pa (e.g. 21e9 for the paper's concrete)."""

    poisson_ratio: Annotated[float, Field(ge=0, lt=0.5)] = 0.2
    """Poisson's ratio ν, dimensionless, 0 ≤ ν < 0.5."""
