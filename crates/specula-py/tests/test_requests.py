"""The Python package and the CLI refuse the same out-of-range values with the same words:
both check the library's requests (specula_core::request)."""

import pytest

import specula

# (Python function, its arguments, the CLI's arguments, the argument's name in Python, in
# the CLI, and the words both say after it), one family of requests after another: the grid
# (plan), the plan, the probe, the measurement, the evaluation, the appearance, the render.
CASES = [
    ("plan", {"k": 4.78, "theta_h_samples": 1}, ["plan", "--k", "4.78", "--theta-h-samples", "1"],
     "theta_h_samples", "--theta-h-samples", "1: expected a whole number from 2 to 360"),
    ("plan", {"k": 4.78, "phi_d_step_deg": 0.1}, ["plan", "--k", "4.78", "--phi-d-step", "0.1"],
     "phi_d_step_deg", "--phi-d-step", "0.1: expected degrees from 0.5 to 90"),
    ("plan", {"k": 4.78, "phi_h_deg": -400.0}, ["plan", "--k", "4.78", "--phi-h", "-400"],
     "phi_h_deg", "--phi-h", "-400: expected degrees from -360 to 360"),
    ("plan", {"k": 0.0}, ["plan", "--k", "0"],
     "k", "--k", "0: expected a number above 0 and at most 100"),
    ("plan", {"theta_h_deg": [1.0, 95.0]}, ["plan", "--theta-h-list", "1,95"],
     "theta_h_deg", "--theta-h-list", "95: expected degrees from 0 to 90"),
    ("probe", {"brdf": "chrome", "theta_d_deg": 95.0}, ["probe", "chrome", "--theta-d", "95"],
     "theta_d_deg", "--theta-d", "95: expected degrees from 0 to 89.5"),
    ("probe", {"brdf": "chrome", "samples": 1}, ["probe", "chrome", "--probe-samples", "1"],
     "samples", "--probe-samples", "1: expected a whole number from 2 to 10000"),
    ("measure", {"truth": "chrome", "probe_samples": 20000},
     ["measure", "--truth", "chrome", "--probe-samples", "20000"],
     "probe_samples", "--probe-samples", "20000: expected a whole number from 2 to 10000"),
    ("measure", {"truth": "chrome", "tilt_deg": 20.0}, ["measure", "--truth", "chrome", "--tilt", "20"],
     "tilt_deg", "--tilt", "20: expected degrees from 0 to 10"),
    ("evaluate", {"truth": "chrome", "max_elevation_deg": 95.0},
     ["evaluate", "--truth", "chrome", "--max-elevation", "95"],
     "max_elevation_deg", "--max-elevation", "95: expected degrees above 0 and at most 90"),
    ("evaluate", {"truth": "chrome", "k": 200.0}, ["evaluate", "--truth", "chrome", "--k", "200"],
     "k", "--k", "200: expected a number above 0 and at most 100"),
    ("appearance", {"brdf": "chrome", "resolution_deg": 100.0},
     ["appearance", "chrome", "--resolution", "100"],
     "resolution_deg", "--resolution", "100: expected degrees above 0 and at most 90"),
    ("render", {"brdf": "chrome", "size": 4}, ["render", "chrome", "--size", "4"],
     "size", "--size", "4: expected a whole number from 8 to 8192"),
]

# The file each command writes, for the commands that write one.
OUT = {"plan": "plan.csv", "probe": "probe.csv", "measure": "out.binary", "render": "out.png"}


@pytest.mark.parametrize("function, kwargs, argv, name, flag, words", CASES)
def test_python_and_the_cli_refuse_the_same_values_with_the_same_words(
    cli, tmp_path, function, kwargs, argv, name, flag, words
):
    out = tmp_path / OUT.get(function, "none")
    if function in ("measure", "render"):
        kwargs = {**kwargs, "out": out}
    with pytest.raises(specula.SpeculaError) as refused:
        getattr(specula, function)(**kwargs)
    assert str(refused.value) == f"{name} {words}"
    if function in OUT:
        argv = [*argv, "--out", out]
    status, _, stderr = cli(*argv, check=False)
    assert status == 2
    assert f"{flag} {words}" in stderr
    assert not out.exists()


# The conversion, the fit, the report and the calibration: each front end fills the
# library's request and calls its one entry point. OUT in an argument is the file the
# command would write, which neither front end may leave behind.
WRITING = [
    ("convert", {"source": "chrome", "out": "OUT", "rgl_elevations": 1},
     ["convert", "chrome", "OUT", "--rgl-elevations", "1"],
     "rgl_elevations", "--rgl-elevations", "1: expected a whole number from 2 to 90", "x.bsdf"),
    ("fit", {"brdf": "chrome", "max_elevation_deg": 95.0, "out": "OUT"},
     ["fit", "chrome", "--max-elevation", "95", "--out", "OUT"],
     "max_elevation_deg", "--max-elevation", "95: expected degrees above 0 and at most 90",
     "fit.toml"),
    ("report", {"source": "chrome", "out": "OUT", "spp": 0},
     ["report", "chrome", "--out", "OUT", "--spp", "0"],
     "spp", "--spp", "0: expected a whole number from 1 to 65536", "r.html"),
    ("calibrate", {"truth": "chrome", "out": "OUT", "white_reflectance": 1.5},
     ["calibrate", "--truth", "chrome", "--out", "OUT", "--white-reflectance", "1.5"],
     "white_reflectance", "--white-reflectance", "1.5: expected a fraction above 0 and at most 1",
     "calibration.toml"),
]


@pytest.mark.parametrize("function, kwargs, argv, name, flag, words, file", WRITING)
def test_the_writing_commands_refuse_the_same_values_with_the_same_words(
    cli, tmp_path, function, kwargs, argv, name, flag, words, file
):
    out = tmp_path / file
    kwargs = {k: (out if v == "OUT" else v) for k, v in kwargs.items()}
    argv = [out if a == "OUT" else a for a in argv]
    with pytest.raises(specula.SpeculaError) as refused:
        getattr(specula, function)(**kwargs)
    assert str(refused.value) == f"{name} {words}"
    status, _, stderr = cli(*argv, check=False)
    assert status == 2
    assert f"{flag} {words}" in stderr
    assert not out.exists()


def test_a_grid_too_large_is_refused_as_the_cli_refuses_it(cli, tmp_path):
    big = {"theta_h_samples": 360, "theta_d_step_deg": "3:0.5@0", "phi_d_step_deg": 0.5}
    with pytest.raises(specula.SpeculaError) as refused:
        specula.plan(k=4.78, **big)
    assert "a grid of 23392800 samples (360 x 180 x 361); at most 1000000" in str(refused.value)
    status, _, stderr = cli("plan", "--k", "4.78", "--theta-h-samples", "360", "--theta-d-step",
                            "3:0.5@0", "--phi-d-step", "0.5", "--out", tmp_path / "p.csv",
                            check=False)
    assert status == 1
    assert "a grid of 23392800 samples (360 x 180 x 361); at most 1000000" in stderr


def test_choices_name_what_they_accept():
    with pytest.raises(specula.SpeculaError, match="order 'fast': expected one of optimized, nested"):
        specula.plan(k=4.78, order="fast")
    with pytest.raises(specula.SpeculaError,
                       match="grid preset 'fine': expected one of recommended, paper"):
        specula.plan(k=4.78, grid_preset="fine")
