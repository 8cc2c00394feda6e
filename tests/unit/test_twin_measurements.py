"""load_measurements (issue 24 item 1): webline's own results files load as they are, units
come from the headers, uneven sampling, gaps, NaNs and a time offset are resampled onto the
controller ticks and reported, and every bad file is one clear error."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import webline
from webline.errors import MissingExtra
from webline.twin import MeasurementError, load_measurements

LBF = 4.4482216152605  # N per pound-force (exact by definition of the avoirdupois pound)


@pytest.fixture(scope="module")
def converter():
    return webline.load_line("converter")


@pytest.fixture(scope="module")
def short_run(converter):
    return webline.simulate(converter, 2.0, scenario="startup")


def write_csv(path: Path, header: list[str], rows: np.ndarray) -> Path:
    lines = [",".join(header)] + [",".join(f"{v:.12g}" for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_runs_own_results_csv_loads_without_mapping(tmp_path, converter, short_run):
    path = short_run.to_csv(tmp_path / "results.csv")
    data = load_measurements(path, converter)
    assert data.dt == pytest.approx(1e-3)
    assert data.offset == 0.0
    # the CSV keeps 9 significant digits: 200 N to within 1e-6 N
    np.testing.assert_allclose(data.signals["tension[process_span]"],
                               short_run.tension[:, 3], atol=1e-5)
    np.testing.assert_allclose(data.signals["torque[unwind]"], short_run.torque[:, 0],
                               rtol=1e-8, atol=1e-8)
    assert any("skipped" in note for note in data.notes)  # flags, estimates: not compared


def test_a_runs_own_results_nc_loads_without_mapping(tmp_path, converter, short_run):
    path = short_run.to_netcdf(tmp_path / "results.nc")
    data = load_measurements(path, converter)
    np.testing.assert_array_equal(data.signals["speed[rewind]"], short_run.speed[:, -1])
    assert "Measurements" in repr(data) and len(repr(data).splitlines()) == 2


def test_units_from_the_header_and_a_mapping_for_foreign_names(tmp_path, converter):
    t = np.arange(0, 3.0, 0.01)
    rows = np.column_stack([t * 1000.0, np.full_like(t, 45.0), np.full_like(t, 600.0)])
    path = write_csv(tmp_path / "log.csv", ["t [ms]", "LC2 [lbf]", "v_drum [ft/min]"], rows)
    data = load_measurements(path, converter, mapping={
        "t": "time", "LC2": "tension[process_span]", "v_drum": "speed[drum]"})
    np.testing.assert_allclose(data.signals["tension[process_span]"], 45.0 * LBF, rtol=1e-12)
    np.testing.assert_allclose(data.signals["speed[drum]"], 600.0 * 0.3048 / 60.0, rtol=1e-12)
    assert data.duration == pytest.approx(2.99)


def test_uneven_sampling_gaps_nans_and_offset_are_resampled_and_reported(tmp_path, converter):
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.004, 0.006, 1000))  # ~200 Hz, uneven
    t = t[(t < 2.0) | (t > 2.5)]  # a 0.5 s gap in the logger
    y = 100.0 + 10.0 * t  # linear: linear interpolation must reproduce it exactly
    y[50] = np.nan
    offset = 1234.5  # a logger's clock
    path = write_csv(tmp_path / "log.csv", ["time [s]", "tension[process_span] [N]"],
                     np.column_stack([t + offset, y]))
    data = load_measurements(path, converter)
    ticks = data.time
    # its first time stamp (written with 12 digits: 1e-8 s)
    assert data.offset == pytest.approx(offset + t[0], abs=1e-7)
    assert np.allclose(np.diff(ticks), 1e-3)
    got = data.signals["tension[process_span]"]
    inside = (ticks + t[0] > 2.0 + 0.01) & (ticks + t[0] < 2.5 - 0.01)
    assert np.isnan(got[inside]).all()  # the gap is left empty, not bridged
    ok = np.isfinite(got)
    # the line through the samples, shifted by the first time stamp (t = 0 there)
    # (time stamps written to 1e-8 s, times a slope of 10 N/s: 1e-7 N)
    np.testing.assert_allclose(got[ok], 100.0 + 10.0 * (ticks[ok] + t[0]), atol=1e-6)
    text = data.report()
    for fragment in ("time offset", "uneven", "NaN samples dropped", "gaps"):
        assert fragment in text, text


def one_line(exc: pytest.ExceptionInfo, *fragments: str) -> None:
    message = str(exc.value)
    assert "\n" not in message
    for fragment in fragments:
        assert fragment in message, message


def test_unknown_column_is_named_with_close_names(tmp_path, converter):
    t = np.arange(0, 3, 0.01)
    path = write_csv(tmp_path / "bad.csv", ["time [s]", "tension[proces_span] [N]"],
                     np.column_stack([t, t]))
    with pytest.raises(MeasurementError) as exc:
        load_measurements(path, converter)
    one_line(exc, "bad.csv", "tension[proces_span]", "matches no signal",
             "tension[process_span]")


def test_wrong_unit_kind_is_refused(tmp_path, converter):
    t = np.arange(0, 3, 0.01)
    path = write_csv(tmp_path / "bad.csv", ["time [s]", "tension[process_span] [m/s]"],
                     np.column_stack([t, t]))
    with pytest.raises(MeasurementError) as exc:
        load_measurements(path, converter)
    one_line(exc, "bad.csv", "tension[process_span] [m/s]", "not a force")


def test_time_that_does_not_increase_is_refused(tmp_path, converter):
    t = np.arange(0, 3, 0.01)
    t[100] = t[98]
    path = write_csv(tmp_path / "bad.csv", ["time [s]", "tension[process_span] [N]"],
                     np.column_stack([t, t]))
    with pytest.raises(MeasurementError) as exc:
        load_measurements(path, converter)
    one_line(exc, "bad.csv", "time [s]", "does not increase at data row 101")


def test_a_record_too_short_names_what_it_cannot_identify(tmp_path, converter):
    # the converter's slowest loop is 4 rad/s: 5 time constants are 1.25 s
    t = np.arange(0, 0.5, 0.01)
    path = write_csv(tmp_path / "bad.csv", ["time [s]", "tension[process_span] [N]"],
                     np.column_stack([t, t]))
    with pytest.raises(MeasurementError) as exc:
        load_measurements(path, converter)
    one_line(exc, "bad.csv", "too short", "inertias", "friction", "modulus", "1.25 s")


def test_an_empty_file_is_refused(tmp_path, converter):
    path = tmp_path / "empty.csv"
    path.write_text("")
    with pytest.raises(MeasurementError) as exc:
        load_measurements(path, converter)
    one_line(exc, "empty.csv", "empty")


def test_parquet_without_pyarrow_names_the_extra(tmp_path, converter, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # as if the extra were not installed
    path = tmp_path / "log.parquet"
    path.write_bytes(b"PAR1")
    with pytest.raises(MissingExtra, match=r"webline\[parquet\]"):
        load_measurements(path, converter)


def test_a_parquet_log_reads_as_its_csv(tmp_path, converter):
    """The same columns written as Parquet (pyarrow, the ``parquet`` extra) and as CSV give
    the same measurements, value for value."""
    pytest.importorskip("pyarrow")
    import pandas as pd

    csv = webline.simulate(converter, 2.0).to_csv(tmp_path / "log.csv")
    pd.read_csv(csv).to_parquet(tmp_path / "log.parquet")  # webline's column names, units
    a = load_measurements(csv, converter).to_dataframe()
    b = load_measurements(tmp_path / "log.parquet", converter).to_dataframe()
    assert len(a) > 100 and a.equals(b)
