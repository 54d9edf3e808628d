"""`pound export RESULT.h5 --csv DIR`: tidy CSV files that read back to what read_hdf5 gives,
units in the headers, --json describing them, written all together or not at all."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_array_equal
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app
from pounding_cli.errors import WriteError
from pounding_cli.export import QUANTITIES
from pounding_cli.model import read_document

from conftest import INPUTS, load_doc

runner = CliRunner()


def run_of(tmp_path_factory: pytest.TempPathFactory, name: str, duration: float) -> Path:
    doc = read_document(INPUTS / name)
    doc["analysis"]["duration"] = duration
    out = tmp_path_factory.mktemp("export") / name.replace(".toml", ".h5")
    pound.run_model(load_doc(doc), output=out)
    return out


@pytest.fixture(scope="module")
def pounding(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The paper's buildings 5 cm apart, through their impact at 14.58 s."""
    return run_of(tmp_path_factory, "paper_pounding.toml", 15.0)


@pytest.fixture(scope="module")
def isolated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An isolated building: yielding members (its isolators)."""
    return run_of(tmp_path_factory, "isolated_moat.toml", 2.0)


def read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def numbers(rows: list[list[str]], column: int) -> np.ndarray:
    return np.array([float(r[column]) if r[column] != "" else np.nan for r in rows])


def test_histories_read_back_exactly(pounding: Path, tmp_path: Path) -> None:
    r = pound.read_hdf5(pounding)
    written = pound.export_csv(pounding, tmp_path, ["histories"])
    assert [w["quantity"] for w in written] == ["displacement", "velocity", "acceleration", "ground", "energy",
                                                 "contact", "yielding"]  # fmt: skip
    header, rows = read_csv(tmp_path / "displacement.csv")
    assert header == ["time [s]", "building", "floor", "u_x [m]", "u_y [m]", "theta_z [rad]"]
    n_floors = sum(b.elevation.size for b in r.buildings.values())
    assert len(rows) == r.time.size * n_floors
    left = [row for row in rows if row[1] == "left" and row[2] == "4"]
    assert_array_equal(numbers(left, 0), r.time)
    for k in range(3):
        assert_array_equal(numbers(left, 3 + k), r.buildings["left"].displacement[:, 3, k])
    header, rows = read_csv(tmp_path / "acceleration.csv")
    assert header[3:] == ["a_x [m/s2]", "a_y [m/s2]", "a_theta_z [rad/s2]"]
    right = [row for row in rows if row[1] == "right" and row[2] == "1"]
    assert_array_equal(numbers(right, 4), r.buildings["right"].acceleration[:, 0, 1])
    header, rows = read_csv(tmp_path / "ground.csv")
    assert header == ["time [s]", "a_X [m/s2]", "a_Y [m/s2]"]
    assert_array_equal(np.column_stack([numbers(rows, 1), numbers(rows, 2)]), r.ground_acceleration)
    header, rows = read_csv(tmp_path / "energy.csv")
    assert header[1] == "input [J]" and header[-1] == "balance_error [J]"
    assert_array_equal(numbers(rows, 1), r.energy_column("input"))
    header, rows = read_csv(tmp_path / "contact.csv")
    assert header[6:8] == ["normal_force [N]", "tangential_force [N]"]
    third = [row for row in rows if row[1] == "2"]
    assert_array_equal(numbers(third, 6), r.contact.normal_force[:, 2])
    assert read_csv(tmp_path / "yielding.csv")[1] == []  # no yielding members: the header alone


def test_single_precision_histories_are_written_in_their_shortest_form(tmp_path: Path) -> None:
    """A run with history_precision = "single" (here the isolated building with its yielding
    isolators): each float32 history value is written with the fewest digits that read back
    to it (numpy's shortest repr, at most 9 significant digits), not the 17 of the float64
    that holds it; read as float32 it is the stored value exactly."""
    doc = read_document(INPUTS / "isolated_moat.toml")
    doc["analysis"].update(duration=2.0, history_precision="single", column_force_histories=True)
    out = tmp_path / "single.h5"
    pound.run_model(load_doc(doc), output=out)
    r = pound.read_hdf5(out)
    pound.export_csv(out, tmp_path, ["displacement", "storey_shear", "column_forces", "yielding"])
    name, b = next(iter(r.buildings.items()))
    for file, column, key, stored in (("displacement.csv", 3, "1", b.displacement[:, 0, 0]),  # floor 1
                                      ("storey_shear.csv", 3, "1", b.forces.storey_shear[:, 0, 0]),  # storey 1
                                      ("column_forces.csv", -4, None, None),
                                      ("yielding.csv", 6, "0", b.yielding.deflection[:, 0, 0])):  # fmt: skip
        header, rows = read_csv(tmp_path / file)
        rows = [row for row in rows if row[1] == name and key in (None, row[2])]
        cells = [row[column] for row in rows if row[column] != ""]
        digits = [len(c.split("e")[0].replace("-", "").replace(".", "").strip("0")) for c in cells]
        assert cells and max(digits) <= 9, file
        if stored is not None:
            assert_array_equal(np.array(cells, dtype=np.float32), stored, err_msg=file)


def test_peaks_and_impacts_read_back(pounding: Path, tmp_path: Path) -> None:
    r = pound.read_hdf5(pounding)
    pound.export_csv(pounding, tmp_path, ["peaks", "impacts"])
    header, rows = read_csv(tmp_path / "interstorey_peaks.csv")
    assert header == ["building", "column", "storey", "dx [m]", "dy [m]", "dtheta [rad]"]
    c9 = [row for row in rows if row[:2] == ["left", "C9"]]
    assert_array_equal(np.column_stack([numbers(c9, 3 + k) for k in range(3)]), r.buildings["left"].column("C9"))
    header, rows = read_csv(tmp_path / "floor_peaks.csv")
    assert header[2:6] == ["elevation [m]", "u_x [m]", "u_y [m]", "theta_z [rad]"]
    assert_array_equal(numbers([row for row in rows if row[0] == "right"], 8), r.buildings["right"].peak_acceleration[:, 2])
    header, rows = read_csv(tmp_path / "impacts.csv")
    events = r.contact.events
    assert len(rows) == events.size >= 1
    assert header[:6] == ["body_a", "body_b", "level", "t_start [s]", "t_end [s]", "peak_normal_force [N]"]
    assert header[6] == "normal_impulse [N*s]"
    assert [row[0] for row in rows] == list(events["body_a"])
    assert_array_equal(numbers(rows, 5), events["peak_normal_force"])
    assert [row[11] for row in rows] == [str(bool(s)) for s in events["slid"]]
    assert not (tmp_path / "displacement.csv").exists()  # only what was asked for


def test_yielding_members_and_empty_cells(isolated: Path, tmp_path: Path) -> None:
    r = pound.read_hdf5(isolated)
    pound.export_csv(isolated, tmp_path, ["yielding", "interstorey_peaks"])
    header, rows = read_csv(tmp_path / "yielding.csv")
    assert header[-4:] == ["deflection_x [m]", "deflection_y [m]", "force_x [N]", "force_y [N]"]
    y = r.buildings["isolated"].yielding
    first = [row for row in rows if row[1] == "isolated" and row[2] == "0"]
    assert first[0][3:6] == [y.members["name"][0], "isolator", "1"]
    assert_array_equal(numbers(first, 8), y.force[:, 0, 0])
    _, rows = read_csv(tmp_path / "interstorey_peaks.csv")
    isd = np.concatenate([b.interstorey_deflection.reshape(-1, 3) for b in r.buildings.values()])
    assert_array_equal(np.isnan(isd[:, 0]), [row[3] == "" for row in rows])  # NaN: an empty cell


def test_pandas_reads_them_with_their_units(pounding: Path, tmp_path: Path) -> None:
    pandas = pytest.importorskip("pandas")
    pound.export_csv(pounding, tmp_path, ["displacement"])
    frame = pandas.read_csv(tmp_path / "displacement.csv")
    assert list(frame.columns) == ["time [s]", "building", "floor", "u_x [m]", "u_y [m]", "theta_z [rad]"]
    assert frame["u_x [m]"].dtype == np.float64 and frame["floor"].dtype == np.int64


def test_cli_json_describes_what_was_written(pounding: Path, tmp_path: Path) -> None:
    r = runner.invoke(app, ["export", str(pounding), "--csv", str(tmp_path / "csv"), "--what", "ground",
                            "--what", "impacts", "--json"])  # fmt: skip
    assert r.exit_code == 0, r.output
    doc = json.loads(r.stdout)
    assert doc["result"] == str(pounding) and doc["folder"] == str(tmp_path / "csv")
    assert [(f["quantity"], Path(f["file"]).name) for f in doc["files"]] == [("ground", "ground.csv"),
                                                                              ("impacts", "impacts.csv")]  # fmt: skip
    ground = doc["files"][0]
    assert ground["columns"] == [{"name": "time", "unit": "s"}, {"name": "a_X", "unit": "m/s2"},
                                 {"name": "a_Y", "unit": "m/s2"}]  # fmt: skip
    assert ground["rows"] == len(read_csv(Path(ground["file"]))[1]) == pound.read_hdf5(pounding).time.size


def test_existing_files_are_kept_without_force(pounding: Path, tmp_path: Path) -> None:
    (tmp_path / "ground.csv").write_text("mine\n")
    r = runner.invoke(app, ["export", str(pounding), "--csv", str(tmp_path), "--what", "ground", "--what", "energy"])
    assert r.exit_code == 2
    assert r.stderr.strip() == f"{tmp_path / 'ground.csv'}: exists; choose another folder or pass --force to overwrite it"
    assert (tmp_path / "ground.csv").read_text() == "mine\n" and not (tmp_path / "energy.csv").exists()
    r = runner.invoke(app, ["export", str(pounding), "--csv", str(tmp_path), "--what", "ground", "--force"])
    assert r.exit_code == 0 and read_csv(tmp_path / "ground.csv")[0][0] == "time [s]"
    assert r.stderr.strip() == f"wrote {tmp_path / 'ground.csv'} ({pound.read_hdf5(pounding).time.size:,} rows)"


def test_nothing_is_written_when_one_file_fails(pounding: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(result):
        raise OSError(28, "No space left on device")

    monkeypatch.setitem(QUANTITIES, "energy", QUANTITIES["energy"].__class__("broken", broken))
    with pytest.raises(WriteError, match=r"energy\.csv: cannot write the file \(No space left on device\)"):
        pound.export_csv(pounding, tmp_path, ["ground", "energy", "impacts"])
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # not ground.csv either, no temporary file


@pytest.mark.parametrize("case", ["unknown quantity", "not a result", "missing", "the result itself"])
def test_bad_input_exits_2_naming_it(case: str, pounding: Path, tmp_path: Path) -> None:
    args = ["export", str(pounding), "--csv", str(tmp_path)]
    if case == "unknown quantity":
        args += ["--what", "forces?"]
        expected = "--what: unknown quantity 'forces?'; choose from displacement, "
    elif case == "not a result":
        (tmp_path / "x.h5").write_text("not HDF5")
        args[1] = str(tmp_path / "x.h5")
        expected = f"{tmp_path / 'x.h5'}: not an HDF5 file"
    elif case == "missing":
        args[1] = str(tmp_path / "none.h5")
        expected = f"{tmp_path / 'none.h5'}: no such file"
    else:
        result = tmp_path / "impacts.csv"  # a result file named like an output
        result.write_bytes(pounding.read_bytes())
        args[1:2] = [str(result), "--what", "impacts", "--force"]
        expected = f"{result}: is the result file being exported ({result}); writing there would destroy it"
    r = runner.invoke(app, args)
    assert r.exit_code == 2, r.output
    assert r.stderr.startswith(expected), r.stderr
