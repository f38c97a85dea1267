"""Ctrl-C during a long call: `measure` stops after the sample in progress and resumes; `render`
stops at its next tile."""

import _thread
import threading
import time

import numpy as np
import pytest

import specula

GRID = dict(grid_preset="paper", theta_h_samples=12, theta_d_step_deg=6.0, phi_d_step_deg=15.0, probe_samples=30,
            checks=False, seed=3)


def interrupt_when_measuring(session, timeout_s=60.0):
    """Sends the main thread a SIGINT (as Ctrl-C does) once the journal exists."""

    def watch():
        deadline = time.monotonic() + timeout_s
        while not session.exists() and time.monotonic() < deadline:
            time.sleep(0.01)
        time.sleep(0.2)
        _thread.interrupt_main()

    thread = threading.Thread(target=watch, daemon=True)
    thread.start()
    return thread


def test_ctrl_c_stops_measure_which_then_resumes_to_the_same_table(tmp_path):
    whole = specula.measure("silver-925", tmp_path / "whole.binary", **GRID)

    out, session = tmp_path / "cut.binary", tmp_path / "cut.sqlite"
    watcher = interrupt_when_measuring(session)
    with pytest.raises(KeyboardInterrupt):
        specula.measure("silver-925", out, session=session, **GRID)
    watcher.join()
    cut = specula.read_session(session)
    main = cut["stages"].get("main", {"done": 0, "planned": 1})
    assert main["done"] < main["planned"], "the interrupt came after the measurement"
    assert not out.exists()

    resumed = specula.measure("silver-925", out, session=session, **GRID)
    assert resumed["measured_samples"] == whole["measured_samples"]
    np.testing.assert_array_equal(specula.read_merl(out), specula.read_merl(tmp_path / "whole.binary"))


def test_ctrl_c_stops_a_render_at_its_next_tile_and_writes_nothing(tmp_path):
    out = tmp_path / "long.png"

    def interrupt():
        time.sleep(1.0)
        _thread.interrupt_main()

    threading.Thread(target=interrupt, daemon=True).start()
    started = time.monotonic()
    # 1024 x 1024 pixels at 4096 rays each: minutes of work.
    with pytest.raises(KeyboardInterrupt):
        specula.render("chrome", out=out, size=1024, spp=4096)
    assert time.monotonic() - started < 30
    assert not out.exists()
