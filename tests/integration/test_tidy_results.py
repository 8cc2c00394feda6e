"""Tidy results (issue 23, items 2 and 3): ``Result.to_dataframe`` is the CSV's table, the
metrics a tidy table, signals labelled DataArrays."""

from __future__ import annotations

import csv
import io

import numpy as np
import pandas as pd
import pytest

import webline


#: 5 s of the converter once for the module (its run takes about a second)
@pytest.fixture(scope="module")
def converter() -> webline.Result:
    return webline.simulate("converter", "5 s")


def test_dataframe_is_one_row_per_record_one_column_per_signal_and_element(
        converter, tmp_path) -> None:
    """5 s of ``converter``: one row per record (indexed by time [s]) and exactly the CSV's
    columns, in its order, with its values; under 50 MB (the issue's bound: it was 2.8 M rows
    and 1.3 GB, every combination of time, span, node, drive and roll)."""
    df = converter.to_dataframe()
    path = converter.to_csv(tmp_path / "results.csv")
    with path.open() as f:
        header = next(csv.reader(f))
    names = [h.rsplit(" [", 1)[0] for h in header]  # 'tension[span1] [N]' -> 'tension[span1]'
    assert df.shape == (len(converter.time), len(header) - 1)
    assert df.index.name == "time" and list(names[1:]) == list(df.columns)
    np.testing.assert_array_equal(df.index.to_numpy(), converter.time)
    k = 1
    np.testing.assert_array_equal(df[f"tension[{converter.span_names[k]}]"],
                                  converter.tension[:, k])
    # the CSV holds the same numbers to its 9 significant digits
    table = np.loadtxt(io.StringIO(path.read_text()), delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[:, 1:], df.to_numpy(dtype=float), rtol=1e-8, atol=1e-300,
                               equal_nan=True)
    assert df.attrs["units"][f"tension[{converter.span_names[0]}]"] == "N"
    assert df.memory_usage(deep=True).sum() < 50e6


def test_metrics_is_a_tidy_table(converter) -> None:
    """``metrics()``: one row per (element, metric) with its value and unit, the same numbers
    as the dictionary form ``metrics_by_element()``; the status in ``attrs``."""
    table = converter.metrics()
    assert isinstance(table, pd.DataFrame)
    assert list(table.columns) == ["element", "metric", "value", "unit"]
    by_element = converter.metrics_by_element()
    expected = [(element, metric, value) for metric, values in by_element.items()
                if metric != "status" for element, value in values.items()]
    assert len(table) == len(expected)
    for element, metric, value in expected:
        row = table[(table.element == element) & (table.metric == metric)]
        assert len(row) == 1
        np.testing.assert_equal(row.value.iloc[0], value)
    assert set(table.unit[table.metric == "slack_time"]) == {"s"}
    assert set(table.unit[table.metric == "tension_max"]) == {"N"}
    assert table.attrs["status"] == converter.status == by_element["status"]


def test_signals_are_labelled_dataarrays(converter) -> None:
    """``result.signals.tension``: an xarray DataArray over (time, span) with its units, so
    ``.sel(span=...)`` picks a span by name; the same numbers as ``result.tension``."""
    tension = converter.signals.tension
    assert tension.dims == ("time", "span") and tension.attrs["units"] == "N"
    assert list(tension.span.values) == converter.span_names
    assert tension.time.attrs["units"] == "s"
    name = converter.span_names[2]
    np.testing.assert_array_equal(tension.sel(span=name).values, converter.tension[:, 2])
    assert converter.signals.torque.dims == ("time", "drive")
    assert "tension" in dir(converter.signals)
