"""Materials of columns (and, later, of colliding slabs)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from .base import Real, Strict


class Material(Strict):
    """An isotropic linear-elastic material."""

    elastic_modulus: Annotated[Real, Field(gt=0, le=1e13)]
    """Static Young's modulus E, Pa (21e9 for the paper's concrete), at most 1e13."""

    poisson_ratio: Annotated[Real, Field(ge=0, lt=0.5)] = 0.2
    """Poisson's ratio ν, dimensionless, 0 ≤ ν < 0.5 (enters the impact stiffness of the
    contact model; the columns' shear-type stiffness does not use it)."""
