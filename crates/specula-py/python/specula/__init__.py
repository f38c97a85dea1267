"""Specula for Python: the Specula crates behind numpy arrays.

Angles are degrees (arguments named ``*_deg``), BRDF values f_r in 1/sr per RGB channel,
and a MERL table is a ``(90, 90, 180, 3)`` float64 array indexed
``[theta_h_i, theta_d_i, phi_d_i, channel]`` with NaN where a cell is not measured.
See ``docs/book/src/python.md`` for a tutorial.
"""

from ._specula import (
    __version__,
    Brdf,
    SpeculaError,
    appearance,
    calibrate,
    compare,
    convert,
    evaluate,
    fit,
    fit_k,
    load,
    materials,
    measure,
    plan,
    probe,
    read_merl,
    read_provenance,
    read_session,
    read_uncertainty,
    reconstruct,
    render,
    report,
    write_merl,
)

__all__ = [
    "__version__",
    "Brdf",
    "SpeculaError",
    "appearance",
    "calibrate",
    "compare",
    "convert",
    "evaluate",
    "fit",
    "fit_k",
    "load",
    "materials",
    "measure",
    "plan",
    "probe",
    "read_merl",
    "read_provenance",
    "read_session",
    "read_uncertainty",
    "reconstruct",
    "render",
    "report",
    "write_merl",
]
