"""The HDF5 file follows the layout of DESIGN.md / docs/user-guide.md, atomically."""

from __future__ import annotations

import json
import re

import h5py
import numpy as np
import pytest
from numpy.testing import assert_array_equal

import pounding_cli as pound
from pounding_cli.solver import integrate

from conftest import EXAMPLE


@pytest.fixture(scope="module")
def example_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "out.h5"
    return pound.run_model(EXAMPLE, output=out), out


def test_layout_and_units(example_run):
    result, path = example_run
    with h5py.File(path, "r") as f:
        assert f.attrs["status"] == "complete"
        assert f.attrs["units"] == "SI"
        assert f.attrs["pound_version"] == pound.__version__
        assert len(f.attrs["input_sha256"]) == 64
        model = json.loads(f.attrs["model"])
        assert [b["name"] for b in model["buildings"]] == ["left", "right"]
        nt = f["time"].shape[0]
        assert f["time"].attrs["units"] == "s"
        assert f["ground/acceleration"].shape == (nt, 2)
        for name, floors, columns in (("left", 4, 9), ("right", 3, 15)):
            g = f[f"buildings/{name}"]
            for ds in ("displacement", "velocity", "acceleration"):
                assert g[ds].shape == (nt, floors, 3)
                assert "units" in g[ds].attrs
            assert g["velocity"].attrs["reference"] == "relative to the ground"
            assert g["acceleration"].attrs["reference"] == "absolute"
            assert g["columns"].shape == (columns,)
            assert set(("name", "x", "y", "section")) <= set(g["columns"].dtype.names)
            assert g["peaks/interstorey_deflection"].shape == (columns, floors, 3)
            assert g["peaks/interstorey_deflection"].attrs["units"] == "m, m, rad"
        assert f["buildings/left/columns"]["name"][8].decode() == "C9"
        assert_array_equal(f["buildings/left/columns"][8][["x", "y"]].tolist(), (8.0, 8.0))
        events = f["impacts/events"]
        assert events.shape == (0,)
        for field in ("body_a", "body_b", "level", "t_start", "t_end", "peak_normal_force", "normal_impulse",
                      "peak_area", "peak_depth", "x", "y", "slid", "tangential_force_at_peak", "normal_x",
                      "normal_y"):  # fmt: skip
            assert field in events.dtype.names
        assert f["energy"].shape == (nt, 7)
        assert f["energy"].attrs["columns"] == ", ".join(pound.results.ENERGY_NAMES)
        diag = f["diagnostics"].attrs
        for key in ("integrator", "dt", "steps", "contact_steps", "wall_time_s"):
            assert key in diag


def test_read_back_equals_what_was_written(example_run):
    result, path = example_run
    again = pound.read_hdf5(path)
    assert_array_equal(again.time, result.time)
    assert_array_equal(again.energy, result.energy)
    for name, b in result.buildings.items():
        c = again.buildings[name]
        assert_array_equal(c.displacement, b.displacement)
        assert_array_equal(c.interstorey_deflection, b.interstorey_deflection)
        assert c.column_names == b.column_names
        assert_array_equal(c.column_section, b.column_section)
    assert again.input_sha256 == result.input_sha256
    assert again.complete


def test_written_atomically_no_temporary_left(example_run):
    _, path = example_run
    assert sorted(p.name for p in path.parent.iterdir()) == ["out.h5"]


def test_same_input_same_datasets(tmp_path):
    """Two runs of the same model give bitwise-identical datasets and the same input hash."""
    a = pound.run_model(EXAMPLE, output=tmp_path / "a.h5")
    b = pound.run_model(EXAMPLE, output=tmp_path / "b.h5")
    assert a.input_sha256 == b.input_sha256
    with h5py.File(tmp_path / "a.h5") as fa, h5py.File(tmp_path / "b.h5") as fb:
        names = []
        fa.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        for n in names:
            x, y = fa[n][()], fb[n][()]
            for field in x.dtype.names or (None,):
                xf, yf = (x, y) if field is None else (x[field], y[field])
                if xf.dtype.hasobject:  # variable-length strings: compare the values
                    assert xf.tolist() == yf.tolist(), (n, field)
                else:
                    assert xf.tobytes() == yf.tobytes(), (n, field)


def test_diverged_run_is_written_and_marked(tmp_path, monkeypatch):
    """A run that blows up keeps its partial results with status "failed: …"."""
    from pounding_cli import api
    from pounding_cli.assembly import TimeGrid

    def beyond_the_limit(analysis, omega_max, duration, *args, **kwargs):
        limit = 2 / omega_max
        return TimeGrid(dt=1.05 * limit, stride=1, n_steps=int(duration / limit), stability_limit=limit)

    # the input check refuses such a step, so bypass the time-grid choice
    monkeypatch.setattr(api, "time_grid", beyond_the_limit)
    result = pound.run_model(EXAMPLE, output=tmp_path / "x.h5")
    assert re.match(r"failed: (diverged|unstable) at step \d+ \(t = ", result.status)
    with h5py.File(tmp_path / "x.h5") as f:
        assert re.match(r"failed: (diverged|unstable)", f.attrs["status"])
        n = f["time"].shape[0]
        assert 0 < n < 2000
        assert np.isfinite(f["buildings/left/displacement"][()]).all()
        assert (np.abs(f["buildings/left/displacement"][()]) <= integrate.DIVERGENCE_LIMIT).all()


def test_impacts_written_and_read_back(tmp_path):
    """The pounding example: one impact at the third floor; the impact log, the pairs and the
    contact histories in /impacts, and read_hdf5 returns them unchanged."""
    path = tmp_path / "p.h5"
    result = pound.run_model(EXAMPLE.with_name("paper_pounding.toml"), output=path)
    c = result.contact
    assert c.impact_count == 1
    with h5py.File(path) as f:
        events = f["impacts/events"][()]
        assert events.shape == (1,)
        assert events["body_a"][0].decode() == "left" and events["body_b"][0].decode() == "right"
        assert events["level"][0] == 3 and events["floor_b"][0] == 3
        assert events["t_end"][0] > events["t_start"][0]
        assert f["impacts/pairs"].shape == (3,)
        nt = f["time"].shape[0]
        for name in ("normal_force", "tangential_force", "area", "depth"):
            assert f[f"impacts/{name}"].shape == (nt, 3)
        assert f["impacts/action_point"].shape == (nt, 3, 2)
        # the contact column of the energy is the work the contacts took; the balance closes
        # to the error of the sixth-order quadrature over the hybrid's exact steps of 2 and
        # 4 ms and of the trapezoidal rule over its CDM steps of 2.6 µs (measured 2.1e-9)
        assert abs(f["energy"][:, 6]).max() < 1e-6 * f["energy"][:, 0].max()
    again = pound.read_hdf5(path)
    assert repr(again.contact.events.tolist()) == repr(c.events.tolist())  # repr: NaN (xi of a slab–slab contact) equals NaN
    assert_array_equal(again.contact.normal_force, c.normal_force)
    assert repr(again.contact.pairs.tolist()) == repr(c.pairs.tolist())


def test_impact_log_of_an_older_file_reads_with_nan(tmp_path):
    """A file written before the impact log kept F_T and n at the peak reads back with NaN in
    those columns (the other columns unchanged); the report says null and the plan view
    recomputes the normal and draws no F_T."""
    from pounding_cli.report import open_run, summary
    from pounding_cli.report.geometry import plan_geometry
    from pounding_cli.report.plan import peak_instant

    path = tmp_path / "old.h5"
    result = pound.run_model(EXAMPLE.with_name("paper_pounding.toml"), output=path)
    new = ("tangential_force_at_peak", "normal_x", "normal_y")
    with h5py.File(path, "r+") as f:
        events = f["impacts/events"][()]
        old = events[[n for n in events.dtype.names if n not in new]]
        units = f["impacts/events"].attrs["units"]
        del f["impacts/events"]
        f.create_dataset("impacts/events", data=old).attrs["units"] = units
    again = pound.read_hdf5(path).contact.events
    assert np.isnan(again[list(new)].tolist()).all()
    kept = [n for n in again.dtype.names if n not in new]
    assert repr(again[kept].tolist()) == repr(result.contact.events[kept].tolist())  # repr: NaN equals NaN
    assert summary(path)["impacts"]["peak"]["tangential_force_at_peak"] is None
    run = open_run(path)
    instant = peak_instant(run, plan_geometry(run))
    assert instant.contacts[0].f_tangential is None and "F_T not logged" in instant.description
    np.testing.assert_allclose(instant.contacts[0].normal, [1.0, 0.0], atol=0.02)


def test_friction_times_of_an_older_file_read_as_absent(tmp_path):
    """A file written before the impact log located its friction switches (issue 28) reads back
    with t_slip, t_stick NaN and slips 0 (the other columns unchanged), and the report says null."""
    from pounding_cli.report import summary

    path = tmp_path / "old.h5"
    result = pound.run_model(EXAMPLE.with_name("paper_pounding.toml"), output=path)
    assert result.contact.events["slips"].max() >= 1, "the example's impact slips"
    new = ("t_slip", "t_stick", "slips")
    with h5py.File(path, "r+") as f:
        events = f["impacts/events"][()]
        units = f["impacts/events"].attrs["units"]
        del f["impacts/events"]
        f.create_dataset("impacts/events", data=events[[n for n in events.dtype.names if n not in new]]).attrs[
            "units"] = units
    again = pound.read_hdf5(path).contact.events
    assert np.isnan(again["t_slip"]).all() and np.isnan(again["t_stick"]).all() and (again["slips"] == 0).all()
    kept = [n for n in again.dtype.names if n not in new]
    assert repr(again[kept].tolist()) == repr(result.contact.events[kept].tolist())  # repr: NaN equals NaN
    event = summary(path)["impacts"]["events"][0]
    assert event["t_slip"] is None and event["t_stick"] is None and event["slips"] == 0


def _histories(b) -> dict[str, np.ndarray]:
    """The buildings' histories that analysis.history_precision stores (motion, forces,
    yielding members), by name."""
    out = {"displacement": b.displacement, "velocity": b.velocity, "acceleration": b.acceleration,
           "storey_shear": b.forces.storey_shear, "base_shear": b.forces.base_shear,
           "column_shear": b.forces.column_shear, "column_moment": b.forces.column_moment}  # fmt: skip
    if b.yielding is not None:
        out.update(member_deflection=b.yielding.deflection, member_force=b.yielding.force)
    return out


def test_single_precision_histories_are_the_double_ones_rounded(tmp_path):
    """analysis.history_precision = "single" changes what is stored, not what is computed: the
    solver runs in double precision either way, so every building history of the single file
    is the double run's rounded to float32 (IEEE round to nearest), equal bit for bit, and the
    peaks, impact log, contact histories and energies are the double run's exactly. The
    inelastic example with its column force histories covers every history the setting
    stores (motion, storey and column forces, yielding members); at twice the record it has
    impacts."""
    from conftest import INPUTS
    from pounding_cli.model.load import read_document, validate_model

    doc = read_document(INPUTS / "paper_inelastic.toml")
    doc["analysis"]["column_force_histories"] = True
    doc["excitation"]["scale"] = 2.0  # 8 impacts
    runs = {}
    for precision in ("double", "single"):
        doc["analysis"]["history_precision"] = precision
        out = tmp_path / f"{precision}.h5"
        pound.run_model(validate_model(doc, INPUTS / f"{precision}.toml"), output=out)
        runs[precision] = pound.read_hdf5(out)
    double, single = runs["double"], runs["single"]
    assert double.contact.events.size > 0
    assert_array_equal(single.energy, double.energy)
    for field in double.contact.events.dtype.names:  # by field: assert_array_equal takes NaN = NaN there
        assert_array_equal(single.contact.events[field], double.contact.events[field], err_msg=field)
    assert_array_equal(np.asarray(single.contact.normal_force), np.asarray(double.contact.normal_force))
    for name, b in double.buildings.items():
        s = single.buildings[name]
        histories = _histories(b)
        for key, value in _histories(s).items():
            assert value.dtype == np.float32, key
            assert histories[key].dtype == np.float64, key
            assert_array_equal(value, histories[key].astype(np.float32), err_msg=key)
        assert_array_equal(s.peak_displacement, b.peak_displacement)
        assert_array_equal(s.interstorey_deflection, b.interstorey_deflection)
        assert_array_equal(s.forces.peak_storey_shear, b.forces.peak_storey_shear)
        assert_array_equal(np.asarray(s.forces.floor_contact), np.asarray(b.forces.floor_contact))
    with h5py.File(tmp_path / "single.h5") as f:
        assert f["buildings/left/displacement"].dtype == np.float32
        assert f["energy"].dtype == np.float64
    assert (tmp_path / "single.h5").stat().st_size < 0.6 * (tmp_path / "double.h5").stat().st_size
