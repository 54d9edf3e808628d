"""The docs agree with the code.

- every page's marked blocks, generated pages and images equal a fresh rebuild by
  docs/build.py (the slow check; its parts that need no run are checked fast too);
- the mechanism itself: a changed block is found and named, run-dependent output is masked;
- every command has a help text and is documented in the CLI reference and the user guide;
- every field of every input model is in the model-fields reference;
- the TOML blocks of the user guide parse.
"""

from __future__ import annotations

import importlib.util
import re
import sys
import tomllib
import typing
from pathlib import Path

import pytest
import typer
from pydantic import BaseModel

import pounding_cli
from pounding_cli.cli import app
from pounding_cli.model import PoundModel

REPO = Path(__file__).resolve().parents[1]
DOCS = REPO / "docs"
GUIDE = DOCS / "user-guide.md"
REGENERATE = "run python docs/build.py references"


def _module(name: str):
    spec = importlib.util.spec_from_file_location(name, DOCS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while the class is built
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def generator():
    return _module("generate_reference")


@pytest.fixture(scope="module")
def build():
    return _module("build")


def _blocks(text: str, language: str) -> list[tuple[int, str, str]]:
    """(line number, marker comment or "", body) of every fenced block in `language`."""
    out = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        if lines[i].strip() == f"```{language}":
            start = i
            body = []
            i += 1
            while i < len(lines) and lines[i].strip() != "```":
                body.append(lines[i])
                i += 1
            before = [ln.strip() for ln in lines[:start] if ln.strip()]
            marker = before[-1] if before and before[-1].startswith("<!--") else ""
            out.append((start + 1, marker, "\n".join(body) + "\n"))
        i += 1
    return out


# --- (a) generated references ----------------------------------------------------------------


def test_generated_references_are_up_to_date(build):
    """The CLI and model-field references, as docs/build.py rebuilds them (fast: no runs)."""
    outcome = build.build(["references"], check=True)
    assert outcome.ok, "\n".join(outcome.errors + outcome.changes) + f"\n{REGENERATE}"


def test_generation_is_deterministic(generator):
    assert generator.cli_markdown() == generator.cli_markdown()
    assert generator.model_fields_markdown() == generator.model_fields_markdown()
    assert "\x1b" not in generator.cli_markdown(), "escape codes in the CLI reference"


def test_check_mode_reports_stale_files(generator, tmp_path, monkeypatch):
    monkeypatch.setattr(generator, "MODEL_FIELDS", tmp_path / "model-fields.md")
    monkeypatch.setattr(generator, "CLI", tmp_path / "cli.md")
    monkeypatch.setattr(generator, "REFERENCE", tmp_path)
    monkeypatch.setattr(generator, "DOCS", tmp_path)
    assert generator.main(["--check"]) == 1
    assert generator.main([]) == 0
    assert generator.main(["--check"]) == 0
    (tmp_path / "cli.md").write_text("stale\n", encoding="utf-8")
    assert generator.main(["--check"]) == 1


# --- (b) commands ----------------------------------------------------------------------------


def _commands() -> dict[str, typing.Any]:
    group = typer.main.get_command(app)
    return dict(group.commands)


def test_every_command_has_help_and_is_documented():
    cli_md = (DOCS / "reference" / "cli.md").read_text(encoding="utf-8")
    guide = GUIDE.read_text(encoding="utf-8")
    commands = _commands()
    assert {"validate", "run", "schema"} <= set(commands)
    for name, command in commands.items():
        assert (command.help or "").strip(), f"command {name!r} has no help text"
        assert f"## `pound {name}`" in cli_md, f"pound {name} is not in docs/reference/cli.md: {REGENERATE}"
        assert f"pound {name}" in guide, f"pound {name} is not described in docs/user-guide.md"


def test_every_option_is_in_the_user_guide():
    guide = GUIDE.read_text(encoding="utf-8")
    group = typer.main.get_command(app)
    params = [(None, p) for p in group.params]
    params += [(name, p) for name, c in group.commands.items() for p in c.params]
    for command, param in params:
        for flag in [*param.opts, *param.secondary_opts]:
            if flag.startswith("--") and flag != "--help":
                where = f"pound {command}" if command else "pound"
                assert f"`{flag}" in guide or f"{flag}`" in guide or f"/{flag}" in guide, (
                    f"option {flag} of {where} is not mentioned in docs/user-guide.md"
                )


# --- (c) model fields ------------------------------------------------------------------------


def _models(cls: type[BaseModel], seen: dict[str, type[BaseModel]] | None = None) -> dict[str, type[BaseModel]]:
    """Every pydantic model reachable from `cls` through its fields' annotations."""
    seen = {} if seen is None else seen
    if cls.__name__ in seen:
        return seen
    seen[cls.__name__] = cls

    def walk(tp: typing.Any) -> None:
        if isinstance(tp, type) and issubclass(tp, BaseModel):
            _models(tp, seen)
        for arg in typing.get_args(tp):
            walk(arg)

    for info in cls.model_fields.values():
        walk(info.annotation)
    return seen


def _reference_sections(text: str) -> dict[str, str]:
    """Anchor id -> the text of that section of model-fields.md."""
    parts = re.split(r'<a id="([^"]+)"></a>', text)
    return {parts[i]: parts[i + 1] for i in range(1, len(parts) - 1, 2)}


def test_every_model_field_is_in_the_reference():
    text = (DOCS / "reference" / "model-fields.md").read_text(encoding="utf-8")
    sections = _reference_sections(text)
    models = _models(PoundModel)
    exported = {
        name: obj
        for name in pounding_cli.model.__all__
        if isinstance(obj := getattr(pounding_cli.model, name), type) and issubclass(obj, BaseModel)
    }
    assert set(exported) <= set(models), f"models not reachable from PoundModel: {set(exported) - set(models)}"
    for name, model in models.items():
        section = sections.get(name.lower())
        assert section is not None, f"no section for {name} in docs/reference/model-fields.md: {REGENERATE}"
        for field_name, info in model.model_fields.items():
            key = info.alias or field_name
            assert f"| `{key}` |" in section, (
                f"{name}.{key} is not in docs/reference/model-fields.md: {REGENERATE}"
            )
            assert (info.description or "").strip(), f"{name}.{key} has no description"


def test_bounds_render_the_binding_limit(generator):
    """A number given both an exclusive and an inclusive bound (pydantic: a positive type
    with ge=1) is documented by the one that binds; at a tie, the exclusive one."""
    bounds = generator._bounds
    assert bounds({"exclusiveMinimum": 0, "minimum": 1.0, "maximum": 1e12}, "mass") == "1 ≤ mass ≤ 1e+12"
    assert bounds({"exclusiveMinimum": 2, "minimum": 1}, "x") == "> 2"
    assert bounds({"exclusiveMinimum": 1, "minimum": 1}, "x") == "> 1"
    assert bounds({"maximum": 5, "exclusiveMaximum": 3}, "x") == "< 3"
    assert bounds({"minimum": 0, "exclusiveMaximum": 0.5}, "ν") == "0 ≤ ν < 0.5"


@pytest.mark.parametrize(
    "model, field, low, rendered",
    [("Floor", "mass", 1.0, "1 ≤ mass ≤ 1e+12"), ("Floor", "mass_per_area", 0.01, "0.01 ≤ mass_per_area ≤ 1e+09"),
     ("Floor", "rotational_inertia", 1e-3, "0.001 ≤ rotational_inertia ≤ 1e+18"),
     ("Isolation", "mass", 1.0, "1 ≤ mass ≤ 1e+12")],
)  # fmt: skip
def test_documented_lower_bound_is_the_enforced_one(generator, model, field, low, rendered):
    """The reference row states the bound the model enforces: `low` passes, just below fails."""
    from pydantic import TypeAdapter, ValidationError

    from pounding_cli.model import Floor
    from pounding_cli.model.inelastic import Isolation

    cls = {"Floor": Floor, "Isolation": Isolation}[model]
    adapter = TypeAdapter(cls.model_fields[field].annotation)
    assert adapter.validate_python(low) == low
    with pytest.raises(ValidationError):
        adapter.validate_python(low * (1 - 1e-9))
    text = (DOCS / "reference" / "model-fields.md").read_text(encoding="utf-8")
    assert f"| `{field}` | number | not set | {rendered} |" in text


# --- (d), (e) TOML blocks of the user guide ---------------------------------------------------


def _toml_blocks():
    return _blocks(GUIDE.read_text(encoding="utf-8"), "toml")


def test_every_toml_block_parses():
    blocks = _toml_blocks()
    assert blocks, "docs/user-guide.md has no TOML blocks"
    for line, _, body in blocks:
        try:
            tomllib.loads(body)
        except tomllib.TOMLDecodeError as exc:
            pytest.fail(f"docs/user-guide.md line {line}: TOML block does not parse: {exc}")


# --- docs/build.py: the check, and the mechanism ----------------------------------------------


def test_pages_follow_the_rules(build):
    """Fast, without running anything: every page's markers parse, every transcript or shell
    block carries a marker, and every block quoted from a file is verbatim."""
    problems = []
    for page in build.PAGES:
        text = (REPO / page).read_text(encoding="utf-8")
        try:
            blocks = build.parse(text, page)
        except build.BuildError as exc:
            problems.append(str(exc))
            continue
        problems += build.unmarked_transcripts(text, page, blocks)
        for block in blocks:
            if block.kind == "from":
                source = REPO / block.arg
                if not source.is_file() or block.body not in source.read_text(encoding="utf-8"):
                    problems.append(f"{block.where}: no longer a verbatim part of {block.arg}")
    assert not problems, "\n".join(problems)


def test_every_page_is_built():
    """README.md and every Markdown page under docs/ is either in build.PAGES (its marked
    blocks rebuilt) or written whole by one of build.GENERATORS (docs/bench/ holds the
    bench's own result files, which the pages quote)."""
    build = _module("build")
    generated = {out for gen in build.GENERATORS for out in gen.outputs}
    pages = {"README.md", *(str(p.relative_to(REPO)) for p in DOCS.rglob("*.md"))}
    pages = {p for p in pages if not p.startswith("docs/bench/")}
    missing = sorted(pages - set(build.PAGES) - generated)
    assert not missing, f"pages the docs build does not cover: {missing}"


PAGE = """# A page

<!-- run: echo "pound 0.1.0" -->
```text
$ echo "pound 0.1.0"
pound 0.0.9
```

<!-- run: printf 'solver 0.0123 s (4.56 µs/step)\\n│ solver 0.5 s (1.2 µs/step); compile 0.3 s │\\n' -->
```text
```

Prose with a figure: <!-- fig: version -->9.9<!-- /fig --> and no marker below.

```sh
pound run x.toml
```
"""


def test_check_names_the_page_the_block_and_the_command(build, tmp_path, monkeypatch):
    """A block whose command now prints something else is reported with its page, line and
    command, and the difference; masks make timings and table cells stable; an unmarked
    shell block is an error."""
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "figures.py").write_text((DOCS / "figures.py").read_text(encoding="utf-8"), encoding="utf-8")
    (tmp_path / "page.md").write_text(PAGE, encoding="utf-8")
    monkeypatch.setattr(build, "ROOT", tmp_path)
    state = build.State(tmp_path, build.environment())
    errors: list[str] = []
    old, new, changes = build.build_page("page.md", state, errors)
    reports = [c.report() for c in changes]
    assert reports[0].startswith('page.md:3: run: echo "pound 0.1.0"\n  differs from what it gives now:')
    assert "-pound 0.0.9" in reports[0] and "+pound 0.1.0" in reports[0]
    assert "solver … s (… µs/step)\n│ solver … s (… µs/step); compile … s       │" in new
    assert f"figure: <!-- fig: version -->{pounding_cli.__version__}<!-- /fig -->" in new
    assert errors == ["page.md:15: a transcript or shell block without a marker (<!-- run: … -->, <!-- sh -->, "
                      "or <!-- not-run: reason -->)"]  # fmt: skip
    _, again, changes = build.build_page("page.md", state, [])
    assert again == new and len(changes) == 3, "rebuilding in place must leave the text as the first build wrote it"


def test_a_failing_command_is_an_error_naming_it(build, tmp_path, monkeypatch):
    (tmp_path / "page.md").write_text("<!-- run(exit=2): false -->\n```text\n```\n", encoding="utf-8")
    monkeypatch.setattr(build, "ROOT", tmp_path)
    errors: list[str] = []
    build.build_page("page.md", build.State(tmp_path, build.environment()), errors)
    assert errors and errors[0].startswith("page.md:1: run(exit=2): false\n  exited with 1, expected 2")


def test_what_needs_shared_is_skipped_without_it(build, tmp_path, monkeypatch):
    """A block marked needs=shared, and a figure of a record kept in ../shared, are skipped and
    listed, not failed, where ../shared is absent (a clone on its own)."""
    project = tmp_path / "project"
    (project / "docs").mkdir(parents=True)
    (project / "docs" / "figures.py").write_text((DOCS / "figures.py").read_text(encoding="utf-8"), encoding="utf-8")
    (project / "page.md").write_text("<!-- run(needs=shared): false -->\n```text\n```\n\n"
                                     "<!-- fig: arias ../shared/records/x.AT2 '' -->1<!-- /fig -->\n",
                                     encoding="utf-8")  # fmt: skip
    monkeypatch.setattr(build, "ROOT", project)
    state = build.State(project, build.environment())
    errors: list[str] = []
    old, new, changes = build.build_page("page.md", state, errors)
    assert not errors and not changes and new == old
    assert [line.split(" (")[0] for line in state.skipped] == ["page.md:1: run(needs=shared): false",
                                                               "page.md:5: fig: arias ../shared/records/x.AT2 ''"]  # fmt: skip


@pytest.mark.slow
def test_the_docs_are_what_the_code_gives():
    """`python docs/build.py --check`: every transcript, figure, table, generated page and
    image of README.md and docs/ is what the code gives now, the examples of every page run in
    order in one scratch checkout (a few minutes; the paper's Kobe studies are skipped where
    ../shared is absent)."""
    build = _module("build")
    outcome = build.build(check=True)
    report = "\n".join(outcome.errors + outcome.changes)
    assert outcome.ok, f"{report}\n{len(outcome.changes)} differences, {len(outcome.errors)} errors: run python docs/build.py"
