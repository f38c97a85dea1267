"""The appearance figures through Python, checked against `specula appearance --csv`."""

import numpy as np
import pytest

import specula
from conftest import read_csv


def assert_figures_match_row(figures, row):
    """Every CSV column of `row` (printed to 4 decimals, empty when unknown) in `figures`."""
    for column, text in row.items():
        if column == "source":
            continue
        if text == "":
            assert figures[column] is None, column
        else:
            assert figures[column] == pytest.approx(float(text), abs=5.01e-5), column


@pytest.fixture(scope="module")
def holed_silver(tmp_path_factory):
    """silver-925 tabulated, with the cells of theta_d >= 30 deg not measured."""
    table = specula.load("silver-925").tabulate()
    table[:, 30:] = np.nan
    path = tmp_path_factory.mktemp("appearance") / "holed.binary"
    specula.write_merl(path, table)
    return path


def test_appearance_matches_the_cli_against_a_reference(cli, holed_silver):
    sources = ["green-paint", "silver-925-scratched", str(holed_silver)]
    _, out, err = cli("appearance", *sources, "--against", "chrome", "--csv")
    rows = read_csv(out)
    assert [r["source"] for r in rows] == ["chrome", *sources]
    ours = specula.appearance(sources, against="chrome")
    assert isinstance(ours, list) and len(ours) == len(sources)
    for figures, row in zip(ours, rows[1:]):
        assert set(figures) == set(row) - {"source"} | {"name", "warnings"}
        assert_figures_match_row(figures, row)
    # The reference's own row: its figures alone, and no differences to itself.
    chrome = specula.appearance("chrome")
    assert not any(key.startswith(("d_", "de00_")) for key in chrome)
    assert_figures_match_row(chrome, {k: v for k, v in rows[0].items()
                                      if not k.startswith(("d_", "de00_"))})
    # The holed table misses colour readings: None here, empty there, and the same warnings.
    holed = ours[2]
    assert holed["name"] == "holed"
    assert any(holed[f"L_{g}"] is None for g in (15, 25, 45, 75, 110))
    cli_warnings = [line.split(": ", 2)[2] for line in err.splitlines()
                    if line.startswith(f"warning: {holed_silver}: ")]
    assert holed["warnings"] == cli_warnings and cli_warnings


def test_appearance_takes_a_brdf_an_array_or_a_source_alike(cli, holed_silver):
    _, out, _ = cli("appearance", "silver-925", "--csv", "--resolution", "1.82")
    row = read_csv(out)[0]
    silver = specula.load("silver-925")
    by_source = specula.appearance("silver-925", resolution_deg=1.82)
    assert_figures_match_row(by_source, row)
    assert by_source["name"] == "silver-925"
    assert specula.appearance(silver, resolution_deg=1.82) == by_source
    assert any("finer than the instrument" in w for w in by_source["warnings"])
    # A table as an array gives the figures of its file.
    _, out, _ = cli("appearance", holed_silver, "--csv")
    assert_figures_match_row(specula.appearance(specula.read_merl(holed_silver)), read_csv(out)[0])


def test_appearance_rejects_a_resolution_out_of_range():
    with pytest.raises(specula.SpeculaError,
                       match="resolution_deg 0: expected degrees above 0 and at most 90"):
        specula.appearance("chrome", resolution_deg=0.0)
