"""The `pound` command line: parses, calls the Python API, prints. Nothing else.

Exit codes: 0 success; 1 the analysis ran but failed (partial results kept and marked);
2 bad input or usage. `--json` output goes to stdout; progress and messages to stderr.
"""

from __future__ import annotations

import json
import os
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any, Iterator

import typer
from rich.console import Console, ConsoleDimensions
from rich.markup import escape
from rich.table import Table

from . import __version__
from .atomic import write_text
from .errors import InputError, PoundError

app = typer.Typer(no_args_is_help=True, pretty_exceptions_enable=False)


def _examples(*commands: str) -> str:
    """The end of a command's --help: its examples, one command a line."""
    return "Examples:\n\n" + "\n\n".join(f"  {c}" for c in commands)


def _no_python_types(display: Any) -> Any:
    """typer's help prints each parameter's Python type (<bool>, <path>, <list[Path]>): pound's
    name what they take by their metavar (FILE, DIR, N, URL), shown in its place; an argument's
    metavar is its name already, and a flag takes nothing."""

    def display_type_rich(self: Any, ctx: Any) -> str | None:
        if isinstance(self, typer.core.TyperArgument) or (getattr(self, "is_flag", False) and self.metavar is None):
            return None
        return display(self, ctx)

    return display_type_rich


for _kind in ("TyperOption", "TyperArgument"):  # absent from another typer: its help stays as it prints it
    if hasattr(getattr(typer.core, _kind, None), "display_type_rich"):
        _cls = getattr(typer.core, _kind)
        _cls.display_type_rich = _no_python_types(_cls.display_type_rich)

PIPE_WIDTH = 10_000
"""Columns of a console that is not a terminal (a pipe, a file): wider than any table pound
prints, so that a table is as wide as its content and never cut or wrapped to 80 columns."""


class _Console(Console):
    """A rich console at the terminal's width, or at PIPE_WIDTH when it writes to a pipe or a
    file, whatever COLUMNS says (checked at each print: the streams may be replaced, as tests
    do)."""

    @property
    def size(self) -> ConsoleDimensions:
        size = Console.size.fget(self)  # type: ignore[attr-defined]
        return size if self.is_terminal else ConsoleDimensions(PIPE_WIDTH, size.height)  # COLUMNS too: no cut

    @size.setter
    def size(self, new_size: tuple[int, int]) -> None:
        Console.size.fset(self, new_size)  # type: ignore[attr-defined]


# plain lines are never hard-wrapped (a script reading stdout sees each one on its line);
# tables are printed with soft_wrap=False, at the terminal's width, or whole to a pipe or file
out = _Console(highlight=False, soft_wrap=True)
# messages are never hard-wrapped: a script that greps stderr sees each one on its line
err = _Console(stderr=True, highlight=False, soft_wrap=True)

ModelArg = Annotated[Path, typer.Argument(metavar="FILE", help="Model file (.toml or .json).", show_default=False)]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print one JSON document to stdout instead of tables.")]
StrictOpt = Annotated[
    bool, typer.Option("--strict", help="Plausibility warnings (a value legal but almost certainly wrong) are errors: exit 2.")
]


@contextmanager
def reported() -> Iterator[None]:
    """Turn pound's errors into a message on stderr and their exit code; never a traceback."""
    from .interrupts import InterruptedAfterWriting, die_by

    try:
        yield
    except PoundError as exc:
        err.print(str(exc), markup=False)
        raise typer.Exit(exc.exit_code) from None
    except InterruptedAfterWriting as exc:  # the result file is complete: end as the signal asks
        die_by(exc.signum)
    except KeyboardInterrupt:
        err.print("interrupted", markup=False)
        raise typer.Exit(1) from None
    except Exception as exc:  # a bug in pound: say so in one paragraph, keep details on demand
        if os.environ.get("POUND_DEBUG"):
            raise
        err.print(
            f"internal error: {type(exc).__name__}: {exc}. This is a bug in pound; please report "
            "it with the model file (set POUND_DEBUG=1 to see the traceback).",
            markup=False,
        )
        raise typer.Exit(1) from None


def _version(show: bool) -> None:
    if show:
        out.print(f"pound {__version__}", markup=False)
        raise typer.Exit()


@app.callback(
    help="Simulate earthquake-induced pounding between adjacent buildings in 3D.\n\n"
    "Exit codes: 0 success, 1 the analysis failed (partial results kept and marked), "
    "2 bad input or usage. Shell completion: pound --install-completion.",
    epilog=_examples("pound validate inputs/paper_pounding.toml", "pound run inputs/paper_pounding.toml -o out.h5"),
)
def main_options(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Print the version and exit.")
    ] = False,
) -> None:
    """pound's global options."""


@app.command(
    help="Check an input file and print what it resolves to.\n\n"
    "A model: per building, floor masses, periods and participating mass, Rayleigh "
    "coefficients and its time-step limit; the contact candidates and their limit; the record; "
    "the time step, which limit sets it and the steps the integrator will take. A record "
    "definition (components L and T, no buildings): what `pound record` prints of it. A sweep "
    "file (it names a base model): every case checked and listed, as `pound sweep --dry-run` "
    "lists them. --json prints the same as one JSON document.",
    epilog=_examples("pound validate inputs/paper_pounding.toml", "pound validate model.toml --json --strict"),
)
def validate(
    file: Annotated[Path, typer.Argument(metavar="FILE", help="Model, record definition or sweep file (.toml or .json).", show_default=False)],
    json_: JsonOpt = False,
    strict: StrictOpt = False,
    plot: Annotated[
        Path | None,
        typer.Option("--plot", metavar="FILE", help="A model: also draw its geometry at rest, a plan with the gaps "
                     "dimensioned and an elevation of the floor levels side by side (.png, .pdf, .svg)."),
    ] = None,
) -> None:
    """Check a model, record definition or sweep file and print what it resolves to."""
    from .model import read_document
    from .model.load import document_kind

    with reported():
        data = read_document(file)
        kind = document_kind(data)
        if plot is not None and kind != "model":
            raise InputError(f"--plot draws a model's geometry at rest, and this is a {kind} file"
                             + ("; pound record --plot draws a record" if kind == "record" else ""), file=file)  # fmt: skip
        if kind == "record":
            _validate_record(file, data, json_)
        elif kind == "sweep":
            _validate_sweep(file, data, json_, strict)
        else:
            _validate_model(file, data, json_, strict, plot)
    if plot is not None:
        err.print(f"wrote {plot}", markup=False)


def _warn(warnings: list[dict[str, str]], strict: bool) -> None:
    """Print plausibility warnings on stderr, one `FILE: field: message` line each; with
    --strict raise them as the error (exit 2) instead."""
    from .plausibility import Notice, strict_error

    if strict and warnings:
        raise strict_error([Notice(**w) for w in warnings])
    for w in warnings:
        err.print(f"{w['file']}: {w['field']}: {w['message']}", markup=False)


def _validate_model(file: Path, data: dict[str, Any], json_: bool, strict: bool, plot: Path | None) -> None:
    from .api import describe_scene, prepare
    from .model import validate_model

    scene = prepare(validate_model(data, file))
    info = describe_scene(scene)
    _warn(info["warnings"], strict)
    if plot is not None:
        from .gap.rest_plot import rest_figure
        from .outputs import refuse_inputs
        from .report.style import save_figure

        refuse_inputs(plot, [(file, "the model being validated")], "another file for the plot (--plot)")
        save_figure(rest_figure(scene.system, scene.loaded.model.all_obstacles(), info["contact"]), plot)
    if json_:
        print(json.dumps(info, indent=2))
    else:
        _print_description(info)


def _validate_record(file: Path, data: dict[str, Any], json_: bool) -> None:
    from .model.record import validate_record
    from .records.inspect import describe_definition
    from .records.summary import summarise

    summary = summarise(describe_definition(validate_record(data, file), file)).model_dump(mode="json")
    if json_:
        print(json.dumps(summary, indent=2, ensure_ascii=False))
    else:
        _print_record(summary)


def _validate_sweep(file: Path, data: dict[str, Any], json_: bool, strict: bool) -> None:
    from .model import validate_sweep
    from .sweep import run_sweep
    from .sweep.progress import print_cases

    outcome = run_sweep(validate_sweep(data, file), dry_run=True, strict=strict)
    for line in outcome.warnings:
        err.print(line, markup=False)
    if json_:
        print(json.dumps([outcome.rows[i] for i in outcome.selected], indent=2, ensure_ascii=False))
    else:
        print_cases(out, outcome)


@app.command(
    help="How far apart must the buildings be: the separation each contact candidate needs.\n\n"
    "Runs the model once with contact off and, for each candidate pair and level, finds the smallest "
    "separation along the direction of its clear distance at rest at which the moving outlines never "
    "meet over the record (exact for convex outlines: a ray cast on their Minkowski difference at "
    "every sample, crests refined between samples), the time of closest approach and the margin "
    "(gap − required). Beside it, the code-style estimates ABS, SRSS and DDC from the peak "
    "displacements of the facing edges, each with its ratio to the exact value. -o writes them "
    "to HDF5 (group /gap), --plot draws the governing pair's approach history.\n\n"
    "With --suite, every record of a suite (a built-in FEMA P695 set, far-field or near-field, or a "
    "suite file), in each orientation, is a case run in parallel (--jobs, --scheduler as pound sweep) "
    "into the folder -o (default MODEL-SUITE/), resumably; per pair it prints the median, lognormal β "
    "and 84th percentile of the required separation and the probability of pounding at the gap as built "
    "(and at each --at gap), writes OUTPUT/gap-suite.h5 (group /gap_suite), and --plot draws the "
    "pounding fragility.",
    epilog=_examples("pound gap inputs/paper_pounding.toml", "pound gap model.toml --json -o gap.h5 --plot approach.png",
                     "pound gap inputs/paper_pounding.toml --suite far-field --jobs 2 --plot fragility.png"),
)
def gap(
    model: ModelArg,
    output: Annotated[Path | None, typer.Option("-o", "--output", metavar="FILE", help="Also write the results to this HDF5 file (group /gap).")] = None,
    json_: JsonOpt = False,
    plot: Annotated[Path | None, typer.Option("--plot", metavar="FILE", help="Also draw the governing pair's approach history (.png, .pdf, .svg).")] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite the output file if it exists (never one of the inputs).")] = False,
    suite: Annotated[str | None, typer.Option("--suite", metavar="SUITE", help="Run every record of this suite: far-field, near-field (FEMA P695; the extra pounding-cli[suites]) or a suite file (.toml, .json); -o is then a folder.")] = None,
    at: Annotated[list[float] | None, typer.Option("--at", metavar="GAP", help="With --suite: also the probability of pounding at this gap, m (repeatable).")] = None,
    jobs: Annotated[int | None, typer.Option("-j", "--jobs", metavar="N", help="With --suite: local worker processes (default: all cores).")] = None,
    scheduler: Annotated[str | None, typer.Option("--scheduler", metavar="URL", help="With --suite: run on the Dask scheduler at this address.")] = None,
    scheduler_file: Annotated[Path | None, typer.Option("--scheduler-file", metavar="FILE", help="With --suite: run on the Dask scheduler described in this file.")] = None,
) -> None:
    """The separation each contact candidate needs over the record."""
    if suite is not None:
        _gap_suite(model, suite, output, json_, plot, force, at, jobs, scheduler, scheduler_file)
        return
    for name, given in (("--at", at), ("--jobs", jobs), ("--scheduler", scheduler), ("--scheduler-file", scheduler_file)):
        if given is not None:
            err.print(f"{name}: applies with --suite only", markup=False)
            raise typer.Exit(2)
    with reported():
        from .api import check_output_path, prepare, run_inputs
        from .gap.required import required_gaps
        from .model import load_model
        from .outputs import refuse_inputs

        scene = prepare(load_model(model))
        for path, what in ((output, "another output file (-o)"), (plot, "another file for the plot (--plot)")):
            if path is not None:
                refuse_inputs(path, run_inputs(scene), what)
        if output is not None:
            check_output_path(output, force)
        result = required_gaps(scene)
        if output is not None:
            from .gap.hdf5 import write_gap

            write_gap(result, output)
        if plot is not None:
            from .gap.plot import approach_figure
            from .report.style import save_figure

            save_figure(approach_figure(result), plot)
    if json_:
        print(json.dumps({"pairs": [p.as_dict() for p in result.pairs], "governing": result.governing,
                          "sample_interval_s": result.sample}, indent=2, ensure_ascii=False))  # fmt: skip
    else:
        _print_gaps(result)
    for path in (output, plot):
        if path is not None:
            err.print(f"wrote {path}", markup=False)


def _gap_suite(model: Path, suite: str, output: Path | None, json_: bool, plot: Path | None, force: bool,
               at: list[float] | None, jobs: int | None, scheduler: str | None, scheduler_file: Path | None) -> None:  # fmt: skip
    """pound gap --suite: run the suite's cases, print the statistics, write the file and plot."""
    if scheduler and scheduler_file:
        err.print("--scheduler and --scheduler-file: give one of them", markup=False)
        raise typer.Exit(2)
    with reported():
        from .suites.gap_suite import gap_suite

        done = lambda k, n: err.print(f"case {k} of {n} done", markup=False) if sys.stderr.isatty() else None  # noqa: E731
        result = gap_suite(model, suite, output, jobs=jobs, scheduler=scheduler, scheduler_file=scheduler_file, at=at,
                           force=force, on_progress=done)  # fmt: skip
        if plot is not None:
            from .report.style import save_figure
            from .suites.plot import fragility_figure

            save_figure(fragility_figure(result.pairs, result.gaps, result.fragility_empirical, result.fragility_fit), plot)
    if json_:
        print(json.dumps(result.as_dict(), indent=2, ensure_ascii=False))
    else:
        _print_suite(result)
    err.print(f"wrote {result.folder / 'gap-suite.h5'}", markup=False)
    if plot is not None:
        err.print(f"wrote {plot}", markup=False)
    if result.failed:
        raise typer.Exit(1)


def _print_suite(result: Any) -> None:
    """pound gap --suite's table: per pair the distribution of the required separation over the
    cases, the code-style estimates' medians and the probability of pounding at the gap (mm)."""
    from .suites.plot import pair_name

    d = result.suite.describe()
    period = f" at T = {d['period_s']:.4g} s" if d["period_s"] else ""
    out.print(f"suite {d['suite']}: {d['records']} records, {d['cases']} cases ({d['orientations']}), scaling "
              f"{d['scaling']['method']}{period}; {len(result.cases) - len(result.failed)} complete, "
              f"{sum(c['reused'] for c in result.cases)} read from an earlier run", markup=False)  # fmt: skip
    table = Table(title="required separation over the suite, mm (lognormal fit: median θ, dispersion β, 84th percentile)",
                  title_justify="left")  # fmt: skip
    cols = ["pair", "gap", "θ", "β", "84 %", "ABS θ", "SRSS θ", "DDC θ", "P(pound) records", "P(pound) fit"]
    cols += [f"P at {1e3 * g:g}" for g in result.at]
    for col in cols:
        table.add_column(col, justify="left" if col == "pair" else "right")
    mm = lambda v: "–" if v is None else f"{1e3 * v:.4g}"  # noqa: E731
    for p in result.pairs:
        r = p["required"]
        table.add_row(pair_name(p), mm(p["clear_distance"]), mm(r["median"]), "–" if r["beta"] is None else f"{r['beta']:.3f}",
                      mm(r["p84"]), mm(p["abs"]["median"]), mm(p["srss"]["median"]), mm(p["ddc"]["median"]),
                      f"{p['p_pound_empirical']:.3f}", f"{p['p_pound_fit']:.3f}",
                      *(f"{a['p_empirical']:.3f} / {a['p_fit']:.3f}" for a in p["at"]))  # fmt: skip
    out.print(table, soft_wrap=False)
    for c in result.failed:
        err.print(f"{c['case']}: {c['status']}", markup=False)


def _suite_report(path: Path, json_: bool, plots: Path | None, fmt: str, given: dict[str, bool], html: Path | None) -> None:
    """pound report on a `pound gap --suite` result: its table, --json, the fragility plot (--plots)."""
    from .report.suite_document import suite_document, suite_tables, write_fragility
    from .report.tables import rich_table

    refused = [name for name, on in given.items() if on] + (["--html"] if html is not None else [])
    if refused:
        raise InputError(f"{refused[0]} does not apply to the result of pound gap --suite (its report is a table, "
                         "--json and --plots)", field=refused[0])  # fmt: skip
    doc = suite_document(path)
    written = write_fragility(path, plots, fmt) if plots is not None else None
    if written is not None:
        err.print(f"wrote {written}", markup=False)
    if json_:
        print(json.dumps(doc, indent=2, ensure_ascii=False))
        return
    for spec in suite_tables(doc):
        out.print(rich_table(spec), soft_wrap=False)


def _print_gaps(result: Any) -> None:
    """pound gap's table: per pair the gap at rest, the required separation, when, the margin
    and the code-style estimates with their ratios to it (mm)."""
    from .gap.plot import pair_label

    if not result.pairs:
        out.print("no contact candidates: nothing can touch", markup=False)
        return
    table = Table(title="required separation in mm (contact off; exact for convex outlines)", title_justify="left")
    for col in ("pair", "z (m)", "gap", "required", "t* (s)", "margin", "ABS", "SRSS", "DDC", "ρ"):
        table.add_column(col, justify="left" if col == "pair" else "right")
    for p in result.pairs:
        ratio = (lambda v: f"{1e3 * v:.4g} ×{v / p.required:.2f}") if p.required > 0 else (lambda v: f"{1e3 * v:.4g}")
        table.add_row(pair_label(p) + ("" if p.simulated else " *"), f"{p.elevation:g}", f"{1e3 * p.clear_distance:.4g}",
                      f"{1e3 * p.required:.5g}", f"{p.time:.4f}", f"{1e3 * p.margin:+.4g}", ratio(p.abs), ratio(p.srss),
                      ratio(p.ddc), f"{p.rho:.3f}")  # fmt: skip
    out.print(table, soft_wrap=False)
    g = result.pairs[result.governing]
    verdict = "they meet at the gap as built" if g.margin < 0 else "they never meet at the gap as built"
    out.print(f"governing: {pair_label(g)}, required {1e3 * g.required:.5g} mm at t = {g.time:.4f} s, margin "
              f"{1e3 * g.margin:+.4g} mm: {verdict}", markup=False)  # fmt: skip
    out.print("  required: the smallest separation along the direction of the gap at rest at which the pair never meets; "
              "ABS, SRSS, DDC from the facing edges' peak displacements (× the exact value); ρ: CQC correlation of the "
              "two fundamental modes", markup=False)  # fmt: skip


@app.command(
    help="Run one analysis and write its results to HDF5.\n\n"
    "Time histories, peak interstorey deflections of every column, the energy balance. "
    "A run that fails (diverges, is interrupted by Ctrl-C or SIGTERM) still writes its partial "
    "results, marked in the file's status, and exits 1. An existing output file is not "
    "overwritten without --force; a missing output folder is created.",
    epilog=_examples("pound run inputs/paper_pounding.toml -o out.h5", "pound run model.toml -o results/ --json --strict"),
)
def run(
    model: ModelArg,
    output: Annotated[
        str | None,
        typer.Option("-o", "--output", metavar="FILE", help="HDF5 result file (default: the model's name with .h5, in the current "
                     "folder); a name ending in / is a folder, written into with that default name."),
    ] = None,
    json_: JsonOpt = False,
    progress: Annotated[
        bool | None, typer.Option("--progress/--no-progress", help="Progress on stderr: a bar on a terminal, else a line per 10 % (default: on when stderr is a terminal).")
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite the output file if it exists (never one of the run's inputs).")] = False,
    strict: StrictOpt = False,
    jobs: Annotated[
        int | None, typer.Option("-j", "--jobs", metavar="N", help="Run the scene's independent groups (buildings that cannot reach each other) on N local processes, merged into one file.")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option("--scheduler", metavar="URL", help="Run the scene's independent groups on the Dask scheduler at this address, e.g. tcp://host:8786.")
    ] = None,
) -> None:
    """Run one analysis and write its results to HDF5."""
    import signal

    show = sys.stderr.isatty() if progress is None else progress
    with reported():  # from the start: a SIGTERM while pound loads is "interrupted", exit 1
        from .api import default_output, run_model
        from .outputs import output_file

        target, note = output_file(output, default_output(model).name) if output is not None else (default_output(model), None)
        grouped = jobs is not None or scheduler is not None
        if grouped and jobs is not None and jobs < 1:
            raise InputError(f"expected a number of processes of at least 1, got {jobs}", field="--jobs")
        with _progress_bar(show) as bar:  # grouped: the groups as they end
            if grouped:
                from .city.grouped import run_in_groups

                result = run_in_groups(model, target, jobs=jobs, scheduler=scheduler, force=force, strict=strict,
                                       warn=lambda n: err.print(str(n), markup=False), progress=bar)  # fmt: skip
            else:
                result = run_model(model, output=target, progress=bar, force=force, strict=strict,
                                   warn=lambda n: err.print(str(n), markup=False))  # fmt: skip
    for sig in (signal.SIGTERM, signal.SIGINT):  # the file has its final name: a signal now ends pound by it
        signal.signal(sig, signal.SIG_DFL)
    if note:
        err.print(note, markup=False)
    summary = run_summary(result)
    if json_:
        print(json.dumps(summary, indent=2))
    else:
        _print_summary(summary)
    if not result.complete:
        err.print(f"{model}: {result.status}; partial results in {target}", markup=False)
        raise typer.Exit(1)


@app.command(
    help="Run many analyses of one base model in parallel: a parametric sweep.\n\n"
    "FILE is a sweep file (.toml or .json: docs/sweep.md): a base model and the values its "
    "fields take, as named cases and/or a grid or zip of parameters, in one study or several. "
    "Every case is checked before any runs; a bad path or value exits 2 naming the case and "
    "the field. Each case's results go to OUTPUT/cases/<hash>.h5 (as `pound run` writes them), "
    "and OUTPUT/summary.csv and summary.h5 get one row per case. Rerunning skips the cases "
    "already complete (matched by their inputs and pound's version number, which stays the same "
    "while a development install's code changes: after updating or changing pound, give a fresh "
    "OUTPUT). OUTPUT must be new, empty or a sweep's own (it holds a .pound-sweep marker); another "
    "folder needs --force. Runs on local processes (--jobs, default all cores) or a Dask cluster "
    "(--scheduler, --scheduler-file). Exits 1 if a case failed.",
    epilog=_examples("pound sweep inputs/pounding_angle_gap.sweep.toml -o angle_gap/ --jobs 4", "pound sweep study.sweep.toml --dry-run"),
)
def sweep(
    sweep_file: Annotated[Path, typer.Argument(metavar="FILE", help="Sweep file (.toml or .json).", show_default=False)],
    output: Annotated[
        Path | None,
        typer.Option("-o", "--output", metavar="DIR", help="Output folder (default: the sweep file's name without .sweep.toml, in the current folder)."),
    ] = None,
    jobs: Annotated[
        int | None, typer.Option("-j", "--jobs", metavar="N", help="Local worker processes, one case and one thread each (default: all cores).")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option("--scheduler", metavar="URL", help="Run on the Dask scheduler at this address, e.g. tcp://host:8786.")
    ] = None,
    scheduler_file: Annotated[
        Path | None, typer.Option("--scheduler-file", metavar="FILE", help="Run on the Dask scheduler described in this file (dask scheduler --scheduler-file).")
    ] = None,
    study: Annotated[
        list[str] | None, typer.Option("--study", metavar="NAME", help="Run only this study (repeatable); every case is still checked and listed.")
    ] = None,
    dry_run: Annotated[
        bool, typer.Option("--dry-run", help="Check every case and list it (hash, status, values) without running or writing anything.")
    ] = False,
    json_: Annotated[
        bool, typer.Option("--json", help="Print JSON Lines on stdout: one JSON object (a case's summary row) per line, as each case finishes; with --dry-run, each case as listed.")
    ] = False,
    progress: Annotated[
        bool | None, typer.Option("--progress/--no-progress", help="Progress bar on stderr (default: when stderr is a terminal).")
    ] = None,
    force: Annotated[
        bool, typer.Option("--force", help="Write into an OUTPUT folder that a sweep did not create and that is not empty (its sweep.json, summary.* and cases/ are replaced; never the sweep's inputs).")
    ] = False,
    strict: StrictOpt = False,
) -> None:
    """Run a parametric sweep."""
    from .sweep.progress import SweepProgress, print_cases, print_outcome

    if scheduler and scheduler_file:
        err.print("--scheduler and --scheduler-file: give one of them", markup=False)
        raise typer.Exit(2)
    show = sys.stderr.isatty() if progress is None else progress

    def emit(row: dict[str, Any]) -> None:
        try:
            print(json.dumps(row, ensure_ascii=False), flush=True)
        except BrokenPipeError:  # the reader left (| head): the sweep goes on, silently
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())

    with reported():
        from .sweep import run_sweep

        with SweepProgress(err, show) as bar:
            outcome = run_sweep(
                sweep_file, output, jobs=jobs, scheduler=scheduler, scheduler_file=scheduler_file,
                studies=study, dry_run=dry_run, on_row=emit if json_ and not dry_run else None,
                on_progress=bar.update, log=bar.log, force=force, strict=strict,
            )  # fmt: skip
    if dry_run:
        for line in outcome.warnings:
            err.print(line, markup=False)
        if json_:
            for i in outcome.selected:
                emit(outcome.rows[i])
        else:
            print_cases(out, outcome)
        return
    print_outcome(err, outcome)
    if not outcome.ok:
        raise typer.Exit(1)


@app.command(
    help="Write the JSON Schemas of the input files.\n\n"
    "They are generated from the pydantic models that validate the files.",
    epilog=_examples("pound schema --out schemas", "pound schema --check"),
)
def schema(
    out_dir: Annotated[Path, typer.Option("--out", metavar="DIR", help="Folder to write the schemas into.")] = Path("schemas"),
    check: Annotated[bool, typer.Option("--check", help="Write nothing; exit 1 if the files differ.")] = False,
) -> None:
    """Write the JSON Schemas of the input files."""
    from .schema import schema_files

    stale = []
    for name, text in schema_files().items():
        path = out_dir / name
        if check:
            if not path.exists() or path.read_text(encoding="utf-8") != text:
                stale.append(str(path))
            continue
        out_dir.mkdir(parents=True, exist_ok=True)
        with reported():
            write_text(path, text)
        err.print(f"wrote {path}", markup=False)
    if stale:
        err.print(f"out of date: {', '.join(stale)}; run `pound schema`", markup=False)
        raise typer.Exit(1)


@app.command(
    help="Describe a ground-motion record: metadata and intensity measures per component.\n\n"
    "FILE is a record definition (.toml or .json: components L and T after its processing and "
    "scaling) or a record file in any format pound reads (PEER .AT2, CSMIP/COSMOS V1/V2, "
    "MiniSEED, SAC, K-NET, plain text: every trace, as read). Prints Δt, points, duration, "
    "PGA, PGV, PGD (the acceleration integrated exactly as linear between samples, from rest), "
    "Arias intensity and the 5-95 % significant duration of each component.",
    epilog=_examples("pound record inputs/ridgecrest2019_ccc.record.toml --plot ccc.png", "pound record inputs/records/CICCC.RAW --trace HNE --json"),
)
def record(
    file: Annotated[Path, typer.Argument(metavar="FILE", help="Record definition (.toml, .json) or record file.", show_default=False)],
    trace: Annotated[
        str | None, typer.Option("--trace", metavar="ID", help="Record file: the one trace to describe (SEED id, channel code or index).")
    ] = None,
    units: Annotated[
        str | None,
        typer.Option("--units", metavar="UNIT", help="Record file: units of its values (g, m/s2, cm/s2, gal), for files that do not declare them."),
    ] = None,
    format: Annotated[
        str, typer.Option("--format", metavar="FORMAT", help="Record file: auto, text, or an obspy format name (MSEED, SAC, AT2, COSMOS, KNET).")
    ] = "auto",
    dt: Annotated[
        float | None, typer.Option("--dt", metavar="SECONDS", help="Record file: sample interval in s, for plain text with one value per line.")
    ] = None,
    json_: JsonOpt = False,
    plot: Annotated[
        Path | None,
        typer.Option("--plot", metavar="FILE", help="Also draw acceleration, velocity, displacement and the 5 %-damped PSA spectrum (.png, .pdf, .svg)."),
    ] = None,
) -> None:
    """Describe a ground-motion record."""
    from .records.inspect import open_record
    from .records.summary import summarise

    with reported():
        data = open_record(file, trace=trace, units=units, format=format, dt=dt)
        summary = summarise(data).model_dump(mode="json")
        if plot is not None:
            from .outputs import refuse_inputs
            from .records.plot import record_figure, save_figure

            inputs = [(file, "the record being described")] + [(file.parent / c.file, f"the record file of {c.name}")
                                                         for c in data.components if c.file]  # fmt: skip
            refuse_inputs(plot, inputs, "another file for the plot (--plot)")
            save_figure(record_figure(data), plot)
    if json_:
        print(json.dumps(summary, indent=2, ensure_ascii=False))
    else:
        _print_record(summary)
    if plot is not None:
        err.print(f"wrote {plot}", markup=False)


@app.command(
    help="Measure run time against error, and stress-test stability.\n\n"
    "For every scene (the shipped ones, or --scene files), a reference run at a far smaller Δt, "
    "then each integrator setting, timed (median of --repeats, solver only) and compared with "
    "the reference. Prints the table and writes bench.h5, bench.md and bench.png into --out. "
    "--quick: a short version (three settings, the first 15 s, one repeat); docs/bench.md gives "
    "how long it took.",
    epilog=_examples("pound bench --quick --out bench-results", "pound bench --stability"),
)
def bench(
    scene: Annotated[list[Path] | None, typer.Option("--scene", metavar="FILE", help="A model file to bench (repeatable).")] = None,
    out_dir: Annotated[Path, typer.Option("--out", metavar="DIR", help="Folder for bench.h5, bench.md, bench.png.")] = Path("bench-results"),
    quick: Annotated[
        bool, typer.Option("--quick", help="Three settings, the first 15 s of each scene but the stiff one, one repeat.")
    ] = False,
    repeats: Annotated[int, typer.Option("--repeats", metavar="N", help="Timed runs per setting (median).", min=1)] = 3,
    stability: Annotated[
        bool, typer.Option("--stability", help="Run the stability stress cases instead (stability.md).")
    ] = False,
    scaling: Annotated[
        bool, typer.Option("--scaling", help="Measure cost against 1, 5, 10, 20, 40 buildings in a row (scaling.md).")
    ] = False,
    blocks: Annotated[
        bool, typer.Option("--blocks", help="With --scaling: whole `pound run` cost of city blocks of 9, 25, 100 buildings and 10 blocks with --jobs 2 (city-scaling.md).")
    ] = False,
    start: Annotated[
        bool, typer.Option("--start", help="Time pound's commands from cold processes (median of --repeats, at least 5) and break a run's time down by stage: numba's start-up against pound's own (start.md).")
    ] = False,
    json_: JsonOpt = False,
) -> None:
    """Measure run time against error."""
    from .bench import SETTINGS, bench as run_bench, scene_files
    from .bench.report import markdown, plot, table_rows, write_hdf5
    from .bench.run import QUICK_SETTINGS

    if start:
        from dataclasses import asdict

        from .bench.start import markdown as start_markdown, start_times

        with reported():
            out_dir.mkdir(parents=True, exist_ok=True)
            report = start_times(max(repeats, 5), log=lambda text: err.print(text, markup=False))
            text = start_markdown(report)
            write_text(out_dir / "start.md", text)
        print(json.dumps({**asdict(report), "numba_s": report.numba_s}, indent=2)) if json_ else out.print(text, markup=False)
        return
    if scaling:
        if blocks:
            from .bench.city_scaling import city_scaling as measure, markdown as table

            _bench_table(measure, table, out_dir / "city-scaling.md", json_)
        else:
            from .bench.scaling import markdown as table, scaling as measure  # type: ignore[assignment]

            _bench_table(measure, table, out_dir / "scaling.md", json_)
        return
    if stability:
        from dataclasses import asdict

        from .bench.stability import markdown as stability_markdown, stability as run_stability

        with reported():
            out_dir.mkdir(parents=True, exist_ok=True)
            outcomes = run_stability(log=lambda text: err.print(text, markup=False))
            text = stability_markdown(outcomes)
            write_text(out_dir / "stability.md", text)
        if json_:
            print(json.dumps([{**asdict(o), "acceptable": o.acceptable} for o in outcomes], indent=2))
        else:
            out.print(text, markup=False)
        if not all(o.acceptable for o in outcomes):
            raise typer.Exit(1)
        return

    import os
    import time

    models = list(scene) if scene else scene_files()
    if quick and not scene:
        models = [m for m in models if m.stem != "stiff_contact"]
    with reported():
        out_dir.mkdir(parents=True, exist_ok=True)
        start, load = time.perf_counter(), f"{os.getloadavg()[0]:.1f}"
        reports = run_bench(
            models, QUICK_SETTINGS if quick else SETTINGS, repeats=1 if quick else repeats,
            reference_divisor=1 if quick else 4, duration=15.0 if quick else None,
            log=lambda text: err.print(text, markup=False),
        )  # fmt: skip
        elapsed = round(time.perf_counter() - start)
        took = f"{elapsed // 60} min {elapsed % 60} s" if elapsed >= 60 else f"{elapsed} s"
        text = markdown(reports) + (
            f"\nThis bench (`pound bench{' --quick' if quick else ''}`, {len(models)} scenes) took {took} "
            f"of wall time on {os.cpu_count()} CPUs, references included (load average {load} at the start, "
            f"{os.getloadavg()[0]:.1f} at the end).\n"
        )
        write_text(out_dir / "bench.md", text)
        write_hdf5(reports, out_dir / "bench.h5")
        plot(reports, out_dir / "bench.png")
    if json_:
        print(json.dumps(table_rows(reports), indent=2))
    else:
        out.print(text, markup=False)
        out.print(f"written: {out_dir / 'bench.md'}, {out_dir / 'bench.h5'}, {out_dir / 'bench.png'}", markup=False)


@app.command(
    help="Report on runs or a sweep: tables, plots, a plan-view animation, an HTML file.\n\n"
    "The arguments are result files written by `pound run`, or one sweep folder written by `pound sweep`. "
    "For runs: the model, record, integrator, Δt, run time, periods, impacts, peak interstorey "
    "deflections per storey (with the column) and the energy balance; --plots writes the ground "
    "motion, floor displacements, deflection profiles (all files on one figure), impacts, energy "
    "balance and plan view; --animate a plan-view GIF or MP4. For a sweep: its summary table; "
    "--plots draws summary columns against a swept parameter (also polar for an angle) and "
    "grouped bars of cases. A failed run or case says so at the top. --json prints one JSON "
    "document (a list of them for several files); --html writes everything into one file.",
    epilog=_examples("pound report out.h5 --plots plots/ --html report.html", "pound report angle_gap/ --plots plots/ --x excitation.angle"),
)
def report(
    paths: Annotated[list[Path], typer.Argument(metavar="FILE|DIR", help="Result files (.h5), or one sweep folder, or the result of pound gap --suite (its gap-suite.h5 or folder).", show_default=False)],
    json_: JsonOpt = False,
    column: Annotated[
        str | None, typer.Option("--column", metavar="COLUMN", help="Narrow the deflections to one column: C9, or building:column (left:C9).")
    ] = None,
    plots: Annotated[Path | None, typer.Option("--plots", metavar="DIR", help="Write every plot into this folder.")] = None,
    format: Annotated[str, typer.Option("--format", metavar="FORMAT", help="Plot format: png, svg or pdf (HTML: png or svg).")] = "png",
    html: Annotated[Path | None, typer.Option("--html", metavar="FILE", help="Write one self-contained HTML report (tables and plots).")] = None,
    floor: Annotated[
        list[str] | None,
        typer.Option("--floor", metavar="BUILDING:FLOOR", help="Runs: floor for the displacement plot, building:floor (left:4; repeatable; default each roof)."),
    ] = None,
    magnify: Annotated[
        float | None, typer.Option("--magnify", metavar="FACTOR", help="Runs: displacement factor of plan views (default: a round factor, stated).", min=0.0)
    ] = None,
    animate: Annotated[Path | None, typer.Option("--animate", metavar="FILE", help="Runs: write a plan-view animation (.gif, or .mp4 with ffmpeg).")] = None,
    level: Annotated[
        int | None, typer.Option("--level", metavar="N", help="Animate one level (1 = lowest floor elevation; default all).", min=1)
    ] = None,
    start: Annotated[float | None, typer.Option("--start", metavar="SECONDS", help="Animation window start, s (default: 6 s around the peak impact).")] = None,
    end: Annotated[float | None, typer.Option("--end", metavar="SECONDS", help="Animation window end, s.")] = None,
    stride: Annotated[int | None, typer.Option("--stride", metavar="N", help="Stored samples per animation frame (default: fit --max-frames).", min=1)] = None,
    max_frames: Annotated[int, typer.Option("--max-frames", metavar="N", help="Most animation frames.", min=1)] = 120,
    fps: Annotated[int, typer.Option("--fps", metavar="N", help="Animation frames per second.", min=1)] = 12,
    x: Annotated[str | None, typer.Option("--x", metavar="PARAMETER", help="Sweep: the swept parameter on the x axis (default: the first numeric one).")] = None,
    y: Annotated[
        list[str] | None, typer.Option("--y", metavar="COLUMN", help="Sweep: summary columns to plot against --x (patterns: 'peak_isd_x_m[left/*/1]'; repeatable).")
    ] = None,
    case: Annotated[
        list[str] | None, typer.Option("--case", metavar="PATTERN", help="Sweep: cases for the bar chart, 'study/case' patterns (repeatable).")
    ] = None,
    study: Annotated[list[str] | None, typer.Option("--study", metavar="NAME", help="Sweep: report only this study (repeatable).")] = None,
) -> None:
    """Report on runs or a sweep."""
    from .report.outputs import Animation, check_options

    given = {"--floor": bool(floor), "--magnify": magnify is not None, "--animate": animate is not None,
             "--level": level is not None, "--start": start is not None, "--end": end is not None,
             "--stride": stride is not None, "--max-frames": max_frames != 120, "--fps": fps != 12,
             "--x": x is not None, "--y": bool(y), "--case": bool(case), "--study": bool(study)}  # fmt: skip
    with reported():
        from .report.suite_document import suite_file

        suite_result = suite_file(paths[0]) if len(paths) == 1 else None
        if suite_result is not None:  # pound gap --suite's result: its statistics and fragility plot
            _suite_report(suite_result, json_, plots, format, given, html)
            return
        sweep_folder = next((p for p in paths if p.is_dir()), None)
        check_options(sweep_folder is not None, given)
        _refuse_reading_what_is_written(paths, [html, animate])
        if sweep_folder is not None:
            if len(paths) > 1:
                raise InputError("give one sweep folder, or result files: not both, and one folder at a time",
                                 field="PATHS")  # fmt: skip
            docs, written, blocks = _sweep_report(sweep_folder, column, plots, format, html, x, y, case, study)
        else:
            from .report.histories import parse_floor

            animation = Animation(animate, level, start, end, stride, max_frames, fps) if animate else None
            docs, written, blocks = _run_report(paths, column, plots, format, html, [parse_floor(f) for f in floor or []],
                                                magnify, animation)  # fmt: skip
    for source, warning, _ in blocks:
        if warning:
            err.print(f"{source}: {warning}", markup=False)
    if written.frames is not None:
        err.print(f"{animate}: {written.frames} frames of {paths[0]}" + (" (the first file)" if len(paths) > 1 else ""),
                  markup=False)  # fmt: skip
    for path in written.files:
        err.print(f"wrote {path}", markup=False)
    if json_:
        print(json.dumps(docs[0] if len(docs) == 1 else docs, indent=2, ensure_ascii=False))
        return
    from .report.tables import rich_table

    for _, warning, tables in blocks:
        if warning:
            out.print(f"[bold red]{warning}[/bold red]")
        for spec in tables:
            out.print(rich_table(spec), soft_wrap=False)


@app.command(
    help="Write a result file's histories, peaks, forces and impact log as tidy CSV files.\n\n"
    "One file per quantity, DIR/<quantity>.csv: a header row naming each column with its unit "
    "in brackets (time [s], u_x [m]), then one row per observation (per time, building and floor "
    "for a history; per column and storey for the peak deflections; per contact episode for the "
    "impact log), for pandas and spreadsheets. --what picks quantities or groups of them "
    "(histories, peaks, forces, all; default all). The files are written together and renamed into "
    "place at the end; existing ones are replaced only with --force. --json describes what was "
    "written (file, rows, columns with units).",
    epilog=_examples("pound export out.h5 --csv csv/", "pound export out.h5 --csv csv/ --what peaks --what impacts --json"),
)
def export(
    result: Annotated[Path, typer.Argument(metavar="FILE", help="Result file written by `pound run` (.h5).", show_default=False)],
    csv_dir: Annotated[Path, typer.Option("--csv", metavar="DIR", help="Folder for the CSV files (made if missing).", show_default=False)],
    what: Annotated[
        list[str] | None,
        typer.Option("--what", metavar="QUANTITY", help="A quantity (displacement, velocity, acceleration, ground, energy, "
                     "contact, yielding, interstorey_peaks, floor_peaks, impacts, storey_shear, column_forces, "
                     "storey_shear_peaks, column_force_peaks) or group (histories, peaks, forces, all); repeatable."),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite CSV files that exist (never the result file).")] = False,
    json_: JsonOpt = False,
) -> None:
    """Write a result file's quantities as CSV files."""
    from .export import export_csv

    with reported():
        written = export_csv(result, csv_dir, what, force=force)
    if json_:
        print(json.dumps({"result": str(result), "folder": str(csv_dir), "files": written}, indent=2, ensure_ascii=False))
        return
    for w in written:
        err.print(f"wrote {w['file']} ({w['rows']:,} row{'' if w['rows'] == 1 else 's'})", markup=False)


def _refuse_reading_what_is_written(paths: list[Path], outputs: list[Path | None]) -> None:
    """A report file (--html, --animate) must not be a file it reports on (a result file, a
    sweep's summary): writing it would destroy the results."""
    from .outputs import refuse_inputs

    inputs = []
    for p in paths:
        inputs += ([(p / name, "a sweep summary being reported") for name in ("summary.h5", "summary.csv", "sweep.json")]
                   if p.is_dir() else [(p, "a result file being reported")])  # fmt: skip
    for output in outputs:
        if output is not None:
            refuse_inputs(Path(output), inputs, "another file for the report")


def _run_report(paths, column, plots, fmt, html, floors, magnify, animation):
    """JSON documents, files written and (file, warning, tables) per run."""
    from .report import open_runs, run_tables, summary
    from .report.outputs import run_outputs
    from .report.tables import status_line

    runs = open_runs(paths)
    docs = [summary(r, column=column) for r in runs]
    written = run_outputs(runs, plots, fmt, column, floors, magnify, animation, html)
    return docs, written, [(d["file"], status_line(d), run_tables(d)) for d in docs]


def _sweep_report(folder, column, plots, fmt, html, x, ys, cases, studies):
    """The JSON document, files written and (folder, warning, tables) of a sweep folder."""
    from .report.outputs import sweep_outputs
    from .report.sweep_data import column_names, open_sweep, select
    from .report.sweep_document import status_line, sweep_summary, sweep_tables

    whole = open_sweep(folder)
    sweep = select(whole, studies)
    if column:
        column_names(sweep, column)  # refuse a column the summary lacks before drawing anything
    doc = sweep_summary(whole, studies)
    written = sweep_outputs(sweep, plots, fmt, column, x, ys, cases, html)
    return [doc], written, [(doc["folder"], status_line(doc), sweep_tables(doc, column))]


# --- printing ---------------------------------------------------------------------------


@contextmanager
def _progress_bar(show: bool) -> Iterator[Any]:
    """The progress callback of a run: a rich bar when stderr is a terminal; otherwise (a log
    file, a pipe, a batch job that asked for --progress) one plain line per tenth done."""
    if not show:
        yield None
        return
    if not err.is_terminal:
        yield _progress_lines()
        return
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    with Progress(
        TextColumn("integrating"), BarColumn(), TextColumn("{task.percentage:>3.0f}%"),
        TimeRemainingColumn(), console=err, transient=True,
    ) as bar:  # fmt: skip
        task = bar.add_task("run", total=1)

        def update(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)

        yield update


def _progress_lines(step: int = 10) -> Any:
    """A progress callback that prints "integrating: 40 %" on stderr each time another `step`
    per cent is done (a line a reader of a log can follow, with no terminal codes)."""
    shown = [-1]

    def update(done: int, total: int) -> None:
        percent = 100 * done // max(total, 1)
        if percent // step > shown[0]:
            shown[0] = percent // step
            err.print(f"integrating: {step * shown[0]} %", markup=False)
            err.file.flush()

    return update


def _bench_table(measure: Any, table: Any, path: Path, json_: bool) -> None:
    """Run a bench's measurements (logging to stderr), write their markdown table to `path`,
    print it (or the points as JSON)."""
    from dataclasses import asdict

    with reported():
        path.parent.mkdir(parents=True, exist_ok=True)
        points = measure(log=lambda text: err.print(text, markup=False))
        text = table(points)
        write_text(path, text)
    print(json.dumps([asdict(p) for p in points], indent=2)) if json_ else out.print(text, markup=False)


def run_summary(result: Any) -> dict[str, Any]:
    """The short summary printed after a run (also the --json document)."""
    import numpy as np

    d = result.diagnostics
    buildings = []
    for name, b in result.buildings.items():
        isd = b.interstorey_deflection
        entry: dict[str, Any] = {"name": name}
        for k, comp in enumerate(("x", "y", "theta")):
            values = isd[:, :, k]
            if values.size == 0 or not (values == values).any():
                continue
            c, s = np.unravel_index(np.nanargmax(values), values.shape)
            peak = {"value": float(values[c, s]), "unit": "rad" if comp == "theta" else "m"}
            if comp != "theta":  # a storey's twist is the same at every column
                peak["column"] = b.column_names[c]
            peak["storey"] = int(s) + 1
            entry[f"peak_interstorey_{comp}"] = peak
        if b.yielding is not None:
            entry["yielding"] = _yielding_summary(b.yielding)
        buildings.append(entry)
    return {
        "status": result.status,
        "output": str(result.output) if result.output else None,
        "input_sha256": result.input_sha256,
        "duration_s": float(result.time[-1]) if result.time.size else 0.0,
        "integrator": d.get("integrator"),
        "dt_s": d.get("dt"),
        "substep_s": d.get("substep") or None,
        "steps": d.get("steps"),
        "exact_substeps": d.get("exact_substeps", 0),
        "exact_steps_of_dt": d.get("exact_steps_of_dt", 0),
        "cdm_steps": d.get("cdm_steps", 0),
        "solver_wall_time_s": d.get("wall_time_s"),
        "us_per_step": d.get("us_per_step"),
        "energy_balance_error": result.balance_error_ratio,
        "impacts": result.contact.impact_count,
        "peak_impact_force_N": result.contact.peak_force,
        "contact_steps": d.get("contact_steps", 0),
        "buildings": buildings,
        "warnings": result.warnings,
    }


def _yielding_summary(y: Any) -> list[dict[str, Any]]:
    """Per kind of yielding member (column, isolator): how many yielded, the one with the
    largest ductility (peak |δ| along a local axis over δ_y) with its peak resultant
    deflection |δ| and residual deflection, and the one with the largest residual deflection;
    deflections are resultants √(δ_x² + δ_y²), m."""
    import numpy as np

    ductility = y.ductility.max(axis=1)
    residual = np.hypot(y.residual_deflection[:, 0], y.residual_deflection[:, 1])
    out = []
    for kind in ("column", "isolator"):
        index = np.flatnonzero(y.members["kind"] == kind)
        if index.size == 0:
            continue
        worst = int(index[np.argmax(ductility[index])])
        most_bent = int(index[np.argmax(residual[index])])
        out.append({
            "kind": kind,
            "members": int(index.size),
            "yielded": int(np.count_nonzero(ductility[index] >= 1.0)),
            "largest_ductility": {
                "member": str(y.members["name"][worst]),
                "storey": int(y.members["storey"][worst]),
                "ductility": float(ductility[worst]),
                "peak_deflection_m": float(y.peak[worst, 2]),
                "residual_deflection_m": float(residual[worst]),
            },
            "largest_residual": {
                "member": str(y.members["name"][most_bent]),
                "storey": int(y.members["storey"][most_bent]),
                "residual_deflection_m": float(residual[most_bent]),
            },
        })  # fmt: skip
    return out


def _print_summary(s: dict[str, Any]) -> None:
    out.print(f"[bold]{escape(s['status'])}[/bold]  →  {escape(str(s['output']))}")
    if s["integrator"] == "hybrid":
        how = (f"hybrid: {s['exact_substeps']:,} exact steps of ≤ {2 * s['substep_s']:.4g} s, "
               f"{s['cdm_steps']:,} CDM steps of {s['dt_s']:.4g} s")  # fmt: skip
    else:
        how = f"{s['integrator']}, Δt = {s['dt_s']:.4g} s"
    out.print(
        f"{s['duration_s']:.2f} s simulated in {s['steps']:,} steps ({how}); "
        f"solver {s['solver_wall_time_s']:.3f} s ({s['us_per_step']:.2f} µs/step); "
        f"energy balance error {100 * s['energy_balance_error']:.3g} % of input",
        markup=False,
    )
    out.print(
        f"impacts: {s['impacts']}" + (f", peak normal force {s['peak_impact_force_N'] / 1e3:.4g} kN, "
        f"{s['contact_steps']:,} steps in contact" if s["impacts"] else ""),
        markup=False,
    )  # fmt: skip
    table = Table(title="Peak interstorey deflection (building axes)")
    for col in ("building", "x (mm)", "y (mm)", "θ (mrad)"):
        table.add_column(col)
    for b in s["buildings"]:
        cells = []
        for comp, scale in (("x", 1e3), ("y", 1e3), ("theta", 1e3)):
            p = b.get(f"peak_interstorey_{comp}")
            where = f"{p['column']}, storey {p['storey']}" if p and "column" in p else f"storey {p['storey']}" if p else ""
            cells.append(f"{scale * p['value']:.3g} ({where})" if p else "-")
        table.add_row(b["name"], *cells)
    out.print(table, soft_wrap=False)
    for b in s["buildings"]:
        for group in b.get("yielding", []):
            w, r = group["largest_ductility"], group["largest_residual"]
            out.print(
                f"{b['name']}: {group['yielded']} of {group['members']} {group['kind']}s yielded; largest "
                f"ductility {w['ductility']:.3g} ({w['member']}, storey {w['storey']}: peak |δ| "
                f"{1e3 * w['peak_deflection_m']:.3g} mm, residual {1e3 * w['residual_deflection_m']:.3g} mm); "
                f"largest residual |δ| {1e3 * r['residual_deflection_m']:.3g} mm ({r['member']}, storey {r['storey']})",
                markup=False,
            )


def _placement(b: dict[str, Any]) -> str:
    """'placed 0.05 m beside left on its +x side (align min): origin (8.05, 0) m, rotation 0°'."""
    p = b["place"]
    extra = "".join([f", offset {p['offset']:g} m" if p["offset"] else "",
                     f", turned {p['rotation']:g}°" if p["rotation"] else ""])  # fmt: skip
    return (f"placed {p['gap']:g} m beside {p['beside']} on its {p['side']} side (align {p['align']}{extra}): "
            f"origin ({b['origin_m'][0]:.10g}, {b['origin_m'][1]:.10g}) m, rotation {b['rotation_deg']:.10g}°")


def _floor_groups(b: dict[str, Any]) -> list[str]:
    """'floors 1-4: m = 64 t, J = 6.827e+05 kg·m²', one line per run of alike floors."""
    rows = list(zip(b["floor_masses_kg"], b["rotational_inertia_kgm2"]))
    lines, first = [], 0
    for i in range(1, len(rows) + 1):
        if i == len(rows) or rows[i] != rows[first]:
            which = f"floor {first + 1}" if i == first + 1 else f"floors {first + 1}-{i}"
            lines.append(f"{which}: m = {rows[first][0] / 1e3:.6g} t, J = {rows[first][1]:.4g} kg·m²")
            first = i
    return lines


CANDIDATE_ROWS = 20
"""pound validate lists at most this many contact candidates (--json gives them all)."""


def _print_candidates(c: dict[str, Any]) -> None:
    """Every contact candidate (up to CANDIDATE_ROWS) with its kind, elevation, ξ and the
    geometry at rest: clear distance, its direction and the closest points (gap.rest)
    (neighbours that cannot meet are a plausibility warning, plausibility.unmet_neighbours)."""
    from .gap.rest import compass

    rows = [(f"{p['body_a']} floor {p['floor_a']}", f"{p['body_b']} floor {p['floor_b']}" if p["floor_b"] else p["body_b"],
             p["kind"], p["elevation_m"], "—", p) for p in c["pairs"] if "storey_b" not in p]  # fmt: skip
    rows += [(f"{p['body_a']} floor {p['floor_a']}", f"{p['body_b']} storey {p['storey_b']}", p["kind"],
              p["elevation_m"], f"{p['xi']:.3f}", p) for p in c["storey_crossings"]]  # fmt: skip
    if rows:
        table = Table(title="contact candidates at rest", title_justify="left")
        for col, justify in (("slab", "left"), ("meets", "left"), ("kind", "left"), ("z (m)", "right"),
                             ("ξ", "right"), ("clear (m)", "right"), ("towards", "right"),
                             ("closest points (m)", "left")):  # fmt: skip
            table.add_column(col, justify=justify)  # type: ignore[arg-type]
        for a, b, kind, z, xi, p in rows[:CANDIDATE_ROWS]:
            (xa, ya), (xb, yb) = p["closest_points_m"]
            table.add_row(a, b, kind.replace("-", "–"), f"{z:g}", xi, f"{p['clear_distance_m']:.4g}",
                          compass(p["direction_x_y"]), f"({xa:.4g}, {ya:.4g}) → ({xb:.4g}, {yb:.4g})")  # fmt: skip
        out.print(table, soft_wrap=False)
        out.print("  z: elevation; ξ: where in the storey struck (0 at its floor below, 1 at the floor above); "
                  "clear: distance in plan, towards: its direction from the slab to what it meets (global axes), "
                  "between the closest points", markup=False)  # fmt: skip
        if len(rows) > CANDIDATE_ROWS:
            out.print(f"  … and {len(rows) - CANDIDATE_ROWS} more (pound validate --json lists them all)", markup=False)
    if c["storey_crossings"]:
        modes = c.get("local_modes", [])
        if modes:
            omegas = [m["omega_rad_s"] for m in modes]
            out.print(f"  slab–storey: the struck columns vibrate with their own mass: {len(modes)} local modes "
                      f"(pseudo-floors), ω {min(omegas):.4g} to {max(omegas):.4g} rad/s; their static flexibility "
                      "beyond them is in series with the contact (docs/theory.md §10, \"The struck columns' own mass\")",
                      markup=False)  # fmt: skip
        if c.get("massless_storeys", c["storey_crossings"]):
            out.print("  slab–storey: struck columns without a material density are massless (their flexibility is "
                      "in series with the contact); with their own mass an impact splits into shorter ones and its "
                      "peak force and the columns' shear rise: give their material a density (kg/m³) "
                      "(docs/theory.md §10, \"The struck columns' own mass\")", markup=False)  # fmt: skip
    multiples = [p.get("phase_step_multiple", 1.0) for p in c["pairs"]]
    if max(multiples, default=1.0) > 1:
        counts = {m: multiples.count(m) for m in sorted(set(multiples))}
        longer = ", ".join(f"× {m:g} ({n} pair{'s' * (n > 1)})" for m, n in counts.items() if m > 1)
        out.print(f"  contact phases step by the pairs that may touch in them, each by its own likely ω: Δt where "
                  f"one of {counts.get(1.0, 0)} may, else up to Δt {longer} (docs/theory.md §10)", markup=False)
    if c.get("pruned"):
        why = "contact.reach" if c["reach_source"] == "contact.reach" else "the bound from the modes and the record's spectral displacement, docs/theory.md"
        out.print(f"  reach {c['reach_m']:.3g} m ({why}): buildings farther apart at rest have no candidates; "
                  "every run checks that none of them could have touched", markup=False)  # fmt: skip


def _print_description(info: dict[str, Any]) -> None:
    out.print(f"[bold]{escape(info['title'] or info['file'])}[/bold]")
    for b in info["buildings"]:
        storeys = f"{b['storeys']} storey" + ("s" if b["storeys"] != 1 else "")
        out.print(f"[bold]building {escape(b['name'])}[/bold]: {storeys}, {b['height_m']:g} m, "
                  f"{b['total_mass_kg'] / 1e3:.6g} t, {b['columns']} column lines"
                  + (f" ({b['yielding_columns']} yielding column instances)" if b["yielding_columns"] else "")
                  + (f"; base-isolated on {b['isolators']} isolators (storey 1, floor 1 = base slab)"
                     if b["isolators"] else "")
                  + (f", in a moat wall {b['moat']['gap_m']:g} m away ({', '.join(b['moat']['walls'])})"
                     if b["moat"] else ""))  # fmt: skip
        if b["place"] is not None:
            out.print(f"  {_placement(b)}", markup=False)
        for line in _floor_groups(b):
            out.print(f"  {line}", markup=False)
        table = Table()
        for col in ("mode", "period (s)", "mass x", "mass y", "mass θ", "ζ"):
            table.add_column(col, justify="right")
        for i, (t, p, z) in enumerate(zip(b["periods_s"], b["participating_mass_ratio_x_y_theta"],
                                          b["damping_ratios"])):  # fmt: skip
            table.add_row(str(i + 1), f"{t:.4f}", *(f"{100 * v:.1f} %" for v in p), f"{100 * z:.2f} %")
        out.print(table, soft_wrap=False)
        r = b["rayleigh"]
        of = "" if r["of"] == "building" else f" of the {r['of']} (periods {', '.join(f'{t:.4f}' for t in r['anchor_periods_s'])} s)"
        out.print(
            f"  Rayleigh: ζ = {r['ratios'][0]:g}, {r['ratios'][1]:g} at modes {r['modes'][0]}, {r['modes'][1]}{of}"
            f" → a0 = {r['a0_per_s']:.5g} 1/s, a1 = {r['a1_s']:.5g} s",
            markup=False,
        )
        out.print(f"  Δt limit (CDM): 2/ω_max = {b['dt_limit_s']:.4g} s (ω_max = {b['omega_max_rad_s']:.4g} rad/s)",
                  markup=False)  # fmt: skip
        iso = b["isolation"]
        if iso is not None:
            period = f" at T_b = {iso['isolated_period_s']:.4g} s (on K2)" if iso["isolated_period_s"] else ""
            out.print(
                f"  isolation: viscous ζ_b = {iso['damping_ratio']:g}{period}; the Rayleigh damping acts on the "
                "superstructure's deformation only, the bearings damp by their hysteresis",
                markup=False,
            )
    from .model.inelastic import BEARING_FIELDS

    for bearing in info["bearings"]:
        given = ", ".join(BEARING_FIELDS[k] for k in bearing["given"])
        out.print(
            f"bearing {bearing['name']}: K1 = {bearing['initial_stiffness_N_per_m'] / 1e6:.4g} MN/m, "
            f"K2 = {bearing['post_yield_stiffness_N_per_m'] / 1e6:.4g} MN/m, Q = {bearing['characteristic_strength_N'] / 1e3:.4g} kN, "
            f"F_y = {bearing['yield_force_N'] / 1e3:.4g} kN, d_y = {bearing['yield_displacement_m'] * 1e3:.4g} mm "
            f"(given {given}; {bearing['interaction']})",
            markup=False,
        )
    c = info["contact"]
    if not c["enabled"]:
        out.print("contact: off", markup=False)
    elif not c["pairs"]:
        out.print("contact: no floors share a level and no slab lies inside a neighbour's storey, so nothing can touch",
                  markup=False)  # fmt: skip
    else:
        out.print(f"contact: {len(c['pairs'])} candidate pairs", markup=False)
        groups: dict[str, list[str]] = {}  # the pairs' kinds by their resolved impact parameters
        for p in c["pairs"]:
            kind = "floor–" + ("storey" if "storey_b" in p else "floor" if p["floor_b"] else p["body_b"])
            kinds = groups.setdefault(_impact_parameters(p), [])
            if kind not in kinds:
                kinds.append(kind)
        for text, kinds in groups.items():
            out.print(f"  {', '.join(kinds)}: {text}", markup=False)
        out.print(f"  Δt limit (CDM, in contact): 2/ω_contact = {c['dt_limit_s']:.4g} s (ω_contact = "
                  f"{c['omega_max_rad_s']:.4g} rad/s, an upper estimate)", markup=False)  # fmt: skip
        if c["omega_likely_rad_s"] < c["omega_max_rad_s"]:
            out.print(f"  likely contacts (by the angles between the slabs' edges): ω_contact = "
                      f"{c['omega_likely_rad_s']:.4g} rad/s, 2/ω_contact = {2 / c['omega_likely_rad_s']:.4g} s",
                      markup=False)  # fmt: skip
    if c["enabled"]:
        _print_candidates(c)
    e = info["excitation"]
    out.print(
        f"excitation: {e['record'] or 'record'}, components {'+'.join(e['components'])} at θ = "
        f"{e['angle_deg']:g}°, scale {e['scale']:g}; {e['duration_s']:g} s at {e['dt_s']:g} s; "
        f"PGA X {e['pga_g']['X']:.3f} g, Y {e['pga_g']['Y']:.3f} g",
        markup=False,
    )
    for note in e["notes"]:
        out.print(f"  note: {note}", markup=False)
    _print_analysis(info["analysis"], info["buildings"])


def _print_analysis(a: dict[str, Any], buildings: list[dict[str, Any]]) -> None:
    """The time grid: which limit sets Δt, and the steps the integrator takes."""
    stiffest = min(buildings, key=lambda b: b["dt_limit_s"])["name"]
    structure = f"{a['stability_limit_s']:.4g} s, building {stiffest}"
    contact = f"{a['contact_limit_s']:.4g} s" if a["contact_limit_s"] else None
    fraction = f"{a['dt_auto_fraction']:g}"
    if not a["dt_auto"]:
        why = f"given — below the structure's limit 2/ω_max ({structure})"
        if contact:
            above = a["dt_s"] >= a["contact_limit_s"]
            why += f"; {'above' if above else 'below'} the contact's 2/ω_contact ({contact})"
            why += ": impacts may go unstable" if above else ""
    elif a["dt_limited_by"] == "contact":
        if a["contact_step_limit_s"] > a["contact_limit_s"]:
            likely = f"{a['contact_step_limit_s']:.4g} s"
            why = (f"auto, {fraction} × 2/ω_contact of the likely contacts — the contact governs ({likely}; the "
                   f"stiffest the outlines allow: {contact}; the structure's: {structure})")  # fmt: skip
        else:
            why = f"auto, {fraction} × 2/ω_contact — the contact limit governs ({contact}; the structure's: {structure})"
    else:
        why = f"auto, {fraction} × 2/ω_max — the structure's limit governs ({structure}"
        why += f"; the contact's: {contact})" if contact else "; no contact candidates)"
    if a["dt_auto"]:
        why += ", shortened to " + ("divide the substep" if a["integrator"] == "hybrid" else "fit the output interval")
    out.print(f"analysis: {a['duration_s']:g} s, output every {a['output_interval_s']:g} s", markup=False)
    out.print(f"  Δt = {a['dt_s']:.4g} s: {why}", markup=False)
    if a["integrator"] == "hybrid":
        doubled = ", two at once between output and record samples" if a["steps"] < a["substeps"] else ""
        out.print(
            f"  integrator: hybrid — {a['steps']:,} exact steps while no contact is possible ({a['substeps']:,} "
            f"substeps of {a['substep_s']:.4g} s{doubled}); the CDM at Δt "
            f"where one is ({a['cdm_steps_per_substep']:,} steps per substep; "
            f"{a['steps_of_dt']:,} steps of Δt would span the whole {a['duration_s']:g} s)",
            markup=False,
        )
        if a["yield_dt_s"]:
            out.print(f"  where only yielding members need the CDM: Δt = {a['yield_dt_s']:.4g} s "
                      f"(the structure's limit × the yielding fraction)", markup=False)  # fmt: skip
    else:
        out.print(f"  integrator: cdm — the central difference method, {a['steps']:,} steps of Δt", markup=False)


def _impact_parameters(p: dict[str, Any]) -> str:
    """A contact pair's resolved impact parameters in words."""
    if p["restitution"] is not None:
        normal = f"normal dashpot for e = {p['restitution']:.3g} (ζ = {p['damping_ratio_normal']:.4g})"
    elif p["damping_normal_N_s_per_m"]:
        normal = f"normal dashpot {p['damping_normal_N_s_per_m']:.4g} N·s/m"
    else:
        normal = "no normal dashpot"
    tangential = p["damping_tangential_N_s_per_m"]
    return (f"k_N = {p['k_normal_N_per_m2'] / 1e3:.4g} kN/m², k_T = {p['k_tangential_N_per_m'] / 1e3:.4g} kN/m; "
            f"μ_s = {p['friction_static']:g}, μ_k = {p['friction_kinetic']:g}; {normal}"
            + (f", tangential dashpot {tangential:.4g} N·s/m" if tangential else ""))  # fmt: skip


def _print_record(s: dict[str, Any]) -> None:
    m = s["metadata"]
    out.print(f"[bold]{m['name'] or s['file']}[/bold]  ({s['kind']} {s['file']})")
    event = ", ".join(x for x in (m["event"], m["date"]) if x)
    if m["magnitude"] is not None:
        event += f"{', ' if event else ''}M {m['magnitude']:g}"
    for label, text in (("event", event), ("station", ", ".join(x for x in (m["station"], m["network"]) if x)),
                        ("source", m["source"]), ("notes", m["notes"])):  # fmt: skip
        if text:
            out.print(f"{label}: {text}", markup=False)
    out.print(f"processing: {'; '.join(s['processing']) if s['processing'] else 'none'}", markup=False)
    table = Table()
    table.add_column("")
    for c in s["components"]:
        table.add_column(c["name"], justify="right")
    rows = [
        ("file", lambda c: Path(c["file"]).name + (f" [{c['trace_id']}]" if c["trace_id"] else "")),
        ("azimuth", lambda c: "-" if c["azimuth_deg"] is None else f"{c['azimuth_deg']:g}°"),
        ("Δt (s)", lambda c: f"{c['dt_s']:g}"),
        ("points", lambda c: str(c["points"])),
        ("duration (s)", lambda c: f"{c['duration_s']:.2f}"),
        ("PGA (g)", lambda c: f"{c['pga_g']:.4f} at {c['pga_time_s']:.2f} s"),
        ("PGA (m/s²)", lambda c: f"{c['pga_m_s2']:.4g}"),
        ("PGV (m/s)", lambda c: f"{c['pgv_m_s']:.4g} at {c['pgv_time_s']:.2f} s"),
        ("PGD (m)", lambda c: f"{c['pgd_m']:.4g} at {c['pgd_time_s']:.2f} s"),
        ("Arias intensity (m/s)", lambda c: f"{c['arias_intensity_m_s']:.4g}"),
        ("D5-95 (s)", lambda c: f"{c['significant_duration_s']:.2f} ({c['t5_s']:.2f}-{c['t95_s']:.2f} s)"),
    ]
    for label, cell in rows:
        table.add_row(label, *(cell(c) for c in s["components"]))
    out.print(table, soft_wrap=False)
    if s["scale_factor"] != 1.0:
        out.print(f"scale factor: {s['scale_factor']:.6g}", markup=False)
    for note in s["notes"]:
        out.print(f"note: {note}", markup=False)
    out.print("PGV, PGD: " + s["integration"], markup=False)


def main() -> None:
    """Console-script entry point. typer ends a KeyboardInterrupt (Ctrl-C, or a SIGTERM once
    __main__ took it over) that arrives while it parses the command line with exit 130 and
    no word, and one that arrives while typer builds the command from the functions' signatures
    (before any command runs) escapes it; pound's contract for an interrupted command is exit
    1, "interrupted"."""
    from .interrupts import InterruptedAfterWriting, die_by

    try:
        app(prog_name="pound")
    except InterruptedAfterWriting as exc:  # the results have their final name: the signal's own end, never exit 1
        die_by(exc.signum)
    except KeyboardInterrupt:
        err.print("interrupted", markup=False)
        raise SystemExit(1) from None
    except SystemExit as exc:
        if exc.code == 130:
            err.print("interrupted", markup=False)
            raise SystemExit(1) from None
        raise
