"""read_uncertainty: the standard uncertainty sidecar `reconstruct` writes beside its table."""

import numpy as np

import specula

SMALL_GRID = ["--grid-preset", "paper", "--theta-h-samples", "8", "--theta-d-step", "15",
              "--phi-d-step", "30"]


def elevation_deg(theta_h_deg, theta_d_deg, phi_d_deg):
    """The larger elevation of light and camera (degrees from the normal) of half-difference
    angles: the light's z is cos(h)cos(d) - sin(h)sin(d)cos(phi_d), the camera's, its mirror
    image about the half vector, cos(h)cos(d) + sin(h)sin(d)cos(phi_d)."""
    h, d, p = (np.radians(a) for a in (theta_h_deg, theta_d_deg, phi_d_deg))
    z = np.cos(h) * np.cos(d) - np.sin(h) * np.sin(d) * np.abs(np.cos(p))
    return np.degrees(np.arccos(np.clip(z, -1.0, 1.0)))


def test_read_uncertainty_returns_the_sidecar_beside_the_table(cli, tmp_path):
    samples_csv = tmp_path / "samples.csv"
    cli("evaluate", "--truth", "green-paint", "--k", "4.78", *SMALL_GRID,
        "--samples-out", samples_csv)
    out = tmp_path / "rec.binary"
    cli("reconstruct", "--samples-csv", samples_csv, "--out", out)
    table = specula.read_merl(out)
    u = specula.read_uncertainty(out)
    assert u.shape == (90, 90, 180, 3)
    assert u.dtype == np.float64
    # The file is the MERL one of the sidecar, NaN where the table has no value and beyond
    # the samples' reach (light or camera more than a degree beyond the furthest sample's
    # elevation), a value everywhere else.
    np.testing.assert_array_equal(u, specula.read_merl(tmp_path / "rec.uncertainty.binary"))
    assert not (np.isnan(table) & ~np.isnan(u)).any()
    samples = np.loadtxt(samples_csv, delimiter=",", skiprows=1)
    reach = elevation_deg(samples[:, 0], samples[:, 2], samples[:, 3]).max()
    i = np.arange(90) + 0.5
    cells = elevation_deg(*np.meshgrid(i * i / 90, i, np.arange(180) + 0.5, indexing="ij"))
    without = ~np.isnan(table) & np.isnan(u)
    assert without.any()
    assert (cells[without.any(axis=-1)] > reach - 1e-6).all()
    within = ~np.isnan(table) & (cells <= reach - 1e-6)[..., None]
    assert within.any() and not np.isnan(u[within]).any()
    # Relative where the value is positive (a zero value has a zero uncertainty in 1/sr).
    known = ~np.isnan(u) & (table > 0)
    assert known.any()
    relative = u[known] / table[known]
    # At least the calibration's 0.5 %, at most the cap of 1000 %.
    assert relative.min() >= 0.005 * (1 - 1e-6)
    assert relative.max() <= 10.0 * (1 + 1e-6)
    # Extrapolated cells (provenance 2) are more uncertain than measured ones (0).
    provenance = specula.read_provenance(out)
    rel = np.full(table.shape, np.nan)
    rel[known] = relative
    assert np.nanmedian(rel[provenance == 2]) > np.nanmedian(rel[provenance == 0])
    assert specula.read_uncertainty(samples_csv) is None
