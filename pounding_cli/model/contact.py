"""Contact (pounding) settings and fixed obstacles.

The impact law of Polycarpou & Komodromos (2013), section 4: a normal force k_N·A_c from
the overlap area A_c of two slabs at one level, acting at the overlap's centroid along the
normal to the line through the two boundary crossings; an incremental tangential spring
k_T with Coulomb stick/slip (static μ_s, kinetic μ_k); optional dashpots.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import Discriminator, Field, PlainValidator, Tag, ValidationInfo, WithJsonSchema, field_validator, model_validator

from .base import Flag, Name, Real, Strict
from .slab import Outline, convex_polygon


def _number_or_auto(value: Any) -> float | Literal["auto"]:
    if value == "auto":
        return "auto"
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > 0:
        return float(value)
    raise ValueError(f'expected a stiffness (a number > 0) or "auto", got {value!r}')


StiffnessOrAuto = Annotated[
    float | Literal["auto"],
    PlainValidator(_number_or_auto),
    WithJsonSchema({"anyOf": [{"type": "number", "exclusiveMinimum": 0}, {"const": "auto", "type": "string"}]}),
]


def _modes_or_auto(value: Any) -> int | Literal["auto"]:
    if value == "auto":
        return "auto"
    if isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= 16:
        return value
    raise ValueError(f'expected a number of local modes (an integer, 0 to 16) or "auto", got {value!r}')


ModesOrAuto = Annotated[
    int | Literal["auto"],
    PlainValidator(_modes_or_auto),
    WithJsonSchema({"anyOf": [{"type": "integer", "minimum": 0, "maximum": 16}, {"const": "auto", "type": "string"}]}),
]


class Contact(Strict):
    """How floors at one level (and floors and obstacles) interact when they overlap."""

    enabled: Flag = True
    """Detect and model pounding. false: the buildings pass through each other (the paper's
    "d = ∞" cases)."""

    k_normal: StiffnessOrAuto = "auto"
    """Normal impact stiffness k_N per unit overlap area, N/m² (F_N = k_N·A_c), or "auto":
    from the two bodies' materials by the paper's eqs. (6)–(7)."""

    k_tangential: StiffnessOrAuto = "auto"
    """Tangential impact stiffness k_T of the incremental friction spring, N/m, or "auto":
    from the two bodies' materials by eq. (8) as corrected in docs/theory.md."""

    friction_static: Annotated[Real, Field(ge=0, le=10)] = 0.8
    """Static friction coefficient μ_s: the contact sticks while |F_T| ≤ μ_s·F_N."""

    friction_kinetic: Annotated[Real, Field(ge=0, le=10)] = 0.6
    """Kinetic friction coefficient μ_k: while sliding |F_T| = μ_k·F_N; at most μ_s."""

    restitution: Annotated[Real, Field(ge=0.14, le=1)] | None = None
    """Coefficient of restitution e of a face-to-face impact, 0.14 to 1, from which a normal
    dashpot is derived (docs/theory.md; a dashpot that cannot pull rebounds with e ≥ 0.135
    while underdamped); 1 or absent: no normal dashpot (the paper's choice)."""

    damping_normal: Annotated[Real, Field(gt=0)] | None = None
    """Normal dashpot coefficient c_N, N·s/m, instead of `restitution`."""

    damping_tangential: Annotated[Real, Field(gt=0)] | None = None
    """Tangential dashpot coefficient c_T, N·s/m, beside the friction spring: the two in series
    with Coulomb's slider, so that while the contact slips the spring relaxes towards the
    friction force with the time constant c_T/k_T (docs/theory.md, "The tangential dashpot");
    absent: none (the paper's choice)."""

    column_modes: ModesOrAuto = "auto"
    """Local bending modes of the columns a slab strikes between floors (slab–storey contact)
    modelled as degrees of freedom, 0 to 16, where the columns' material has a `density`: their
    own mass, which splits an impact into short ones and raises its peak force and the columns'
    shear (docs/theory.md, "The struck columns' own mass"). "auto": for each struck set of
    columns, the fewest modes whose highest frequency on fixed floors reaches 8 times the
    contact's own against the columns' mass, √(k_N·L/m) (L the contact line; at most 16): what
    the finite-element comparison in the validation report needs for the first impact's peak
    force within 0.4 %. Each mode adds 3 degrees of freedom to the struck building. 0: massless
    struck columns."""

    reach: Annotated[Real, Field(gt=0)] | None = None
    """Reach, m: two buildings whose outlines at rest lie farther apart in plan than this get
    no contact candidates. Default: the bound from the buildings' modes and the record's
    spectral displacement (docs/theory.md, "Which buildings can meet"). Every run checks that
    no pruned pair came within reach of touching, and reruns with a larger reach if one did."""

    @model_validator(mode="after")
    def _consistent(self) -> "Contact":
        if self.friction_kinetic > self.friction_static:
            raise ValueError(
                f"friction_kinetic ({self.friction_kinetic:g}) exceeds friction_static "
                f"({self.friction_static:g}); a sliding contact cannot resist more than a sticking one"
            )
        if self.restitution is not None and self.damping_normal is not None:
            raise ValueError("give either 'restitution' or 'damping_normal', not both")
        return self


class ImpactOverrides(Strict):
    """Impact parameters for the pairs a fixed body is in, each replacing [contact]'s where
    given (resolved by :meth:`applied_to`, the same way for every such body)."""

    k_normal: Annotated[Real, Field(gt=0, le=1e15)] | None = None
    """Normal impact stiffness against this body per unit overlap area, N/m²; default: as
    [contact] gives it."""

    k_tangential: Annotated[Real, Field(gt=0, le=1e15)] | None = None
    """Tangential impact stiffness against this body, N/m; default: as [contact] gives it."""

    friction_static: Annotated[Real, Field(ge=0, le=10)] | None = None
    """Static friction coefficient against this body; default: [contact]'s."""

    friction_kinetic: Annotated[Real, Field(ge=0, le=10)] | None = None
    """Kinetic friction coefficient against this body, at most its static one (when only the
    static one is given here, [contact]'s kinetic one is capped at it); default: [contact]'s."""

    restitution: Annotated[Real, Field(ge=0.14, le=1)] | None = None
    """Coefficient of restitution e of a face-to-face impact against this body, 0.14 to 1,
    from which its normal dashpot is derived (1: none); with damping_normal, replaces
    [contact]'s normal dashpot. Default: [contact]'s."""

    damping_normal: Annotated[Real, Field(gt=0)] | None = None
    """Normal dashpot coefficient c_N against this body, N·s/m, instead of `restitution`;
    default: [contact]'s normal dashpot."""

    damping_tangential: Annotated[Real, Field(gt=0)] | None = None
    """Tangential dashpot coefficient c_T against this body, N·s/m; default: [contact]'s."""

    @model_validator(mode="after")
    def _consistent_overrides(self) -> "ImpactOverrides":
        mu_s, mu_k = self.friction_static, self.friction_kinetic
        if mu_s is not None and mu_k is not None and mu_k > mu_s:
            raise ValueError(f"friction_kinetic ({mu_k:g}) exceeds friction_static ({mu_s:g}); a sliding "
                             "contact cannot resist more than a sticking one")  # fmt: skip
        if self.restitution is not None and self.damping_normal is not None:
            raise ValueError("give either 'restitution' or 'damping_normal', not both")
        return self

    def overrides(self) -> dict[str, Any]:
        """The impact parameters given, by field name."""
        return {k: getattr(self, k) for k in IMPACT_FIELDS if getattr(self, k) is not None}

    def applied_to(self, contact: Contact) -> Contact:
        """The contact settings of this body's pairs: [contact]'s with the parameters given
        here in their place. A restitution or damping_normal given here replaces [contact]'s
        normal dashpot, whichever way it was given; μ_k is capped at μ_s."""
        given = self.overrides()
        if not given:
            return contact
        merged = contact.model_dump()
        if "restitution" in given or "damping_normal" in given:
            merged["restitution"] = merged["damping_normal"] = None
        merged.update(given)
        merged["friction_kinetic"] = min(merged["friction_kinetic"], merged["friction_static"])
        return Contact.model_validate(merged)


IMPACT_FIELDS = tuple(ImpactOverrides.model_fields)
"""The fields of [contact] a fixed body (an obstacle, a moat wall) may give for itself."""


class Obstacle(ImpactOverrides):
    """A fixed rigid convex body in plan: a wall, a moat wall, a neighbour taken as rigid.
    Its impact parameters, where given, replace [contact]'s for the pairs it is in."""

    name: Name
    """Obstacle name, unique among buildings and obstacles."""

    polygon: Outline
    """Outline: a convex polygon [[X, Y], ...] in global coordinates, m, either orientation."""

    elevation: Annotated[
        Annotated[Real, Tag("level")] | Annotated[tuple[Real, Real], Tag("range")],
        Discriminator(lambda v: "range" if isinstance(v, (list, tuple)) else "level"),
        WithJsonSchema({"anyOf": [{"type": "number"}, {"type": "array", "maxItems": 2, "minItems": 2,
                                                       "prefixItems": [{"type": "number"}, {"type": "number"}]}]}),
    ]
    """Level of the obstacle above the ground, m: one elevation, or [bottom, top] to meet
    every floor whose elevation lies in that range."""

    material: Name
    """Name of the obstacle's material in [materials] (for "auto" impact stiffness)."""

    @field_validator("polygon")
    @classmethod
    def _convex(cls, polygon: list[tuple[float, float]], info: ValidationInfo) -> list[tuple[float, float]]:
        """Convex, returned counter-clockwise; the messages name the obstacle (validated
        before its polygon) rather than a slab."""
        name = info.data.get("name")
        what = f"the outline of obstacle {name!r}" if name else "the obstacle's outline"
        return convex_polygon(polygon, what, "obstacle", "pound models each obstacle as one rigid convex polygon")

    @model_validator(mode="after")
    def _range_ordered(self) -> "Obstacle":
        if isinstance(self.elevation, tuple) and self.elevation[0] > self.elevation[1]:
            raise ValueError(f"elevation range [{self.elevation[0]:g}, {self.elevation[1]:g}] m is reversed")
        return self

    def spans(self, z: float, tolerance: float) -> bool:
        """Whether a floor at elevation z (m) meets this obstacle."""
        if isinstance(self.elevation, tuple):
            return self.elevation[0] - tolerance <= z <= self.elevation[1] + tolerance
        return abs(z - self.elevation) <= tolerance
