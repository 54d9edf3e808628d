"""The repository's own files: LICENSE and CITATION.cff agree with pyproject.toml."""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]


def _project_version() -> str:
    """The version pyproject.toml gives: its own, or the attribute it names (dynamic)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    if "version" in project["project"]:
        return project["project"]["version"]
    attr = project["tool"]["setuptools"]["dynamic"]["version"]["attr"]  # pounding_cli.__version__
    module, _, name = attr.rpartition(".")
    tree = ast.parse((ROOT / module.replace(".", "/") / "__init__.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == name for t in node.targets):
            return ast.literal_eval(node.value)
    raise AssertionError(f"{attr} not found")


def test_citation_cff_parses_and_names_the_version_and_the_paper() -> None:
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert cff["cff-version"] == "1.2.0"
    assert cff["type"] == "software"
    assert str(cff["version"]) == _project_version(), "CITATION.cff's version differs from pyproject's"
    assert cff["license"] == "MIT"
    for key in ("message", "title", "authors"):  # required by CFF 1.2.0
        assert cff[key], key
    paper = cff["references"][0]
    assert paper["type"] == "conference-paper"
    assert [a["family-names"] for a in paper["authors"]] == ["Polycarpou", "Komodromos"]
    assert paper["year"] == 2013 and "COMPDYN 2013" in paper["collection-title"]
    assert "pounding on the 3D dynamic response of buildings" in " ".join(paper["title"].split())


def test_license_is_mit_as_pyproject_says() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert project["project"]["license"] == {"text": "MIT"}
    assert text.startswith("MIT License\n")
    assert "Copyright (c) 2026 the pound authors" in text
