"""MERL tables and BRDF evaluation through numpy, checked against the CLI and numpy."""

import os

import numpy as np
import pytest

import specula
from conftest import read_csv

SCALE = np.array([1.0, 1.15, 1.66]) / 1500.0


def numpy_merl(path):
    """An independent reader: numpy.fromfile, reshape, scale, negative -> NaN."""
    header = np.fromfile(path, dtype="<i4", count=3)
    assert list(header) == [90, 90, 180]
    planes = np.fromfile(path, dtype="<f8", offset=12).reshape(3, 90, 90, 180)
    table = np.moveaxis(planes, 0, -1) * SCALE
    table[(planes < 0).any(axis=0)] = np.nan
    return table


@pytest.fixture(scope="module")
def silver_binary(tmp_path_factory, cli):
    path = tmp_path_factory.mktemp("merl") / "silver.binary"
    cli("tabulate", "silver-925", "--out", path)
    return path


def test_read_merl_matches_numpy_and_the_brdf(silver_binary):
    table = specula.read_merl(silver_binary)
    assert table.shape == (90, 90, 180, 3) and table.dtype == np.float64
    np.testing.assert_array_equal(table, numpy_merl(silver_binary))
    # The CLI's table of silver-925 against Brdf.tabulate (stored / scale * scale).
    np.testing.assert_allclose(table, specula.load("silver-925").tabulate(), rtol=1e-14)


def test_write_merl_round_trip_with_holes(tmp_path, silver_binary, cli):
    table = specula.read_merl(silver_binary).copy()  # C order, unlike read_merl's planes
    rng = np.random.default_rng(7)
    holes = rng.random(table.shape[:3]) < 0.1
    table[holes] = np.nan
    table[0, 0, 0, 1] = np.nan  # one NaN channel marks the whole cell
    path = tmp_path / "holes.binary"
    specula.write_merl(path, table)
    back = specula.read_merl(path)
    expected = table.copy()
    expected[0, 0, 0] = np.nan
    np.testing.assert_allclose(back, expected, rtol=1e-15)
    assert np.array_equal(np.isnan(back), np.isnan(expected))
    np.testing.assert_array_equal(back, numpy_merl(path))
    _, out, _ = cli("info", path)
    measured = int(out.split("measured: ")[1].split()[0])
    assert measured == int((~np.isnan(expected).any(axis=-1)).sum())


def test_write_merl_rejects_a_wrong_shape(tmp_path):
    with pytest.raises(specula.SpeculaError, match=r"shape \(90, 90, 180, 3\)"):
        specula.write_merl(tmp_path / "bad.binary", np.zeros((90, 90, 90, 3)))


def random_pairs(n, seed):
    """Unit direction pairs above the surface (a few grazing ones included)."""
    rng = np.random.default_rng(seed)
    theta = rng.uniform(0, 89.9, (n, 2))
    phi = rng.uniform(0, 360, (n, 2))
    return theta, phi


def directions(theta_deg, phi_deg):
    t, p = np.radians(theta_deg), np.radians(phi_deg)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)


RGL_FILE = "/work/shared/data/measured/rgl_bsdf/satin_rosaline_rgb.bsdf"


@pytest.mark.parametrize("source", ["silver-925", "green-paint", "silver-925-scratched", "table",
                                    "nbrdf:alum-bronze", RGL_FILE])
def test_eval_matches_the_cli(tmp_path, cli, source, silver_binary):
    # Analytic materials evaluate in batch (`Brdf::eval_pairs`), the others pair by pair;
    # the CLI evaluates every source pair by pair.
    if source == RGL_FILE and not os.path.exists(RGL_FILE):
        pytest.skip("the shared RGL data set is not on this machine")
    source = str(silver_binary) if source == "table" else source
    theta, phi = random_pairs(400, 3)
    dirs = tmp_path / "dirs.csv"
    with open(dirs, "w") as f:
        f.write("theta_i,phi_i,theta_o,phi_o\n")
        for (ti, to), (pi, po) in zip(theta, phi):
            f.write(",".join(repr(float(x)) for x in (ti, pi, to, po)) + "\n")
    _, out, _ = cli("eval", source, "--dirs", dirs)
    expected = np.array([[float(r[c]) for c in "rgb"] for r in read_csv(out)])
    wi = directions(theta[:, 0], phi[:, 0])
    wo = directions(theta[:, 1], phi[:, 1])
    got = specula.load(source).eval(wi, wo)
    assert got.shape == (400, 3)
    np.testing.assert_allclose(got, expected, rtol=1e-13, atol=0)


def test_eval_half_diff_broadcasts_and_agrees_with_directions():
    brdf = specula.load("silver-925")
    theta_h = np.linspace(0.0, 10.0, 7)[:, None]
    theta_d = np.array([5.0, 40.0, 70.0])[None, :]
    values = brdf.eval_half_diff(theta_h, theta_d, 90.0, phi_h_deg=45.0)
    assert values.shape == (7, 3, 3)
    # The same configurations as directions (Rusinkiewicz 1998, built here in numpy).
    th, td = np.radians(np.broadcast_arrays(theta_h, theta_d))
    ph, pd = np.radians(45.0), np.radians(90.0)
    d = np.stack([np.sin(td) * np.cos(pd), np.sin(td) * np.sin(pd), np.cos(td)], axis=-1)

    def rot_y(v, a):
        c, s = np.cos(a), np.sin(a)
        return np.stack([c * v[..., 0] + s * v[..., 2], v[..., 1], -s * v[..., 0] + c * v[..., 2]], -1)

    def rot_z(v, a):
        c, s = np.cos(a), np.sin(a)
        return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1], v[..., 2]], -1)

    h = rot_z(rot_y(np.array([0.0, 0.0, 1.0]) * np.ones_like(d), th), ph)
    wi = rot_z(rot_y(d, th), ph)
    wo = 2 * np.sum(wi * h, axis=-1, keepdims=True) * h - wi
    direct = brdf.eval(wi.reshape(-1, 3), wo.reshape(-1, 3)).reshape(values.shape)
    np.testing.assert_allclose(values, direct, rtol=1e-9)


def test_eval_rejects_bad_directions():
    brdf = specula.load("chrome")
    with pytest.raises(specula.SpeculaError, match="unit vector"):
        brdf.eval([[0.0, 0.0, 2.0]], [[0.0, 0.0, 1.0]])
    with pytest.raises(specula.SpeculaError, match=r"\(N, 3\)"):
        brdf.eval(np.zeros((4, 3)), np.zeros((5, 3)))
    # The first bad row is named, in whichever block of rows it falls.
    wo = np.tile([0.0, 0.0, 1.0], (9000, 1))
    wo[[4500, 4700, 8000]] = [[0.0, 0.0, 0.5], [0.0, 0.0, 2.0], [1.0, 1.0, 0.0]]
    with pytest.raises(specula.SpeculaError, match=r"^wo\[4500\] = \[0\.0, 0\.0, 0\.5\] is not"):
        brdf.eval(np.tile([0.0, 0.0, 1.0], (9000, 1)), wo)


def test_eval_rejects_nan_directions():
    # A NaN has no length within the tolerance of 1; it is named like any other bad row.
    wi = np.tile([0.0, 0.0, 1.0], (3000, 1))
    wi[2500] = [np.nan, 0.0, 1.0]
    with pytest.raises(specula.SpeculaError, match=r"^wi\[2500\] = \[NaN, 0\.0, 1\.0\] is not"):
        specula.load("silver-925").eval(wi, np.tile([0.0, 0.0, 1.0], (3000, 1)))


def test_compare_matches_the_cli(cli, silver_binary):
    _, out, _ = cli("compare", silver_binary, "chrome")
    rows = {r["set"]: r for r in read_csv(out)}
    got = specula.compare(specula.read_merl(silver_binary), "chrome")
    for key in ("all", "within"):
        assert got[key]["cells"] == int(rows[key]["cells"])
        for figure in ("relative_rmse", "log_rmse", "slice_mae"):
            assert got[key][figure] == pytest.approx(float(rows[key][figure]), rel=1e-5)


def test_errors_carry_the_cli_message(cli, tmp_path):
    bad = tmp_path / "short.binary"
    bad.write_bytes(b"\x5a\x00\x00\x00")
    for args, call in [
        (("info", bad), lambda: specula.read_merl(bad)),
        (("tabulate", "no-such-material", "--out", tmp_path / "x.binary"),
         lambda: specula.load("no-such-material")),
    ]:
        status, _, err = cli(*args, check=False)
        assert status == 1
        with pytest.raises(specula.SpeculaError) as caught:
            call()
        assert "error: " + str(caught.value) == err.strip()
