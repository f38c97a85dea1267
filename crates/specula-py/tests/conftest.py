"""Shared fixtures: the `specula` CLI the package is checked against, and a scratch folder."""

import csv
import io
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]


def cli_path() -> pathlib.Path:
    """The CLI binary: $SPECULA_CLI, else the workspace's debug build (`cargo build`)."""
    path = pathlib.Path(os.environ.get("SPECULA_CLI", REPO / "target" / "debug" / "specula"))
    if not path.exists():
        pytest.fail(f"{path}: no specula CLI; run `cargo build -p specula-cli` or set SPECULA_CLI")
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs `specula ARGS...` and returns (exit status, stdout, stderr)."""
    binary = cli_path()

    def run(*args, check=True):
        done = subprocess.run(
            [str(binary), *map(str, args)], capture_output=True, text=True, cwd=REPO
        )
        if check and done.returncode != 0:
            raise AssertionError(f"specula {' '.join(map(str, args))}: {done.stderr}")
        return done.returncode, done.stdout, done.stderr

    return run


def read_csv(text: str):
    """Rows of a CSV text as dicts of strings."""
    return list(csv.DictReader(io.StringIO(text)))
