"""The atlas's compressed store (issue 14: the 96-level atlas under ~400 MB): strings stored as
compressed UTF-8 character arrays, not as uncompressible variable-length strings, and every value
read back unchanged."""

import netCDF4
import numpy as np
import xarray as xr

from contactvib.sweeps.dataset import compressed_encoding, write_atomic


def test_strings_are_compressed_char_arrays_and_values_unchanged(small_dataset, tmp_path):
    ds = xr.load_dataset(small_dataset)
    strings = [n for n, v in ds.variables.items() if v.ndim and v.dtype.kind in "OU"]
    assert {"kind", "resonance", "attractor_type", "found_by"} <= set(strings)
    write_atomic(ds, tmp_path / "c.nc", compress=True)
    back = xr.load_dataset(tmp_path / "c.nc")
    assert back.identical(ds)
    for n in strings:
        np.testing.assert_array_equal(back[n].values, ds[n].values, err_msg=n)
    with netCDF4.Dataset(tmp_path / "c.nc") as nc:
        for n in strings:
            v = nc.variables[n]
            assert v.dtype == np.dtype("S1") and v.filters()["zlib"], n
        assert nc.variables["harmonics_um"].dtype == np.float64  # lossless: float64 kept


def test_char_strings_are_smaller_than_vlen_strings(small_dataset, tmp_path):
    """At a level's size (the small dataset's words repeated to 10,000 points) the char arrays are
    under a third of the variable-length strings."""
    ds = xr.load_dataset(small_dataset)
    names = ["kind", "resonance", "attractor_type", "found_by", "origin"]
    n = ds.sizes["point"]
    words = xr.Dataset({k: ("point", np.tile(ds[k].values, 10_000 // n + 1)[:10_000]) for k in names})
    enc = compressed_encoding(words)
    assert all(enc[k]["dtype"] == "S1" and enc[k]["zlib"] for k in names)
    vlen = {k: {a: b for a, b in v.items() if a != "dtype"} for k, v in enc.items()}
    words.to_netcdf(tmp_path / "char.nc", engine="netcdf4", encoding=enc)
    words.to_netcdf(tmp_path / "vlen.nc", engine="netcdf4", encoding=vlen)
    assert (tmp_path / "char.nc").stat().st_size < (tmp_path / "vlen.nc").stat().st_size / 3
    assert xr.load_dataset(tmp_path / "char.nc").identical(words)


def test_non_ascii_and_empty_strings_round_trip(tmp_path):
    ds = xr.Dataset({"label": ("point", np.array(["", "1/2 µ", "ẏ"], dtype=object)),
                     "empty": ("other", np.array([], dtype=str))})
    write_atomic(ds, tmp_path / "s.nc", compress=True)
    back = xr.load_dataset(tmp_path / "s.nc")
    assert list(back["label"].values) == ["", "1/2 µ", "ẏ"] and back["empty"].size == 0
