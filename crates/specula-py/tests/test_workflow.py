"""The paper's workflow through Python, checked against the CLI on the same inputs."""

import numpy as np
import pytest

import specula
from conftest import read_csv

SMALL_GRID = ["--grid-preset", "paper", "--theta-h-samples", "8", "--theta-d-step", "15",
              "--phi-d-step", "30"]
SMALL = dict(grid_preset="paper", theta_h_samples=8, theta_d_step_deg=15.0, phi_d_step_deg=30.0)


def csv_columns(path):
    rows = read_csv(open(path).read())
    return {key: [r[key] for r in rows] for key in rows[0]}


def test_probe_and_fit_k_match_the_cli(cli, tmp_path):
    path = tmp_path / "probe.csv"
    cli("probe", "silver-925", "--out", path)
    columns = csv_columns(path)
    probe = specula.probe("silver-925")
    np.testing.assert_allclose(probe["theta_h_deg"], np.array(columns["theta_h"], float), rtol=1e-12)
    rgb = np.array([columns[c] for c in "rgb"], float).T
    np.testing.assert_allclose(probe["rgb"], rgb, rtol=1e-12)

    _, out, _ = cli("fit-k", path)
    first = dict(item.split("=") for item in out.splitlines()[0].split())
    fit = specula.fit_k(probe)
    # The CLI prints plain numbers to 4 significant digits.
    assert fit["k"] == pytest.approx(float(first["k"]), rel=1e-3)
    assert fit["error"] == pytest.approx(float(first["error"]), rel=1e-3)
    positions = out.splitlines()[2].split("=")[1].split(",")
    np.testing.assert_allclose(fit["theta_h_deg"], np.array(positions, float), atol=1e-6)
    assert len(fit["theta_h_deg"]) == 30


def test_fit_k_rejects_a_decreasing_probe():
    with pytest.raises(specula.SpeculaError):
        specula.fit_k({"theta_h_deg": [3.0, 1.0, 2.0], "rgb": np.ones((3, 3))})


def test_plan_matches_the_cli(cli, tmp_path):
    path = tmp_path / "plan.csv"
    cli("plan", "--k", "4.78", *SMALL_GRID, "--out", path)
    columns = csv_columns(path)
    plan = specula.plan(k=4.78, **SMALL)
    assert list(plan["status"]) == columns["status"]
    np.testing.assert_array_equal(plan["index"], np.array(columns["index"], int))
    for ours, theirs in [("theta_h_deg", "theta_h"), ("theta_d_deg", "theta_d"),
                         ("phi_d_deg", "phi_d"), ("theta_i_deg", "theta_i"),
                         ("phi_o_deg", "phi_o"), ("time_s", "time_s")]:
        np.testing.assert_allclose(plan[ours], np.array(columns[theirs], float), atol=1.01e-3)
    camera = np.array([float(c) if c else np.nan for c in columns["camera_deg"]])
    np.testing.assert_allclose(plan["camera_deg"], camera, atol=1e-4)
    summary = plan["summary"]["nested"]
    assert summary["total"] == 8 * 6 * 4 == len(plan["index"])
    assert summary["measurable"] == columns["status"].count("ok")
    assert "silver-925" in plan["captures"]
    # The device's bracket prices every capture alike, in both front ends.
    bracket_path = tmp_path / "bracket.csv"
    cli("plan", "--k", "4.78", *SMALL_GRID, "--hdr", "bracket", "--out", bracket_path)
    bracket = specula.plan(k=4.78, hdr="bracket", **SMALL)
    np.testing.assert_allclose(bracket["time_s"],
                               np.array(csv_columns(bracket_path)["time_s"], float), atol=1.01e-3)
    assert bracket["time_s"].sum() > plan["time_s"].sum()


def test_plan_takes_the_recommended_grid_by_default_and_its_notation():
    graded = specula.plan(k=4.78, theta_h_samples=4, theta_d_step_deg="15:5@60",
                          phi_d_step_deg=45.0)
    # theta_d 0, 15, 30, 45, 60, 65, ..., 85; phi_d 0, 45, ..., 180 (the default half turn).
    assert graded["summary"]["nested"]["total"] == 4 * 10 * 5
    assert graded["phi_d_deg"].max() == pytest.approx(180.0)
    assert sorted(set(np.round(graded["theta_d_deg"], 6)))[4:6] == [60.0, 65.0]
    quarter = specula.plan(k=4.78, theta_h_samples=4, theta_d_step_deg=15.0,
                           phi_d_span="quarter")
    assert quarter["summary"]["nested"]["total"] == 4 * 6 * 4
    default = specula.plan(k=4.78)["summary"]["nested"]["total"]
    assert default == 16 * 50 * 7
    with pytest.raises(specula.SpeculaError, match="STEP:GRAZING@FROM"):
        specula.plan(k=4.78, theta_d_step_deg="3:1")
    with pytest.raises(specula.SpeculaError, match="half-turn"):
        specula.plan(k=4.78, phi_d_span="half")
    with pytest.raises(specula.SpeculaError, match="expected one of recommended, paper"):
        specula.plan(k=4.78, grid_preset="fine")


def test_reconstruct_matches_the_cli(cli, tmp_path):
    samples_csv = tmp_path / "samples.csv"
    cli("evaluate", "--truth", "silver-925", "--k", "4.78", *SMALL_GRID,
        "--samples-out", samples_csv)
    columns = csv_columns(samples_csv)
    samples = {f"{a}_deg": np.array(columns[a], float)
               for a in ("theta_h", "phi_h", "theta_d", "phi_d")}
    samples["rgb"] = np.array([columns[c] for c in "rgb"], float).T
    out = tmp_path / "rec.binary"
    cli("reconstruct", "--samples-csv", samples_csv, "--method", "linear", "--out", out)
    result = specula.reconstruct(samples, method="linear")
    np.testing.assert_array_equal(result["table"], specula.read_merl(out))
    np.testing.assert_array_equal(result["provenance"], np.load(tmp_path / "rec.provenance.npy"))
    np.testing.assert_array_equal(specula.read_provenance(out), result["provenance"])
    assert specula.read_provenance(samples_csv) is None
    assert result["lobe"] is None


def test_evaluate_matches_the_cli_and_reconstructs_its_samples(cli):
    _, out, _ = cli("evaluate", "--truth", "green-paint", "--method", "log", *SMALL_GRID)
    row = read_csv("\n".join(out.splitlines()[1:]))[0]
    got = specula.evaluate("green-paint", method="log", **SMALL)
    assert got["name"] == row["material"]
    assert got["k"] == pytest.approx(float(row["k"]), abs=5e-4)
    assert got["measured"] == int(row["measured"]) == len(got["samples"]["rgb"])
    for key, figure in [("within", "rel_rmse"), ("within", "log_rmse"), ("all", "rel_rmse")]:
        column = f"{figure}_{key}"
        name = "relative_rmse" if figure == "rel_rmse" else figure
        assert got[key][name] == pytest.approx(float(row[column]), abs=6e-6)
    # Round trip: the returned samples reconstruct to the same figures.
    table = specula.reconstruct(got["samples"], method="log")["table"]
    again = specula.compare(table, specula.load("green-paint").tabulate(45.0))
    assert again["within"]["relative_rmse"] == pytest.approx(got["within"]["relative_rmse"], rel=1e-12)


def test_measure_and_read_session_agree_with_the_cli(cli, tmp_path):
    out = tmp_path / "m.binary"
    session = tmp_path / "m.sqlite"
    summary = specula.measure("silver-925", out, session=session, ideal=True, checks=False,
                              probe_samples=30, **SMALL)
    assert summary["measured_samples"] > 0 and summary["k_hat"] > 0
    journal = specula.read_session(session)
    assert journal["simulated_truth"] == "silver-925"
    assert journal["grid"] == summary["grid"]
    assert journal["grid"].startswith("8 theta_h, theta_d step 15 deg, phi_d step 30 deg over 0-90")
    assert summary["phi_d_halves"] is False
    assert journal["fit"]["k"] == pytest.approx(summary["k_hat"], rel=1e-12)
    # The probe's samples the device reaches (theta_h up to about 67 deg at theta_d 40).
    probe_done = journal["stages"]["probe"]["done"]
    assert 20 <= probe_done == journal["stages"]["probe"]["planned"] <= 30
    assert len(journal["probe"]["theta_h_deg"]) == probe_done
    samples = journal["samples"]
    assert len(samples["rgb"]) == summary["measured_samples"]
    assert journal["stages"]["main"]["done"] == summary["measured_samples"]
    # The CLI reconstructs the same journal into the same table.
    cli_out = tmp_path / "cli.binary"
    cli("reconstruct", "--session", session, "--out", cli_out)
    np.testing.assert_array_equal(specula.read_merl(out), specula.read_merl(cli_out))
    # The samples came out in degrees (radians to degrees and back round the last bit); the
    # samples alone carry no instrument response, so they match the CLI without deblurring.
    blurred = tmp_path / "blurred.binary"
    cli("reconstruct", "--session", session, "--no-deblur", "--out", blurred)
    again = specula.reconstruct(samples)["table"]
    np.testing.assert_allclose(again, specula.read_merl(blurred), rtol=1e-9)
    assert np.array_equal(np.isnan(again), np.isnan(specula.read_merl(blurred)))


def test_a_session_s_samples_carry_their_noise_into_the_reconstruction(cli, tmp_path):
    out = tmp_path / "m.binary"
    session = tmp_path / "m.sqlite"
    specula.measure("green-paint", out, session=session, checks=False, probe_samples=30,
                    **SMALL)
    samples = specula.read_session(session)["samples"]
    noise = np.asarray(samples["noise_rel"])
    assert noise.shape == (len(samples["rgb"]), 3)
    # Each value's relative standard deviation per channel from the camera: small, positive,
    # finite, and not the same in every channel of a coloured paint.
    assert np.all((noise > 0) & (noise < 0.05))
    assert np.any(np.abs(noise[:, 0] - noise[:, 1]) > 0.1 * noise[:, 1])
    # With its noise the residual is smoothed as the CLI smooths it.
    blurred = tmp_path / "blurred.binary"
    cli("reconstruct", "--session", session, "--no-deblur", "--out", blurred)
    again = specula.reconstruct(samples)["table"]
    np.testing.assert_allclose(again, specula.read_merl(blurred), rtol=1e-9)


def test_a_noise_column_of_the_wrong_shape_is_refused_by_name():
    samples = {"theta_h_deg": [1.0, 2.0], "phi_h_deg": [0.0, 0.0], "theta_d_deg": [30.0, 30.0],
               "phi_d_deg": [90.0, 90.0], "rgb": np.ones((2, 3))}
    for noise, got in [(np.full(2, 0.01), "an array of another dimension"),
                       (np.full((2, 1), 0.01), "(2, 1)")]:
        with pytest.raises(specula.SpeculaError) as caught:
            specula.reconstruct({**samples, "noise_rel": noise})
        assert str(caught.value) == f"noise_rel must have the shape (2, 3), got {got}"


def test_read_session_rejects_a_file_that_is_not_a_journal(cli, tmp_path):
    bad = tmp_path / "bad.sqlite"
    bad.write_text("not a database")
    status, _, err = cli("session", "status", bad, check=False)
    assert status == 1
    with pytest.raises(specula.SpeculaError) as caught:
        specula.read_session(bad)
    assert "error: " + str(caught.value) == err.strip()


def test_read_session_names_a_journal_that_does_not_exist(cli, tmp_path):
    missing = tmp_path / "never-measured.session.sqlite"
    status, _, err = cli("session", "status", missing, check=False)
    assert status == 1 and "no such session journal" in err
    with pytest.raises(specula.SpeculaError) as caught:
        specula.read_session(missing)
    assert "error: " + str(caught.value) == err.strip()
    assert not missing.exists()


def test_measure_refuses_a_time_limit_out_of_range_with_the_clis_words(cli, tmp_path):
    status, _, err = cli("measure", "--truth", "silver-925", "--max-hours", "0",
                         "--out", tmp_path / "x.binary", check=False)
    assert status == 2 and "--max-hours 0: expected hours above 0 and at most 1000" in err
    with pytest.raises((ValueError, specula.SpeculaError)) as caught:
        specula.measure("silver-925", tmp_path / "y.binary", max_hours=0.0)
    assert str(caught.value) == "max_hours 0: expected hours above 0 and at most 1000"
    assert not (tmp_path / "y.session.sqlite").exists()
