"""Result files open in xarray with named dimensions, time as a coordinate and units per
variable (HDF5 dimension scales, read through h5netcdf); files written before the scales
existed still read with read_hdf5."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from numpy.testing import assert_array_equal

import pounding_cli as pound
from pounding_cli.model import read_document

from conftest import INPUTS, load_doc

xr = pytest.importorskip("xarray")
pytest.importorskip("h5netcdf")


@pytest.fixture(scope="module")
def isolated_run(tmp_path_factory: pytest.TempPathFactory) -> pound.RunResult:
    """The shipped isolated building in its moat beside a neighbour (isolators: yielding
    members; floors and walls: contact pairs), 3 s of it."""
    doc = read_document(INPUTS / "isolated_moat.toml")
    doc["analysis"]["duration"] = 3.0
    return pound.run_model(load_doc(doc), output=tmp_path_factory.mktemp("xr") / "isolated.h5")


def test_every_variable_has_named_dimensions_and_units(isolated_run: pound.RunResult) -> None:
    tree = xr.open_datatree(isolated_run.output, engine="h5netcdf")
    seen = 0
    for node in tree.subtree:
        for name, var in node.to_dataset(inherit=False).variables.items():
            assert not any(d.startswith("phony_dim") for d in var.dims), f"{node.path}/{name}: {var.dims}"
            assert isinstance(var.attrs.get("units"), str) and var.attrs["units"], f"{node.path}/{name} has no units"
            seen += 1
    assert seen > 40


def test_a_building_opens_with_time_floor_component_coordinates(isolated_run: pound.RunResult) -> None:
    b = isolated_run.buildings["isolated"]
    ds = xr.open_dataset(isolated_run.output, engine="h5netcdf", group="buildings/isolated")
    assert ds["displacement"].dims == ("time", "floor", "component")
    assert_array_equal(ds["time"].values, isolated_run.time)
    assert ds["time"].attrs["units"] == "s"
    assert_array_equal(ds["floor"].values, np.arange(1, b.elevation.size + 1))
    assert list(ds["component"].values) == ["u_x", "u_y", "theta_z"]
    assert ds["displacement"].attrs["units"] == "m, m, rad"
    assert_array_equal(ds["displacement"].sel(floor=2, component="u_y").values, b.displacement[:, 1, 1])
    assert_array_equal(ds["velocity"].values, b.velocity)
    assert list(ds["column"].values) == b.column_names


def test_peaks_are_labelled_by_column_and_storey(isolated_run: pound.RunResult) -> None:
    b = isolated_run.buildings["isolated"]
    ds = xr.open_dataset(isolated_run.output, engine="h5netcdf", group="buildings/isolated/peaks")
    isd = ds["interstorey_deflection"]
    assert isd.dims == ("column", "storey", "component")
    name = b.column_names[-1]
    assert_array_equal(isd.sel(column=name).values, b.column(name))
    assert_array_equal(ds["storey"].values, np.arange(1, b.elevation.size + 1))
    assert ds["ductility"].dims == ("member", "local_axis")


def test_yielding_impacts_ground_energy_and_modes(isolated_run: pound.RunResult) -> None:
    tree = xr.open_datatree(isolated_run.output, engine="h5netcdf")
    y = tree["buildings/isolated/yielding"]
    assert y["force"].dims == ("time", "member", "local_axis") and y["force"].attrs["units"] == "N"
    assert_array_equal(y["time"].values, isolated_run.time)  # inherited from the root
    impacts = tree["impacts"]
    assert impacts["normal_force"].dims == ("time", "pair")
    assert impacts["action_point"].dims == ("time", "pair", "axis")
    assert impacts.sizes["pair"] == isolated_run.contact.pairs.size
    assert impacts["events"].dims == ("event",)
    ground = tree["ground"]
    assert ground["acceleration"].dims == ("time", "axis") and list(ground["axis"].values) == ["X", "Y"]
    energy = tree.to_dataset()["energy"]
    assert energy.dims == ("time", "energy_term")
    assert_array_equal(energy.sel(energy_term="input").values, isolated_run.energy_column("input"))
    modes = tree["buildings/neighbour/modes"]
    assert modes["participating_mass_ratio"].dims == ("mode", "direction") and modes["period"].attrs["units"] == "s"


def strip_scales(path: Path) -> None:
    """Make `path` a file of the layout before dimension scales: detach every scale, remove
    the scale datasets (every name of each), keep /time as a plain dataset."""
    with h5py.File(path, "a") as f:
        names: list[str] = []
        f.visit_links(names.append)
        done: set[h5py.h5d.DatasetID] = set()  # a dataset with two names (hard links) once
        for name in names:
            obj = f[name]
            if isinstance(obj, h5py.Dataset) and obj.id not in done:
                done.add(obj.id)
                for axis, dim in enumerate(obj.dims):
                    for scale in list(dim.values()):
                        obj.dims[axis].detach_scale(scale)
        for name in sorted(names, key=len, reverse=True):
            obj = f.get(name)
            if isinstance(obj, h5py.Dataset) and obj.attrs.get("CLASS") == b"DIMENSION_SCALE" and name != "time":
                del f[name]
        for key in ("CLASS", "NAME", "REFERENCE_LIST"):
            if key in f["time"].attrs:
                del f["time"].attrs[key]


def test_a_file_written_before_the_scales_reads_the_same(isolated_run: pound.RunResult, tmp_path: Path) -> None:
    old = tmp_path / "old.h5"
    old.write_bytes(Path(isolated_run.output).read_bytes())
    strip_scales(old)
    with h5py.File(old, "r") as f:
        assert "floor" not in f["buildings/isolated"] and not f["time"].attrs.get("CLASS")
    ds = xr.open_dataset(old, engine="h5netcdf", group="buildings/isolated", phony_dims="sort")
    assert all(d.startswith("phony_dim") for d in ds["displacement"].dims)  # truly the old layout
    again, new = pound.read_hdf5(old), pound.read_hdf5(isolated_run.output)
    assert_array_equal(again.time, new.time)
    for name, b in new.buildings.items():
        assert_array_equal(again.buildings[name].displacement, b.displacement)
        assert_array_equal(again.buildings[name].interstorey_deflection, b.interstorey_deflection)
        assert_array_equal(again.buildings[name].yielding.force if b.yielding else 0, b.yielding.force if b.yielding else 0)
    assert_array_equal(again.contact.normal_force, new.contact.normal_force)
    assert again.diagnostics == new.diagnostics and again.warnings == new.warnings == []
