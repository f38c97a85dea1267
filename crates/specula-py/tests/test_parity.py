"""The Python package does what the CLI does: its version, one direction as well as
arrays, conversion, fitting and the through-instrument evaluation."""

import re

import numpy as np
import pytest

import specula
from conftest import read_csv

GRID = {"theta_h_samples": 8, "theta_d_step_deg": 15.0, "phi_d_step_deg": 30.0,
        "phi_d_span": "quarter"}
GRID_ARGS = ["--theta-h-samples", "8", "--theta-d-step", "15", "--phi-d-step", "30",
             "--phi-d-span", "quarter"]


def test_version_is_the_crates(cli):
    _, out, _ = cli("--version")
    assert out.split() == ["specula", specula.__version__]


def test_eval_takes_one_direction_as_well_as_arrays():
    brdf = specula.load("green-paint")
    wi = np.array([0.3, 0.1, np.sqrt(1 - 0.1)])
    wo = np.array([-0.2, 0.0, np.sqrt(1 - 0.04)])
    one = brdf.eval(wi, wo)
    assert one.shape == (3,)
    np.testing.assert_array_equal(one, brdf.eval(wi[None, :], wo[None, :])[0])
    with pytest.raises(specula.SpeculaError, match=r"\(3,\) directions or \(N, 3\) arrays"):
        brdf.eval(wi[:2], wo[:2])


def test_convert_writes_what_the_cli_writes(cli, tmp_path):
    ours, theirs = tmp_path / "py.binary", tmp_path / "cli.binary"
    done = specula.convert("green-paint", ours)
    cli("convert", "green-paint", theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    assert done["format"] == "MERL .binary" and done["measured"] > 0
    words = "grid 'fine': expected one of merl, utia"
    with pytest.raises(specula.SpeculaError, match=words):
        specula.convert("green-paint", tmp_path / "x.csv", grid="fine")
    status, _, stderr = cli("convert", "green-paint", tmp_path / "x.csv", "--grid", "fine",
                            check=False)
    assert status == 2 and words in stderr


def test_fit_exports_the_model_it_names(cli, tmp_path):
    got = specula.fit("chrome", model="conductor", out=tmp_path / "py.toml")
    _, out, _ = cli("fit", "chrome", "--model", "conductor", "--out", tmp_path / "cli.toml")
    assert got["exported"] == "conductor" == got["fits"][0]["model"]
    assert "exported model: conductor" in out
    assert (tmp_path / "py.toml").read_text() == (tmp_path / "cli.toml").read_text()
    assert got["fits"][0]["material"] == (tmp_path / "py.toml").read_text()
    words = "model 'gold': expected one of conductor, coat, both"
    with pytest.raises(specula.SpeculaError, match=words):
        specula.fit("chrome", model="gold")
    status, _, stderr = cli("fit", "chrome", "--model", "gold", check=False)
    assert status == 2 and words in stderr


def test_evaluate_through_the_instrument_matches_the_cli(cli):
    _, out, _ = cli("evaluate", "--truth", "chrome", "--method", "log", "--through-instrument",
                    *GRID_ARGS)
    row = read_csv("\n".join(out.splitlines()[1:]))[0]
    through = specula.evaluate("chrome", method="log", through_instrument=True, **GRID)
    plain = specula.evaluate("chrome", method="log", **GRID)
    assert through["within"]["relative_rmse"] == pytest.approx(float(row["rel_rmse_within"]),
                                                               abs=6e-6)
    assert through["within"]["relative_rmse"] != plain["within"]["relative_rmse"]


def test_render_returns_the_radiance_and_writes_what_the_cli_writes(cli, tmp_path):
    radiance = specula.render("chrome", out=tmp_path / "py.png", size=16, spp=2)
    cli("render", "chrome", "--out", tmp_path / "cli.png", "--size", "16", "--spp", "2")
    assert radiance.shape == (16, 16, 3) and np.isfinite(radiance).all() and radiance.max() > 0
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    with pytest.raises(specula.SpeculaError, match="choose one light"):
        specula.render("chrome", light="point", env="studio", size=16, spp=1)


def test_report_writes_the_page_the_cli_writes(cli, tmp_path):
    table = tmp_path / "paint.binary"
    specula.convert("green-paint", table)
    written = specula.report(table, tmp_path / "py.html", size=16, spp=1, title="paint")
    cli("report", table, "--out", tmp_path / "cli.html", "--size", "16", "--spp", "1",
        "--title", "paint")
    assert written == tmp_path / "py.html"
    page = written.read_text()
    assert page.startswith("<!DOCTYPE html>") and "paint" in page
    # The pages agree but for the time each took to make.
    took = re.compile(r"Report made in [0-9.]+ s")
    assert took.search(page)
    assert took.sub("", page) == took.sub("", (tmp_path / "cli.html").read_text())


def test_reconstruct_writes_what_the_cli_writes(cli, tmp_path):
    samples = specula.evaluate("green-paint", **GRID)["samples"]
    columns = [samples[k] for k in ("theta_h_deg", "phi_h_deg", "theta_d_deg", "phi_d_deg")]
    rows = zip(*columns, *np.asarray(samples["rgb"]).T)
    csv = tmp_path / "samples.csv"
    csv.write_text("theta_h,phi_h,theta_d,phi_d,r,g,b\n"
                   + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows))
    ours, theirs = tmp_path / "py.binary", tmp_path / "cli.binary"
    got = specula.reconstruct(samples, method="lobe", out=ours)
    cli("reconstruct", "--samples-csv", csv, "--method", "lobe", "--out", theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    assert (tmp_path / "py.provenance.npy").read_bytes() == \
        (tmp_path / "cli.provenance.npy").read_bytes()
    np.testing.assert_array_equal(got["provenance"], specula.read_provenance(ours))
    with pytest.raises(specula.SpeculaError) as refused:
        specula.reconstruct(samples, out=tmp_path / "x.csv")
    assert str(refused.value).startswith(f"{tmp_path / 'x.csv'}: this command writes a MERL table")
    status, _, stderr = cli("reconstruct", "--samples-csv", csv, "--out", tmp_path / "x.csv",
                            check=False)
    assert status != 0 and "x.csv: this command writes a MERL table" in stderr
