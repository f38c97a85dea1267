"""The worked adapter on ophyd (examples/ophyd_adapter/adapter.py): a short calibrated
measurement through the driver protocol, its motors, light and camera all ophyd devices, gives
the table the plain example adapter gives for the same fake sample.

Needs ophyd (`pip install ophyd`; CI installs it); skipped with the reason when absent."""

import pathlib
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
SHORT = ["--skip-checks", "--probe-samples", "30", "--theta-h-samples", "6",
         "--theta-d-step", "15", "--phi-d-step", "45",
         "--calibration", REPO / "tools" / "example_adapter_calibration.toml"]


def test_a_calibrated_measurement_through_ophyd_matches_the_example_adapter(cli, tmp_path):
    pytest.importorskip("ophyd", reason="ophyd is not installed (pip install ophyd)")
    ophyd = tmp_path / "ophyd.binary"
    plain = tmp_path / "plain.binary"
    adapter = REPO / "examples" / "ophyd_adapter" / "adapter.py"
    cli("measure", "--connect", f"exec:{sys.executable} {adapter}", *SHORT, "--out", ophyd)
    cli("measure", "--connect", f"exec:{sys.executable} {REPO / 'tools' / 'example_adapter.py'}",
        *SHORT, "--out", plain)
    summary = (tmp_path / "ophyd.summary.txt").read_text()
    assert "source=device: ophyd simulated goniometer" in summary
    measured = int(next(line.split("=")[1] for line in summary.splitlines()
                        if line.startswith("measured_samples=")))
    assert measured > 50
    _, out, _ = cli("compare", ophyd, plain)
    within = next(line.split(",") for line in out.splitlines() if line.startswith("within,"))
    assert float(within[2]) < 1e-9, out
