"""The numpy matrix exponential against scipy's and against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from numpy.testing import assert_allclose

from pounding_cli.solver.expm import expm


@pytest.mark.parametrize("n", [1, 2, 6, 14, 40])
@pytest.mark.parametrize("scale", [1e-3, 0.1, 1.0, 10.0, 300.0])
def test_matches_scipy(n, scale):
    """Random matrices of norms 1e-3 to ~300. Up to scale 10 (the propagators' A·h is ≲ 1):
    1e-12 of the largest entry (measured worst 1.3e-13, with two squarings). At norm 300 (9 squarings, entries up to 1e140, each squaring
    can double a relative rounding error, in scipy's result too): 1e-10."""
    a = np.random.default_rng(n).standard_normal((n, n)) * scale / np.sqrt(n)
    want = scipy.linalg.expm(a)
    tolerance = 1e-12 if scale <= 10 else 1e-10
    assert_allclose(expm(a), want, rtol=0, atol=tolerance * np.abs(want).max())


def test_closed_forms():
    t = 0.7
    rotation = expm(np.array([[0.0, -t], [t, 0.0]]))
    assert_allclose(rotation, [[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]], atol=1e-15)
    nilpotent = expm(np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]))
    assert_allclose(nilpotent, [[1, 1, 0.5], [0, 1, 1], [0, 0, 1]], atol=1e-15)
    assert_allclose(expm(np.diag([-3.0, 0.0, 2.0])), np.diag(np.exp([-3.0, 0.0, 2.0])), rtol=1e-14)
