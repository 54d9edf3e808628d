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

    density: Annotated[Real, Field(gt=0, le=1e5)] | None = None
    """Mass density ρ, kg/m³ (2,500 for reinforced concrete), at most 1e5. Given, the columns a
    slab strikes between floors (slab–storey contact) vibrate with their own mass: their first
    `contact.column_modes` local bending modes become degrees of freedom (docs/theory.md, "The
    struck columns' own mass"), and their mass leaves the floors they stand between. Absent: the
    struck columns are massless (their mass is all in the floors' masses, which the user's
    masses include either way)."""
