"""Isolation bearings given as engineers give them (issue 6): any three of K1, K2, Q, F_y and
d_y that fix the bilinear law, resolved by the closed-form relations

    F_y = K1·d_y,    Q = F_y − K2·d_y = (K1 − K2)·d_y,

and nothing else accepted. The expected values below are computed from (K1, K2, d_y) by
these two relations alone, not by pound's resolution; the tolerance is 1e-12 relative:
each resolution is at most three floating-point operations from the given values, so only
rounding (a few ulp) separates them. Rejected sets (too many, too few, not fixing the law,
not a bilinear law) are also checked end to end in tests/invalid/invalid_bearing_*.toml
(exit 2, the file and the fields named, nothing written)."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
from typer.testing import CliRunner

from pounding_cli import InputError, describe, load_model
from pounding_cli.cli import app
from pounding_cli.model import validate_model
from pounding_cli.model.inelastic import BEARING_FIELDS, Bearing

from test_isolation_reference import model_doc

# a lead-rubber bearing: Q = 9 kN on K2 = 0.18 MN/m, yielding at d_y = 5.56 mm (K1 = 10·K2)
K1, K2, DY = 1.8e6, 1.8e5, 9.0e3 / 1.62e6
CLOSED_FORM = {
    "initial_stiffness": K1,
    "post_yield_stiffness": K2,
    "characteristic_strength": (K1 - K2) * DY,
    "yield_force": K1 * DY,
    "yield_displacement": DY,
}
ATTRIBUTES = {"initial_stiffness": "k1", "post_yield_stiffness": "k2", "characteristic_strength": "q",
              "yield_force": "fy", "yield_displacement": "dy"}  # fmt: skip
TIES = {"initial_stiffness", "yield_force", "yield_displacement"}  # F_y = K1·d_y: K2 is free
TRIPLES = [t for t in itertools.combinations(BEARING_FIELDS, 3) if set(t) != TIES]


def test_every_fixing_triple_is_accepted():
    """Of the ten triples of five constants, nine fix the law; the tenth is refused."""
    assert len(TRIPLES) == 9


@pytest.mark.parametrize("triple", TRIPLES, ids=["+".join(BEARING_FIELDS[k] for k in t) for t in TRIPLES])
def test_triple_resolves_to_the_closed_form(triple):
    bearing = Bearing(**{k: CLOSED_FORM[k] for k in triple})
    c = bearing.constants()
    for field, value in CLOSED_FORM.items():
        assert getattr(c, ATTRIBUTES[field]) == pytest.approx(value, rel=1e-12), field
    for field in triple:  # what was given is kept exactly
        assert getattr(c, ATTRIBUTES[field]) == CLOSED_FORM[field]
    # the bilinear relations hold among the resolved constants
    assert c.fy == pytest.approx(c.k1 * c.dy, rel=1e-12)
    assert c.q == pytest.approx(c.fy - c.k2 * c.dy, rel=1e-12)


def test_elastic_perfectly_plastic_bearing():
    """K2 = 0: Q = F_y; fixed by K1 and either strength, or by Q (= F_y) and d_y."""
    for given in ({"initial_stiffness": K1, "post_yield_stiffness": 0.0, "characteristic_strength": 1e4},
                  {"post_yield_stiffness": 0.0, "characteristic_strength": 1e4, "yield_displacement": 1e4 / K1}):  # fmt: skip
        c = Bearing(**given).constants()
        assert (c.k2, c.q) == (0.0, 1e4)
        assert c.fy == pytest.approx(1e4, rel=1e-12) and c.k1 == pytest.approx(K1, rel=1e-12)
        assert c.dy == pytest.approx(1e4 / K1, rel=1e-12)


@pytest.mark.parametrize(
    "given, words",
    [
        ({k: CLOSED_FORM[k] for k in TIES}, "do not fix the bearing: F_y = K1·d_y ties them"),
        (CLOSED_FORM, "given: initial_stiffness, post_yield_stiffness, characteristic_strength, yield_force and "
                      "yield_displacement (too many"),
        ({"initial_stiffness": K1, "post_yield_stiffness": K2}, "given: initial_stiffness and post_yield_stiffness (too few)"),
        ({}, "given: none (too few)"),
        ({"post_yield_stiffness": 0.0, "characteristic_strength": 1e4, "yield_force": 1e4}, "with K2 = 0, F_y = Q"),
        ({"initial_stiffness": K1, "post_yield_stiffness": K1, "yield_displacement": DY}, "needs K1 > K2 ≥ 0"),
        ({"post_yield_stiffness": K2, "characteristic_strength": 2e4, "yield_force": 1e4}, "are inconsistent"),
        ({"characteristic_strength": 2e4, "yield_force": 1e4, "yield_displacement": DY}, "K2 = -1.8e+06 N/m"),
        ({"initial_stiffness": K1, "characteristic_strength": 1e5, "yield_displacement": DY}, "are inconsistent"),
    ],
    ids=["K1+Fy+dy", "all five", "two", "none", "K2=0+Q+Fy", "K2=K1", "Q>Fy", "Q>Fy via dy", "Q>K1·dy"],
)
def test_refused_with_the_fields_named(given, words):
    with pytest.raises(ValueError) as info:
        Bearing(**given)
    assert words in str(info.value)


def test_lead_rubber_specification_gives_the_same_members(tmp_path):
    """Q + K2 + d_y (no K1) assembles the same isolators as the K1 + K2 + Q it resolves to:
    stiffness, yield force and post-yield ratio equal to rounding."""
    from pounding_cli.api import prepare

    systems = []
    for given in (("initial_stiffness", "post_yield_stiffness", "characteristic_strength"),
                  ("characteristic_strength", "post_yield_stiffness", "yield_displacement")):  # fmt: skip
        doc = model_doc("auto")
        doc["bearings"]["lrb"] = {k: CLOSED_FORM[k] for k in given}
        (tmp_path / "pulse.txt").write_text("0\n1\n0\n")
        systems.append(prepare(validate_model(doc, tmp_path / "model.toml")).system)
    a, b = (s.members for s in systems)
    for name in ("k0", "kh", "fh"):
        np.testing.assert_allclose(getattr(b, name), getattr(a, name), rtol=1e-12, err_msg=name)
    np.testing.assert_allclose(a.k0, K1, rtol=1e-12)
    np.testing.assert_allclose(a.fh, (1 - K2 / K1) * K1 * DY, rtol=1e-12)


def test_validate_shows_the_resolved_constants(tmp_path):
    """`pound validate` (text and --json) shows K1, K2, Q, F_y and d_y and what was given."""
    doc = model_doc("auto")
    doc["bearings"]["lrb"] = {k: CLOSED_FORM[k] for k in ("characteristic_strength", "post_yield_stiffness",
                                                           "yield_displacement")}  # fmt: skip
    (tmp_path / "pulse.txt").write_text("0\n1\n0\n")
    path = tmp_path / "model.json"
    path.write_text(json.dumps(doc))
    info = describe(load_model(path))
    [b] = info["bearings"]
    assert b["name"] == "lrb"
    assert b["given"] == ["post_yield_stiffness", "characteristic_strength", "yield_displacement"]
    for key, field in (("initial_stiffness_N_per_m", "initial_stiffness"), ("post_yield_stiffness_N_per_m",
                       "post_yield_stiffness"), ("characteristic_strength_N", "characteristic_strength"),
                       ("yield_force_N", "yield_force"), ("yield_displacement_m", "yield_displacement")):  # fmt: skip
        assert b[key] == pytest.approx(CLOSED_FORM[field], rel=1e-12), key
    result = CliRunner().invoke(app, ["validate", str(path), "--json"])
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["bearings"] == info["bearings"]
    text = CliRunner().invoke(app, ["validate", str(path)]).stdout
    assert ("bearing lrb: K1 = 1.8 MN/m, K2 = 0.18 MN/m, Q = 9 kN, F_y = 10 kN, d_y = 5.556 mm "
            "(given K2, Q, d_y; elliptical)") in " ".join(text.split())


def test_refused_bearing_names_the_file_and_field(tmp_path):
    doc = model_doc("auto")
    doc["bearings"]["lrb"] = {"post_yield_stiffness": K2, "characteristic_strength": 9e3}
    with pytest.raises(InputError) as info:
        validate_model(doc, tmp_path / "model.toml")
    assert "model.toml" in str(info.value) and "bearings.lrb: give exactly three" in str(info.value)
