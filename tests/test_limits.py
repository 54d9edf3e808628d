"""Resource limits: models that would need more memory, disk or time than is sensible are
refused up front with the estimate and the limit, and the limits can be raised."""

from __future__ import annotations

import importlib

import pytest

import pounding_cli as pound
from pounding_cli.errors import InputError

from conftest import example_doc, load_doc


def test_too_many_storeys_is_refused_with_the_estimate():
    doc = example_doc()
    doc["buildings"][0]["floors"][0]["repeat"] = 500
    doc["buildings"][0]["floors"].append(dict(doc["buildings"][0]["floors"][0]))
    doc["buildings"][0]["floors"].append(dict(doc["buildings"][0]["floors"][0], repeat=1))
    with pytest.raises(InputError, match=r"buildings\[0\]\.floors: 1001 storeys: more than the limit of 1000 .* GiB"):
        pound.describe(load_doc(doc))


def test_tiny_output_interval_is_refused_with_the_estimate():
    doc = example_doc()
    doc["analysis"]["output_interval"] = 1e-9
    with pytest.raises(InputError, match=r"analysis\.dt: the analysis would take .* steps .* more than the limit"):
        pound.describe(load_doc(doc))


def test_limits_can_be_raised_by_the_environment(monkeypatch):
    from pounding_cli import api

    monkeypatch.setenv("POUND_MAX_STOREYS", "3")
    monkeypatch.setenv("POUND_MAX_OUTPUT_GB", "0.5")
    try:
        reloaded = importlib.reload(api)
        assert reloaded.MAX_STOREYS == 3 and reloaded.MAX_OUTPUT_BYTES == 0.5 * 2**30
        with pytest.raises(InputError, match="4 storeys: more than the limit of 3"):
            reloaded.prepare(load_doc(example_doc()))
    finally:
        monkeypatch.delenv("POUND_MAX_STOREYS")
        monkeypatch.delenv("POUND_MAX_OUTPUT_GB")
        importlib.reload(api)
