"""The Python package and the CLI refuse the same out-of-range values with the same words:
both check the library's requests (specula_core::request)."""

import pytest

import specula

# (Python function, its arguments, the CLI's arguments, the argument's name in Python, in
# the CLI, and the words both say after it).
CASES = [
    ("plan", {"k": 4.78, "theta_h_samples": 1}, ["plan", "--k", "4.78", "--theta-h-samples", "1"],
     "theta_h_samples", "--theta-h-samples", "1: expected a whole number from 2 to 360"),
    ("plan", {"k": 4.78, "phi_d_step_deg": 0.1}, ["plan", "--k", "4.78", "--phi-d-step", "0.1"],
     "phi_d_step_deg", "--phi-d-step", "0.1: expected degrees from 0.5 to 90"),
    ("plan", {"k": 4.78, "phi_h_deg": -400.0}, ["plan", "--k", "4.78", "--phi-h", "-400"],
     "phi_h_deg", "--phi-h", "-400: expected degrees from -360 to 360"),
    ("measure", {"truth": "chrome", "probe_samples": 20000},
     ["measure", "--truth", "chrome", "--probe-samples", "20000"],
     "probe_samples", "--probe-samples", "20000: expected a whole number from 2 to 10000"),
    ("measure", {"truth": "chrome", "tilt_deg": 20.0}, ["measure", "--truth", "chrome", "--tilt", "20"],
     "tilt_deg", "--tilt", "20: expected degrees from 0 to 10"),
]


@pytest.mark.parametrize("function, kwargs, argv, name, flag, words", CASES)
def test_python_and_the_cli_refuse_the_same_values_with_the_same_words(
    cli, tmp_path, function, kwargs, argv, name, flag, words
):
    out = tmp_path / ("plan.csv" if function == "plan" else "out.binary")
    if function == "measure":
        kwargs = {**kwargs, "out": out}
    with pytest.raises(specula.SpeculaError) as refused:
        getattr(specula, function)(**kwargs)
    assert str(refused.value) == f"{name} {words}"
    status, _, stderr = cli(*argv, "--out", out, check=False)
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
