#!/usr/bin/env python
"""Rebuild every generated part of the docs from the code, or check that none has drifted.

    python docs/build.py                    # rebuild everything in place
    python docs/build.py --check            # rebuild into a temporary copy; exit 1 on any difference
    python docs/build.py docs/sweep.md      # only these pages or generators (names: --list)
    python docs/build.py --list             # the pages, their marked blocks, the generators

Nothing in README.md or docs/ that a command prints, a figure quoted from a run, a table or
an image is typed by hand: a marker (an HTML comment, invisible once rendered) names where it
comes from, and this script reruns it and rewrites the block in place. The markers:

``<!-- run: CMD -->`` before a fenced block
    The block is ``$ CMD`` followed by what CMD prints (stdout and stderr, as in a terminal),
    run by bash in the reader's checkout (below). Options in brackets before the colon,
    comma separated: ``exit=N`` (the exit code it must give, default 0), ``lines=1-20+31-40``
    (show only these lines of the output; "…" marks what is left out), ``stdout`` (show only
    stdout), ``cwd=DIR`` (run in that folder of the checkout; shown as ``$ cd DIR`` first
    unless ``nocd``), ``needs=shared`` (skipped when ``../shared`` is absent).
``<!-- sh -->`` before a fenced block of shell commands
    Each line is run in order and must exit 0; the block itself is not rewritten (it is what
    the reader types). Install and test commands (:data:`NOT_RUN`) are not run.
``<!-- python -->`` / ``<!-- python(output) -->`` before a fenced Python block
    The block is saved as a script and run with ``python script.py`` in the checkout (as a
    reader would run it: a plain script, ``__name__ == "__main__"``). With ``output``, the
    fenced block right after it is rewritten with what the script prints.
``<!-- file: PATH -->`` before a fenced block
    The block is written to PATH in the checkout, for the commands after it to use.
``<!-- from: PATH -->`` before a fenced block
    The block must be a verbatim part of PATH (checked, not rewritten: which part to quote
    is the writer's choice).
``<!-- error-example: OLD => NEW -->`` before a fenced block
    ``inputs/paper_wide_gap.toml`` with OLD replaced by NEW is saved as ``inputs/model.toml``
    and the block is ``$ pound validate model.toml`` with what it prints (exit 2). Options:
    ``strict`` adds ``--strict``; ``exit=0`` expects a valid model and shows what it says on
    stderr (``> /dev/null``): its plausibility warnings.
``<!-- md: NAME ARGS -->`` … ``<!-- /md -->``
    Markdown (a table, say) made by the function NAME of docs/figures.py.
``<!-- fig: NAME ARGS -->VALUE<!-- /fig -->``
    A figure inside a sentence, made by docs/figures.py (from the bench's result files in
    docs/bench/, or from a run).
Any marker takes ``needs=shared`` among its options: it is skipped (and said so) where
``../shared`` is absent, as in a clone without the project's record copies.
``<!-- not-run: REASON -->`` before a fenced block
    A block of commands deliberately not run (a placeholder name, a cluster address), with
    the reason. Every other fenced block that holds a ``$`` prompt or shell commands calling
    ``pound`` must carry one of the markers above: an unmarked transcript is an error.

**The reader's checkout.** The pages run in :data:`PAGES` order, each command of each page in
the order a reader meets it, all in one scratch folder: ``project/``, a copy of the
repository's files, with ``shared/`` beside it (a link to ``../shared`` when that exists).
So an example that needs a file an earlier one did not make, or that overwrites one without
``--force``, fails the build. Paths inside it are shown as ``/tmp/project``.

**Run-dependent output** (timings, and the scratch folder's path) is masked by
:data:`MASKS`, e.g. ``solver … s (… µs/step)``; a timing quoted in prose comes from the
bench's result files through docs/figures.py, never from a run of the build.

**Generated files** (:data:`GENERATORS`): the CLI and model-field references, the report
images, docs/inelastic.md, docs/paper-example.md, docs/floors.md and docs/suites.md are written whole by their scripts, run
in the same checkout. Text files are compared byte for byte; images by what they show
(their signature files in docs/images/, see docs/make_report_images.py), and copied back
only when that changed.

**The check** (``--check``, ``tests/test_docs.py``) does all of this in the scratch folder
and writes nothing: it exits 1 naming each file, block and command whose output differs,
with the difference.
"""

from __future__ import annotations

import argparse
import difflib
import importlib.util
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"
SHOWN_ROOT = "/tmp/project"
"""The checkout's path as the docs show it."""

PAGES = [
    "README.md",
    "docs/user-guide.md",
    "docs/sweep.md",
    "docs/report.md",
    "docs/records/README.md",
    "docs/records/peer-at2.md",
    "docs/records/cosmos.md",
    "docs/records/knet.md",
    "docs/records/miniseed-sac.md",
    "docs/records/plain-text.md",
    "docs/bench.md",
    "docs/validation.md",
    "docs/theory.md",
    "inputs/records/README.md",
]
"""The pages with markers, in the order a reader meets them (README first)."""


@dataclass
class Generator:
    name: str
    command: str
    outputs: list[str]
    """Text files written whole (compared byte for byte)."""
    images: str = ""
    """A glob of images it draws, shown by the signature file among `outputs`."""
    needs_shared: bool = False


GENERATORS = [
    Generator("references", "python docs/generate_reference.py",
              ["docs/reference/cli.md", "docs/reference/model-fields.md"]),
    Generator("report-images", "python docs/make_report_images.py",
              ["docs/images/report-images.json"], images="docs/images/report-*"),
    Generator("inelastic", "python docs/inelastic_examples.py",
              ["docs/inelastic.md", "docs/images/inelastic-images.json"], images="docs/images/inelastic-*"),
    Generator("paper-example", "python docs/paper_studies.py", ["docs/paper-example.md"], needs_shared=True),
    Generator("floors", "python docs/floors_example.py", ["docs/floors.md", "docs/images/floors-images.json"],
              images="docs/images/floors-*"),
    Generator("suites", "python docs/suites_example.py", ["docs/suites.md", "docs/images/suites-images.json"],
              images="docs/images/suites-*"),
    Generator("city", "python docs/city_example.py", ["docs/city.md", "docs/images/city-images.json"],
              images="docs/images/city-*"),
]  # fmt: skip

NOT_RUN = re.compile(r"^(python -m pip install|pip install|python -m pytest|python -m venv|\. \.venv/)")
"""Commands of a ``sh`` block that set up the reader's machine: not run by the build."""

ENV = {
    "COLUMNS": "100",
    "LINES": "50",
    "NO_COLOR": "1",
    "TERM": "dumb",
    "PYTHONUNBUFFERED": "1",
    "TZ": "UTC",
}
UNSET = ("FORCE_COLOR", "PY_COLORS", "CLICOLOR_FORCE", "TERMINAL_WIDTH", "GITHUB_ACTIONS", "JUPYTER_COLUMNS",
         "TTY_COMPATIBLE", "TTY_INTERACTIVE", "POUND_MAX_STEPS", "POUND_MAX_OUTPUT_GB", "POUND_MAX_MEMORY_GB",
         "POUND_MAX_STOREYS")  # fmt: skip

MASKS = [
    # pound run, pound report: the solver's wall time and its cost per step
    (re.compile(r"solver [0-9.]+(e[-+]?\d+)? s \([0-9.]+ µs/step\)"), "solver … s (… µs/step)"),
    (re.compile(r"compile [0-9.]+(e[-+]?\d+)? s"), "compile … s"),
    (re.compile(r"whole run [0-9.]+(e[-+]?\d+)? s"), "whole run … s"),
    # pound sweep: "8 runs in 2.4 s"
    (re.compile(r"(\d+ runs?) in [0-9.]+ s"), r"\1 in … s"),
    # --json documents and CSV/JSON rows: wall times
    (re.compile(r'("(?:solver_wall_time_s|us_per_step|wall_time_s|solver_time_s|compile_time_s|run_time_s)": )'
                r"-?[0-9.]+(e[-+]?\d+)?"), r"\1…"),  # fmt: skip
]
"""Output that changes from run to run, and what the docs show instead."""

MARKER = re.compile(r"<!--\s*([a-z][a-z-]*)(?:\(([^)]*)\))?\s*(?::\s*(.*?))?\s*-->")
FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})(.*)$")
BLOCK_KINDS = ("run", "sh", "python", "file", "from", "error-example", "not-run")
REGION_KINDS = ("md", "fig")


class BuildError(Exception):
    """A block whose command failed, or a page that breaks the rules; names the page and line."""


# --- parsing -----------------------------------------------------------------------------------


@dataclass
class Block:
    """A marked part of a page: the marker, and the span of text it owns."""

    page: str
    line: int
    kind: str
    arg: str
    options: dict[str, str]
    start: int
    """Offset of the first character of the content the build owns."""
    end: int
    body: str
    """The content between start and end, as on the page."""
    info: str = ""
    """The fence's info string (```text) of a fenced block."""
    output: Block | None = None
    """For python(output): the block of its output."""

    @property
    def where(self) -> str:
        return f"{self.page}:{self.line}"

    @property
    def label(self) -> str:
        opts = f"({', '.join(f'{k}={v}' if v else k for k, v in self.options.items())})" if self.options else ""
        return f"{self.kind}{opts}: {self.arg}" if self.arg else f"{self.kind}{opts}"


def _options(text: str | None) -> dict[str, str]:
    out = {}
    for part in (text or "").split(","):
        key, _, value = part.strip().partition("=")
        if key:
            out[key.strip()] = value.strip()
    return out


def _fenced_after(text: str, pos: int, page: str, line: int) -> tuple[int, int, str, int]:
    """(start, end, info, end of the closing fence line) of the fenced block that follows
    position `pos`, with only blank lines between."""
    rest = text[pos:]
    stripped = rest.lstrip("\n \t")
    offset = pos + len(rest) - len(stripped)
    first = stripped.split("\n", 1)[0]
    m = FENCE.match(first)
    if not m:
        raise BuildError(f"{page}:{line}: the marker is not followed by a fenced block")
    fence, info = m.group(2), m.group(3).strip()
    start = offset + len(first) + 1
    close = re.compile(rf"^\s*{re.escape(fence[0])}{{{len(fence)},}}\s*$", re.M)
    c = close.search(text, start)
    if not c:
        raise BuildError(f"{page}:{line}: the fenced block after the marker is not closed")
    end_of_fence = text.find("\n", c.end())
    return start, c.start(), info, len(text) if end_of_fence < 0 else end_of_fence


def parse(text: str, page: str) -> list[Block]:
    """Every marked block of a page, in order."""
    blocks: list[Block] = []
    taken_until = 0
    for m in MARKER.finditer(text):
        if m.start() < taken_until:
            continue
        kind, opts, arg = m.group(1), _options(m.group(2)), (m.group(3) or "").strip()
        line = text.count("\n", 0, m.start()) + 1
        if kind.startswith("/"):
            continue
        if kind in REGION_KINDS:
            closing = f"<!-- /{kind} -->"
            end = text.find(closing, m.end())
            if end < 0:
                raise BuildError(f"{page}:{line}: <!-- {kind}: … --> without its {closing}")
            start = m.end() + 1 if kind == "md" and text.startswith("\n", m.end()) else m.end()
            blocks.append(Block(page, line, kind, arg, opts, start, end, text[start:end]))
            taken_until = end + len(closing)
        elif kind in BLOCK_KINDS:
            start, end, info, after = _fenced_after(text, m.end(), page, line)
            block = Block(page, line, kind, arg, opts, start, end, text[start:end], info)
            taken_until = after
            if kind == "python" and "output" in opts:
                o_start, o_end, o_info, after = _fenced_after(text, after, page, line)
                block.output = Block(page, text.count("\n", 0, o_start), "output", "", {}, o_start, o_end,
                                     text[o_start:o_end], o_info)  # fmt: skip
                taken_until = after
            blocks.append(block)
    return blocks


def unmarked_transcripts(text: str, page: str, blocks: list[Block]) -> list[str]:
    """Fenced blocks that show a `$` prompt or run `pound` from a shell, outside any marker."""
    owned = [(b.start, b.end) for b in blocks] + [(b.output.start, b.output.end) for b in blocks if b.output]
    problems = []
    lines = text.split("\n")
    offset, i = 0, 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if m:
            start = offset + len(lines[i]) + 1
            j, body = i + 1, []
            while j < len(lines) and not re.match(rf"^\s*{re.escape(m.group(2)[0])}{{{len(m.group(2))},}}\s*$", lines[j]):
                body.append(lines[j])
                j += 1
            inside = any(a <= start <= b for a, b in owned)
            info = m.group(3).strip()
            shell = info in ("sh", "bash", "shell", "console")
            prompt = any(ln.startswith("$ ") for ln in body)
            calls = any(re.match(r"^\s*pound\b", ln) for ln in body)
            if not inside and (prompt or (shell and calls)):
                problems.append(f"{page}:{i + 1}: a transcript or shell block without a marker "
                                "(<!-- run: … -->, <!-- sh -->, or <!-- not-run: reason -->)")  # fmt: skip
            offset += sum(len(ln) + 1 for ln in lines[i : j + 1])
            i = j + 1
            continue
        offset += len(lines[i]) + 1
        i += 1
    return problems


# --- the reader's checkout ---------------------------------------------------------------------


def repository_files(root: Path) -> list[Path]:
    """The repository's files as a fresh clone has them (tracked, and new files not ignored)."""
    try:
        out = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=root,
                             capture_output=True, check=True).stdout  # fmt: skip
        return [root / p for p in out.decode().split("\0") if p and (root / p).is_file()]
    except (OSError, subprocess.CalledProcessError):
        skip = {".git", "__pycache__", ".pytest_cache", "build", "dist"}
        return [p for p in root.rglob("*") if p.is_file() and not skip & set(p.relative_to(root).parts)]


def checkout(tmp: Path) -> Path:
    """A copy of the repository at tmp/project, with tmp/shared beside it when ../shared exists."""
    project = tmp / "project"
    for path in repository_files(ROOT):
        target = project / path.relative_to(ROOT)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(path, target)
    if SHARED.is_dir():
        (tmp / "shared").symlink_to(SHARED, target_is_directory=True)
    return project


def environment() -> dict[str, str]:
    """The commands' environment: this one, with a fixed terminal width and no colour, and
    this Python's folder first on PATH, so that `pound` and `python` are the ones this build
    runs with, whether or not its virtual environment is activated."""
    env = {k: v for k, v in os.environ.items() if k not in UNSET}
    env.update(ENV)
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    return env


# --- output ------------------------------------------------------------------------------------


def mask(text: str, project: Path) -> str:
    """Run-dependent output replaced by what the docs show; in a table's row each cell keeps
    its width, so that the row stays aligned."""
    text = text.replace(str(project.resolve()), SHOWN_ROOT).replace(str(project), SHOWN_ROOT)
    out = []
    for line in text.split("\n"):
        if "│" in line:
            line = "│".join(_masked(cell).ljust(len(cell)) for cell in line.split("│"))
        else:
            line = _masked(line)
        out.append(line.rstrip())
    return "\n".join(out).strip("\n")


def _masked(text: str) -> str:
    for pattern, replacement in MASKS:
        text = pattern.sub(replacement, text)
    return text


def select_lines(text: str, spec: str) -> str:
    """Lines `spec` ("1-20+31-40", 1-based) of `text`, with "…" for every gap."""
    lines = text.split("\n")
    keep: list[int] = []
    for part in spec.split("+"):
        a, _, b = part.partition("-")
        lo, hi = int(a), int(b) if b else int(a)
        keep += range(lo - 1, min(hi, len(lines)))
    out, last = [], -1
    for k in sorted(set(keep)):
        if k != last + 1:
            out.append("…")
        out.append(lines[k])
        last = k
    if last != len(lines) - 1:
        out.append("…")
    return "\n".join(out)


# --- running -----------------------------------------------------------------------------------


@dataclass
class State:
    project: Path
    env: dict[str, str]
    figures: object = None
    skipped: list[str] = field(default_factory=list)
    timings: list[tuple[str, float]] = field(default_factory=list)


def shell(command: str, state: State, cwd: Path, timeout: float = 1800) -> tuple[int, str, str]:
    """Exit code and output of a bash command: stdout and stderr interleaved as a terminal
    shows them (Python unbuffered), and no separate stderr."""
    p = subprocess.run(["bash", "-c", command], cwd=cwd, env=state.env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, timeout=timeout)  # fmt: skip
    return p.returncode, p.stdout.decode("utf-8", "replace"), ""


def shell_stdout(command: str, state: State, cwd: Path) -> tuple[int, str, str]:
    """Exit code, stdout and stderr of a bash command, apart."""
    p = subprocess.run(["bash", "-c", command], cwd=cwd, env=state.env, capture_output=True, timeout=1800)
    return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")


def _fail(block: Block, what: str, output: str) -> BuildError:
    tail = "\n".join("    " + ln for ln in output.strip("\n").split("\n")[-15:])
    return BuildError(f"{block.where}: {block.label}\n  {what}\n{tail}")


def needs_shared(block: Block) -> bool:
    return block.options.get("needs") == "shared"


def figures_module(project: Path):
    """docs/figures.py of the checkout, imported."""
    spec = importlib.util.spec_from_file_location("pound_docs_figures", project / "docs" / "figures.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    module.ROOT = project
    return module


def render(block: Block, state: State) -> str | None:
    """The new content of a block (None: the block is left as it is)."""
    project = state.project
    if needs_shared(block) and not (project.parent / "shared").is_dir():
        state.skipped.append(f"{block.where}: {block.label} (needs ../shared, which is absent)")
        return None
    if block.kind == "run":
        cwd = project / block.options.get("cwd", ".")
        run = shell_stdout if "stdout" in block.options else shell
        code, output, _ = run(block.arg, state, cwd)
        expected = int(block.options.get("exit", "0"))
        if code != expected:
            raise _fail(block, f"exited with {code}, expected {expected}", output)
        output = mask(output, project)
        if "lines" in block.options:
            output = select_lines(output, block.options["lines"])
        prompt = f"$ {block.arg}"
        if "cwd" in block.options and "nocd" not in block.options:
            prompt = f"$ cd {block.options['cwd']}\n{prompt}"
        return f"{prompt}\n{output}\n" if output else f"{prompt}\n"
    if block.kind == "sh":
        for line in _commands(block.body):
            if NOT_RUN.match(line):
                continue
            code, output, _ = shell(line, state, project)
            if code != 0:
                raise _fail(block, f"`{line}` exited with {code}", output)
        return None
    if block.kind == "python":
        script = project / f"docs-snippet-{block.line}.py"
        script.write_text(block.body, encoding="utf-8")
        try:  # -P: not the checkout's copy of pounding_cli (numba would compile it afresh) but the installed one
            code, out, err = shell_stdout(f"{sys.executable} -P {script.name}", state, project)
        finally:
            script.unlink()
        if code != 0:
            raise _fail(block, f"the script exited with {code}", out + err)
        if block.output is not None:
            return mask(out, project) + "\n"
        return None
    if block.kind == "file":
        target = project / block.arg
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(block.body, encoding="utf-8")
        return None
    if block.kind == "from":
        source = ROOT / block.arg
        if not source.is_file() or block.body not in source.read_text(encoding="utf-8"):
            raise BuildError(f"{block.where}: {block.label}\n  the block is no longer a verbatim part of {block.arg}")
        return None
    if block.kind == "error-example":
        old, _, new = block.arg.partition(" => ")
        folder = project / "inputs"
        example = (folder / "paper_wide_gap.toml").read_text(encoding="utf-8")
        if old not in example:
            raise BuildError(f"{block.where}: {block.label}\n  {old!r} is not in inputs/paper_wide_gap.toml")
        (folder / "model.toml").write_text(example.replace(old, new, 1), encoding="utf-8")
        expected = int(block.options.get("exit", "2"))
        command = "pound validate model.toml" + (" --strict" if "strict" in block.options else "")
        command += " > /dev/null" if expected == 0 else ""  # a warning: what stderr says, not the description
        code, out, err = shell_stdout(command, state, folder)
        if code != expected:
            raise _fail(block, f"exited with {code}, expected {expected}", out + err)
        return f"$ {command}\n" + mask(err, project) + "\n"
    if block.kind == "not-run":
        if not block.arg:
            raise BuildError(f"{block.where}: <!-- not-run: … --> must say why")
        return None
    if block.kind in ("md", "fig"):
        if state.figures is None:
            state.figures = figures_module(project)
        name, *args = shlex.split(block.arg)
        try:
            value = state.figures.figure(name, *args)
        except state.figures.NeedsShared as exc:
            state.skipped.append(f"{block.where}: {block.label} ({exc})")
            return None
        except Exception as exc:  # noqa: BLE001 - name the block
            raise BuildError(f"{block.where}: {block.label}\n  {type(exc).__name__}: {exc}") from None
        return f"{value.strip()}\n" if block.kind == "md" else str(value)
    raise BuildError(f"{block.where}: unknown marker {block.kind!r}")


def _commands(body: str) -> list[str]:
    """The commands of a shell block: lines joined at a trailing backslash, comments dropped."""
    out, current = [], ""
    for raw in body.split("\n"):
        line = raw.rstrip()
        if line.endswith("\\"):
            current += line[:-1] + " "
            continue
        line = (current + line).strip()
        current = ""
        if line and not line.startswith("#"):
            out.append(line)
    return out


@dataclass
class Change:
    where: str
    label: str
    old: str
    new: str

    def report(self) -> str:
        diff = difflib.unified_diff(self.old.split("\n"), self.new.split("\n"), "in the docs", "now", lineterm="", n=1)
        return f"{self.where}: {self.label}\n  differs from what it gives now:\n" + "\n".join(
            "    " + ln for ln in diff)


def build_page(page: str, state: State, errors: list[str]) -> tuple[str, str, list[Change]]:
    """(old text, new text, changes) of one page, its commands run in `state`'s checkout."""
    text = (ROOT / page).read_text(encoding="utf-8")
    blocks = parse(text, page)
    errors += unmarked_transcripts(text, page, blocks)
    changes, pieces, pos = [], [], 0
    for block in blocks:
        t0 = time.perf_counter()
        try:
            new = render(block, state)
        except BuildError as exc:
            errors.append(str(exc))
            new = None
        except subprocess.TimeoutExpired as exc:
            errors.append(f"{block.where}: {block.label}\n  timed out after {exc.timeout:.0f} s")
            new = None
        state.timings.append((f"{block.where} {block.label}", time.perf_counter() - t0))
        target = block.output or block
        if new is not None and new != target.body:
            changes.append(Change(target.where if target is block else f"{block.where} (output)", block.label,
                                  target.body, new))  # fmt: skip
        if new is not None:
            pieces.append(text[pos : target.start])
            pieces.append(new)
            pos = target.end
    pieces.append(text[pos:])
    return text, "".join(pieces), changes


def run_generator(gen: Generator, state: State, errors: list[str]) -> list[tuple[str, str | bytes, str | bytes]]:
    """Run a generator in the checkout: (path, old, new) of each text output that changed, and
    of each image whose signature changed or that is missing."""
    if gen.needs_shared and not (state.project.parent / "shared").is_dir():
        state.skipped.append(f"generator {gen.name}: {gen.command} (needs ../shared, which is absent)")
        return []
    t0 = time.perf_counter()
    code, out, _ = shell(gen.command, state, state.project, timeout=3600)
    state.timings.append((f"generator {gen.name}", time.perf_counter() - t0))
    if code != 0:
        errors.append(f"generator {gen.name}: `{gen.command}` exited with {code}\n"
                      + "\n".join("    " + ln for ln in out.strip().split("\n")[-15:]))  # fmt: skip
        return []
    changed = []
    for rel in gen.outputs:
        old_path, new_path = ROOT / rel, state.project / rel
        old = old_path.read_text(encoding="utf-8") if old_path.exists() else ""
        new = new_path.read_text(encoding="utf-8") if new_path.exists() else ""
        if old != new:
            changed.append((rel, old, new))
    if gen.images:
        shown = _signatures(ROOT, gen), _signatures(state.project, gen)
        for new_path in sorted(state.project.glob(gen.images)):
            rel = str(new_path.relative_to(state.project))
            if rel.endswith(".json"):
                continue
            if shown[0].get(new_path.name) != shown[1].get(new_path.name) or not (ROOT / rel).exists():
                changed.append((rel, b"", new_path.read_bytes()))
    return changed


def _signatures(root: Path, gen: Generator) -> dict:
    """What each image of a generator shows, from its signature files under `root`."""
    out: dict = {}
    for rel in gen.outputs:
        if rel.endswith(".json") and (root / rel).exists():
            out.update(json.loads((root / rel).read_text(encoding="utf-8")))
    return out


# --- the entry point ---------------------------------------------------------------------------


@dataclass
class Outcome:
    changes: list[str]
    errors: list[str]
    skipped: list[str]
    timings: list[tuple[str, float]]
    written: list[str]

    @property
    def ok(self) -> bool:
        return not self.changes and not self.errors


def build(targets: list[str] | None = None, check: bool = False, keep: Path | None = None) -> Outcome:
    """Rebuild the pages and generators named in `targets` (all by default) in a scratch
    checkout; with `check`, write nothing and report the differences."""
    pages = [p for p in PAGES if not targets or p in targets]
    gens = [g for g in GENERATORS if not targets or g.name in targets]
    unknown = set(targets or []) - set(PAGES) - {g.name for g in GENERATORS}
    if unknown:
        raise SystemExit(f"unknown page or generator: {', '.join(sorted(unknown))} (see --list)")
    changes, errors, written = [], [], []
    with tempfile.TemporaryDirectory(prefix="pound-docs-") as tmp:
        project = checkout(Path(tmp))
        state = State(project, environment())
        new_pages = {}
        for page in pages:
            old, new, page_changes = build_page(page, state, errors)
            changes += [c.report() for c in page_changes]
            if new != old:
                new_pages[page] = new
        outputs = []
        for gen in gens:
            for rel, old, new in run_generator(gen, state, errors):
                outputs.append((rel, new))
                if isinstance(new, str):
                    changes.append(Change(rel, f"written whole by {gen.command}", old, new).report())
                else:
                    changes.append(f"{rel}: the image is missing or shows something else now ({gen.command})")
        if keep is not None:
            shutil.copytree(project, keep, symlinks=True, dirs_exist_ok=True)
        if not check:
            for page, text in new_pages.items():
                (ROOT / page).write_text(text, encoding="utf-8")
                written.append(page)
            for rel, new in outputs:
                target = ROOT / rel
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(new) if isinstance(new, bytes) else target.write_text(new, encoding="utf-8")
                written.append(rel)
    return Outcome(changes, errors, state.skipped, state.timings, written)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)  # fmt: skip
    parser.add_argument("targets", nargs="*", help="pages or generators (default: all; see --list)")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 on any difference")
    parser.add_argument("--list", action="store_true", help="list the pages, their blocks and the generators")
    parser.add_argument("--keep", type=Path, help="copy the scratch checkout here afterwards (to inspect it)")
    parser.add_argument("--timings", action="store_true", help="print how long each block took")
    args = parser.parse_args(argv)
    if args.list:
        for page in PAGES:
            print(page)
            for block in parse((ROOT / page).read_text(encoding="utf-8"), page):
                print(f"  {block.line}: {block.label}")
        for gen in GENERATORS:
            print(f"{gen.name}: {gen.command} -> {', '.join(gen.outputs)}{' ' + gen.images if gen.images else ''}")
        return 0
    t0 = time.perf_counter()
    outcome = build(args.targets, check=args.check, keep=args.keep)
    for line in outcome.skipped:
        print(f"skipped {line}")
    if args.timings:
        for what, seconds in sorted(outcome.timings, key=lambda t: -t[1])[:25]:
            print(f"{seconds:7.1f} s  {what}")
    for line in outcome.errors:
        print(f"ERROR {line}")
    if args.check:
        for line in outcome.changes:
            print(line)
    else:
        for rel in outcome.written:
            print(f"wrote {rel}")
    elapsed = time.perf_counter() - t0
    what = "differences" if args.check else "changes written"
    print(f"{len(outcome.changes)} {what}, {len(outcome.errors)} errors, {len(outcome.skipped)} skipped "
          f"in {elapsed:.0f} s" + ("; run python docs/build.py" if args.check and outcome.changes else ""))  # fmt: skip
    return 0 if (outcome.ok if args.check else not outcome.errors) else 1


if __name__ == "__main__":
    sys.exit(main())
