"""Statistics of a quantity over a suite's records, and the probability of pounding.

For the values x_1 … x_n of one quantity over the records (the required separation of one
pair, or a peak), the lognormal fit is the maximum-likelihood one (scipy.stats.lognorm.fit
with loc = 0):

    θ = exp(mean ln x_i)            the median, in the unit of x
    β = √(mean (ln x_i − ln θ)²)    the lognormal dispersion (dimensionless)
    x_84 = θ·e^β                    the 84th percentile (one β above the median)

taken over the positive values (n⁺ of the n); a pair that never comes closer than it is at
rest has required ≤ 0 under a record and counts as never pounding.

The pounding fragility of a pair is the probability that a record of the suite makes it
meet at a gap g (m), i.e. that its required separation R exceeds g:

    empirical:  P(g) = #{i : R_i > g} / n
    fitted:     P(g) = (n⁺/n)·Φ(ln(θ/g)/β)          (g > 0; n⁺/n at g ≤ 0)

with Φ the standard normal distribution function (β = 0: a step at θ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Lognormal:
    """The lognormal fit of a sample: median θ, dispersion β, 84th percentile, n⁺ of n."""

    median: float
    beta: float
    n_positive: int
    n: int

    @property
    def p84(self) -> float:
        return self.median * math.exp(self.beta) if math.isfinite(self.median) else math.nan

    def as_dict(self) -> dict[str, float | int | None]:
        finite = lambda v: v if math.isfinite(v) else None  # noqa: E731
        return {"median": finite(self.median), "beta": finite(self.beta), "p84": finite(self.p84),
                "n_positive": self.n_positive, "n": self.n}  # fmt: skip


def fit_lognormal(values: np.ndarray) -> Lognormal:
    """The maximum-likelihood lognormal fit of the positive finite `values` (NaN are failed
    cases, left out of n too); θ and β NaN when none is positive."""
    x = np.asarray(values, dtype=np.float64)
    x = x[~np.isnan(x)]
    positive = x[np.isfinite(x) & (x > 0)]
    if positive.size == 0:
        return Lognormal(math.nan, math.nan, 0, int(x.size))
    logs = np.log(positive)
    return Lognormal(float(np.exp(logs.mean())), float(logs.std()), int(positive.size), int(x.size))


def empirical_exceedance(values: np.ndarray, gaps: np.ndarray) -> np.ndarray:
    """Fraction of the (non-NaN) `values` greater than each gap of `gaps`."""
    x = np.asarray(values, dtype=np.float64)
    x = np.sort(x[~np.isnan(x)])
    if x.size == 0:
        return np.full(np.shape(gaps), np.nan)
    return (x.size - np.searchsorted(x, np.asarray(gaps, dtype=np.float64), side="right")) / x.size


def fitted_exceedance(fit: Lognormal, gaps: np.ndarray) -> np.ndarray:
    """The fitted probability that R exceeds each gap (module docstring)."""
    from scipy.special import ndtr

    g = np.asarray(gaps, dtype=np.float64)
    if fit.n == 0 or not math.isfinite(fit.median):
        return np.zeros_like(g) if fit.n else np.full_like(g, np.nan)
    share = fit.n_positive / fit.n
    with np.errstate(divide="ignore"):
        z = np.log(fit.median / np.where(g > 0, g, np.nan))
    if fit.beta > 0:
        p = ndtr(z / fit.beta)
    else:
        p = (z > 0).astype(np.float64)
    return np.where(g > 0, share * p, share)


def gap_grid(values: np.ndarray, points: int = 201) -> np.ndarray:
    """Gaps (m) at which a fragility is tabulated: 0 to 1.5 × the largest value."""
    x = np.asarray(values, dtype=np.float64)
    top = float(np.nanmax(x[np.isfinite(x)])) if np.isfinite(x).any() else 0.0
    return np.linspace(0.0, 1.5 * top if top > 0 else 1.0, points)
