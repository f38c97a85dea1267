"""Type stubs of the ``specula`` package (the native module ``specula._specula``)."""

import os
from typing import Any, Mapping, Optional, Sequence, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt

Path = Union[str, "os.PathLike[str]"]
FloatArray = npt.NDArray[np.float64]
ArrayLike = npt.ArrayLike

__version__: str

class SpeculaError(Exception):
    """A Specula error, with the CLI's one-line message (the file and the problem)."""

class Brdf:
    """A BRDF: an analytic material, a measured table, a model fit or a reconstruction."""

    @property
    def name(self) -> str:
        """The BRDF's short name."""
    def eval(self, wi: ArrayLike, wo: ArrayLike) -> FloatArray:
        """f_r (1/sr) at (N, 3) arrays of unit directions; returns (N, 3) R, G, B."""
    def eval_half_diff(
        self,
        theta_h_deg: ArrayLike,
        theta_d_deg: ArrayLike,
        phi_d_deg: ArrayLike,
        phi_h_deg: Optional[ArrayLike] = None,
    ) -> FloatArray:
        """f_r (1/sr) at broadcast half-difference angles (degrees); shape + (3,)."""
    def tabulate(self, phi_h_deg: float = 0.0) -> FloatArray:
        """The BRDF at the MERL bin centres: a (90, 90, 180, 3) array."""

BrdfLike = Union[Brdf, Path, FloatArray]

class Figures(TypedDict):
    cells: int
    relative_rmse: float
    log_rmse: float
    slice_mae: float

class Comparison(TypedDict):
    all: Figures
    within: Figures

class ProbeDict(TypedDict):
    theta_h_deg: FloatArray
    rgb: FloatArray

class KFit(TypedDict):
    k: float
    error: float
    family: str
    samples: int
    evaluations: int
    theta_h_deg: FloatArray

class Samples(TypedDict, total=False):
    theta_h_deg: FloatArray
    phi_h_deg: FloatArray
    theta_d_deg: FloatArray
    phi_d_deg: FloatArray
    rgb: FloatArray
    # Each value's relative standard deviation per channel (N, 3) from the camera's noise (a
    # measured session's samples have it; the lobe method smooths the residual within it).
    noise_rel: FloatArray

class Evaluation(TypedDict):
    name: str
    k: Optional[float]
    measured: int
    within: Figures
    all: Figures
    samples: Samples

def read_merl(path: Path) -> FloatArray:
    """Read a MERL .binary file: (90, 90, 180, 3) f_r in 1/sr, NaN where not measured."""

def write_merl(path: Path, array: FloatArray) -> None:
    """Write a (90, 90, 180, 3) array as a MERL .binary file (NaN: not measured)."""

def read_provenance(merl_path: Path) -> Optional[npt.NDArray[np.uint8]]:
    """The OUT.provenance.npy sidecar of a reconstructed table: (90, 90, 180) uint8, or None."""

def read_uncertainty(merl_path: Path) -> Optional[npt.NDArray[np.float64]]:
    """The OUT.uncertainty.binary sidecar: standard uncertainty (k = 1) in 1/sr, (90, 90, 180, 3), NaN where none, or None."""

def load(source: Path) -> Brdf:
    """Any BRDF the CLI takes: preset, material .toml, MERL, RGL .bsdf, UTIA, model:name fits."""

def convert(
    source: Path,
    out: Path,
    phi_h_deg: float = 45.0,
    grid: str = "merl",
    rgl_elevations: int = ...,
    rgl_ndf_size: int = ...,
    rgl_sample_size: int = ...,
) -> dict[str, Any]:
    """`specula convert SOURCE OUT`: the format follows OUT's extension."""

def calibrate(
    truth: BrdfLike,
    out: Path,
    white_reflectance: float = 0.99,
    white_certificate: Optional[Path] = None,
    seed: int = 1,
    device: Optional[Path] = None,
) -> Path:
    """`specula calibrate --truth`: the simulated device calibrated, written to `out`."""

def fit(
    brdf: BrdfLike,
    model: str = "both",
    max_elevation_deg: float = 75.0,
    out: Optional[Path] = None,
    mitsuba: Optional[Path] = None,
    pbrt: Optional[Path] = None,
    gltf: Optional[Path] = None,
) -> dict[str, Any]:
    """`specula fit`: analytic materials fitted, the best exported; {"exported", "reason",
    "notes", "fits"}."""

def render(
    brdf: BrdfLike,
    out: Optional[Path] = None,
    shape: str = "sphere",
    env: Optional[str] = None,
    light: Optional[str] = None,
    spp: int = 256,
    size: int = 512,
    exposure: float = 0.0,
    seed: int = 1,
) -> FloatArray:
    """`specula render`: the linear radiance as (size, size, 3); `out` written as the CLI does."""

def report(
    source: Path,
    out: Path,
    truth: Optional[str] = None,
    samples_csv: Optional[Path] = None,
    table: Optional[Path] = None,
    size: int = 320,
    spp: int = 32,
    title: Optional[str] = None,
) -> Path:
    """`specula report`: one self-contained HTML page about a measured BRDF; returns `out`."""

def materials() -> list[str]:
    """Names of the built-in material database (presets first), each a source for load()."""

def compare(a: BrdfLike, b: BrdfLike, max_elevation_deg: float = 75.0) -> Comparison:
    """`specula compare A B`: relative_rmse, log_rmse, slice_mae over all cells and within."""

@overload
def appearance(
    brdf: BrdfLike, against: Optional[BrdfLike] = None, resolution_deg: Optional[float] = None
) -> dict[str, Any]:
    """`specula appearance --csv` as a dict keyed by its columns (gloss_20 ... flop_index,
    d_* and de00_* with `against`), plus `name` and `warnings`; None where unknown."""
@overload
def appearance(
    brdf: Sequence[BrdfLike],
    against: Optional[BrdfLike] = None,
    resolution_deg: Optional[float] = None,
) -> list[dict[str, Any]]:
    """The figures of each BRDF of a list, as for one."""

def probe(
    brdf: BrdfLike,
    theta_d_deg: Optional[float] = None,
    phi_d_deg: Optional[float] = None,
    phi_h_deg: Optional[float] = None,
    samples: Optional[int] = None,
) -> ProbeDict:
    """The probe of paper 5.2: a dense theta_h column at square-root positions; `None`
    takes the paper's theta_d 40, phi_d 90, phi_h 45 deg and 90 positions."""

def fit_k(
    probe: Mapping[str, ArrayLike], family: str = "exponential", samples: Optional[int] = None
) -> KFit:
    """k-hat of a theta_h sampling function fitted to a probe (paper 5.2)."""

def plan(
    k: Optional[float] = None,
    theta_h_deg: Optional[Sequence[float]] = None,
    family: str = "exponential",
    grid_preset: Optional[str] = None,
    theta_h_samples: Optional[int] = None,
    theta_d_step_deg: Optional[Union[float, str]] = None,
    phi_d_step_deg: Optional[float] = None,
    phi_d_span: Optional[str] = None,
    phi_h_deg: Optional[float] = None,
    order: str = "optimized",
    device: Optional[Path] = None,
) -> dict[str, Any]:
    """A measurement plan (paper 5.3) as a dict of arrays in execution order, plus "summary".
    A grid argument left `None` takes `grid_preset`'s value: "recommended" (the default: 16
    theta_h, theta_d "3:1@60" = every 3 deg, every 1 from 60, phi_d step 30 over
    phi_d_span "half-turn" 0-180, phi_h 45 deg) or "paper" (30, 3, 15 over "quarter" 0-90,
    45). `theta_d_step_deg` is a number (an even step) or "STEP:GRAZING@FROM"."""

def reconstruct(
    samples: Mapping[str, ArrayLike], method: str = "lobe", out: Optional[Path] = None
) -> dict[str, Any]:
    """Sparse samples into the MERL grid: "table", "provenance" (uint8: 0 measured, 1
    interpolated, 2 extrapolated, 3 from the prior) and lattice facts. `method`: "lobe"
    (default), "prior" (lobe blended with the MERL-100 prior as far as the samples trust it),
    "log" or "linear". Samples that measure both halves of phi_d (0-90 and 90-180 deg) are
    reconstructed half by half. `out`: a MERL .binary written with its provenance beside it
    (OUT.provenance.npy), as `specula reconstruct --out`."""

def evaluate(
    truth: BrdfLike,
    method: str = "lobe",
    k: Optional[float] = None,
    placement: str = "function",
    family: str = "exponential",
    grid_preset: Optional[str] = None,
    theta_h_samples: Optional[int] = None,
    theta_d_step_deg: Optional[Union[float, str]] = None,
    phi_d_step_deg: Optional[float] = None,
    phi_d_span: Optional[str] = None,
    phi_h_deg: Optional[float] = None,
    max_elevation_deg: float = 75.0,
    device: Optional[Path] = None,
    through_instrument: bool = False,
) -> Evaluation:
    """The accuracy harness (`specula evaluate --truth`); the grid arguments as `plan`'s;
    `through_instrument=True` as `--through-instrument`."""

def measure(
    truth: BrdfLike,
    out: Path,
    session: Optional[Path] = None,
    seed: int = 1,
    ideal: bool = False,
    point_light: bool = False,
    probe_samples: Optional[int] = None,
    family: str = "exponential",
    grid_preset: Optional[str] = None,
    theta_h_samples: Optional[int] = None,
    theta_d_step_deg: Optional[Union[float, str]] = None,
    phi_d_step_deg: Optional[float] = None,
    phi_d_span: Optional[str] = None,
    phi_h_deg: Optional[float] = None,
    order: str = "optimized",
    hdr: str = "predicted",
    method: str = "lobe",
    deblur: bool = True,
    checks: bool = True,
    tilt_deg: float = 0.0,
    tilt_azimuth_deg: float = 0.0,
    device: Optional[Path] = None,
) -> dict[str, Any]:
    """A simulated measurement (`specula measure --truth`); returns its summary (with "grid"
    and "phi_d_halves"). The grid arguments as `plan`'s; a resumed session keeps its own grid
    unless `grid_preset` is given."""

def read_session(path: Path) -> dict[str, Any]:
    """A session journal read-only: its grid, stages, events, fit, probe and the main
    samples (with each value's relative noise per channel, "noise_rel" (N, 3), which `reconstruct` smooths the
    residual within)."""

__all__: list[str]
