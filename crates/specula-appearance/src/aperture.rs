//! The flux an instrument's source and receptor apertures collect from a material: the
//! integral every gloss, haze and distinctness-of-image figure is made of.
//!
//! **Geometry** (ISO 2813 / ASTM D523 section 6, ASTM E430): the source and the receptor lie
//! in the plane of measurement (the xz plane of the sample frame, z the normal), the source at
//! `theta` on the -x side, the receptor centred on the mirror direction at `theta` on the +x
//! side, shifted by an in-plane offset for off-specular windows. Apertures are rectangles of
//! full angles subtended at the specimen: `in_plane_deg` in the plane of measurement,
//! `perpendicular_deg` across it.
//!
//! A direction of an aperture is given by offsets `(a, b)` from its centre: `a` turns it in the
//! plane of measurement (positive away from the normal), `b` lifts it out of that plane:
//! `d = (cos b sin(theta + a), sin b, cos b cos(theta + a))` on the receptor's side (x
//! mirrored on the source's). The solid angle element is `cos b da db`, and the mirror image
//! of the source direction `(a, b)` is the receptor direction `(a, -b)`.
//!
//! **Flux.** With uniform radiance over the source, the flux reaching the receptor is
//! `Phi = int_S cos theta_i int_W f_r(w_i, w_o) cos theta_o dw_o dw_i` (Nicodemus et al.,
//! NBS Monograph 160, 1977: the BRDF's definition integrated over both beams), of the
//! luminance `Y` of the BRDF's R, G, B (the colour assumption of [`crate::colour`]).
//!
//! **Quadrature.** The source is a Gauss-Legendre grid. A glossy BRDF peaks at the mirror
//! image of each source direction, so the receptor integral is taken in polar coordinates
//! about that image (or about the window's point nearest to it, for an off-specular window):
//! the rectangle is a fan of four triangles from that centre, one per edge, each split at the
//! foot of its height and integrated by Gauss-Legendre in `asinh` of the position along the
//! edge (even in the polar angle near the foot, logarithmic towards far corners) and in
//! `ln r` out to the edge, which resolves a lobe of any width
//! down to `1e-5` of the aperture's size with the same nodes. Towards grazing angles a lobe
//! narrows across the plane of measurement by about `cos theta` (a facet tilted out of the
//! plane by `e` turns the reflection by `2 e cos theta`), so the polar coordinates are taken
//! in `(a, b / cos theta)`, where the lobe is round again.

use gauss_quad::legendre::GaussLegendre;
use specula_core::merl::{Bin, CELLS};
use specula_core::{Brdf, HalfDiff, Rgb};
use std::num::NonZeroUsize;

/// Luminance weights of linear sRGB / Rec. 709 R, G, B (IEC 61966-2-1: the Y row of the
/// RGB to XYZ matrix under D65), the colour assumption of [`crate::colour`].
pub const LUMINANCE_WEIGHTS: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// Luminance `Y` of an RGB triple under [`LUMINANCE_WEIGHTS`].
pub fn luminance(rgb: Rgb) -> f64 {
    LUMINANCE_WEIGHTS[0] * rgb.x + LUMINANCE_WEIGHTS[1] * rgb.y + LUMINANCE_WEIGHTS[2] * rgb.z
}

/// A rectangular aperture: full angles subtended at the specimen, degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aperture {
    /// Width in the plane of measurement.
    pub in_plane_deg: f64,
    /// Height perpendicular to the plane of measurement.
    pub perpendicular_deg: f64,
}

/// A source aperture at `theta_deg` from the normal and one receptor window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Beams {
    /// Angle of the source's centre (and of the mirror direction) from the normal.
    pub theta_deg: f64,
    /// The source aperture.
    pub source: Aperture,
    /// The receptor window.
    pub window: Aperture,
    /// In-plane offset of the window's centre from the mirror direction (positive away
    /// from the normal).
    pub offset_deg: f64,
}

/// Which MERL cells of a measured table hold extrapolated values (cell order of
/// [`specula_core::merl`]), e.g. from a reconstruction's provenance sidecar.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtrapolatedCells(Vec<bool>);

impl ExtrapolatedCells {
    /// The mask, one flag per MERL cell; `None` unless it has [`CELLS`] entries.
    pub fn new(flags: Vec<bool>) -> Option<Self> {
        (flags.len() == CELLS).then_some(Self(flags))
    }

    /// True when the cell holding the pair `(wi, wo)` is extrapolated.
    pub fn contains(&self, wi: glam::DVec3, wo: glam::DVec3) -> bool {
        self.0[Bin::of(HalfDiff::from_directions(wi, wo)).index()]
    }
}

/// The flux a receptor window collects, with how much of it the table could not vouch for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flux {
    /// `Phi` of the module documentation (luminance, 1/sr x sr^2 = sr).
    pub value: f64,
    /// Fraction of the integration's geometric weight that fell on cells the BRDF has not
    /// measured (skipped, so `value` counts the measured part only).
    pub unmeasured_fraction: f64,
    /// Fraction of `value` that comes from extrapolated cells.
    pub extrapolated_fraction: f64,
}

/// Gauss-Legendre nodes and weights mapped onto `[lo, hi]`.
fn gauss_legendre(nodes: usize, lo: f64, hi: f64) -> Vec<(f64, f64)> {
    let rule = GaussLegendre::new(NonZeroUsize::new(nodes).expect("at least one node"));
    let half = 0.5 * (hi - lo);
    rule.as_node_weight_pairs()
        .iter()
        .map(|&(x, w)| (lo + half * (x + 1.0), half * w))
        .collect()
}

/// Nodes of the source grid, in plane and across.
const SOURCE_NODES: [usize; 2] = [4, 6];
/// Nodes along each edge of a window (the polar angle), and in `ln r`.
const ANGLE_NODES: usize = 10;
const RADIUS_NODES: usize = 28;
/// Innermost radius of the polar grid, relative to the distance to the window's edge.
const INNERMOST_RADIUS: f64 = 1e-5;

/// A direction at offsets `(a, b)` (radians) from the centre at `theta` (radians) on the
/// receptor's side (+x); the source's side mirrors x.
fn direction(theta: f64, a: f64, b: f64, source_side: bool) -> glam::DVec3 {
    let x = b.cos() * (theta + a).sin();
    glam::DVec3::new(
        if source_side { -x } else { x },
        b.sin(),
        b.cos() * (theta + a).cos(),
    )
}

/// The source aperture's quadrature: directions `w_i` with weights `cos theta_i dw_i`.
pub fn source_nodes(theta_deg: f64, source: Aperture) -> Vec<(glam::DVec3, f64)> {
    let theta = theta_deg.to_radians();
    let (ha, hb) = half_widths_rad(source);
    let mut nodes = Vec::with_capacity(SOURCE_NODES[0] * SOURCE_NODES[1]);
    for (a, wa) in gauss_legendre(SOURCE_NODES[0], -ha, ha) {
        for (b, wb) in gauss_legendre(SOURCE_NODES[1], -hb, hb) {
            let wi = direction(theta, a, b, true);
            nodes.push((wi, wa * wb * b.cos() * wi.z));
        }
    }
    nodes
}

fn half_widths_rad(aperture: Aperture) -> (f64, f64) {
    (
        0.5 * aperture.in_plane_deg.to_radians(),
        0.5 * aperture.perpendicular_deg.to_radians(),
    )
}

/// Accumulated sums of one integration.
#[derive(Default)]
struct Sums {
    flux: f64,
    extrapolated: f64,
    weight: f64,
    unmeasured_weight: f64,
}

/// The flux of `beams` from `brdf` (see the module documentation).
pub fn collect(brdf: &dyn Brdf, beams: &Beams, extrapolated: Option<&ExtrapolatedCells>) -> Flux {
    let theta = beams.theta_deg.to_radians();
    let (ha, hb) = half_widths_rad(beams.window);
    let offset = beams.offset_deg.to_radians();
    let window = [offset - ha, offset + ha, -hb, hb];
    let mut sums = Sums::default();
    for (wi, source_weight) in source_nodes(beams.theta_deg, beams.source) {
        let (a_src, b_src) = source_offsets(wi, theta);
        // The mirror image of (a, b) is (a, -b); the nearest point of the window to it.
        let centre = [
            a_src.clamp(window[0], window[1]),
            (-b_src).clamp(window[2], window[3]),
        ];
        over_window_polar(window, centre, theta.cos(), |a, b, weight| {
            let wo = direction(theta, a, b, false);
            let w = source_weight * weight * b.cos() * wo.z;
            sums.weight += w;
            match brdf.eval_smooth(wi, wo) {
                Some(f) => {
                    let y = luminance(f) * w;
                    sums.flux += y;
                    if extrapolated.is_some_and(|cells| cells.contains(wi, wo)) {
                        sums.extrapolated += y;
                    }
                }
                None => sums.unmeasured_weight += w,
            }
        });
    }
    Flux {
        value: sums.flux,
        unmeasured_fraction: ratio(sums.unmeasured_weight, sums.weight),
        extrapolated_fraction: ratio(sums.extrapolated, sums.flux),
    }
}

fn ratio(part: f64, whole: f64) -> f64 {
    if whole > 0.0 {
        part / whole
    } else {
        0.0
    }
}

/// The in-plane and perpendicular offsets of `wi` from the source's centre at `theta`.
fn source_offsets(wi: glam::DVec3, theta: f64) -> (f64, f64) {
    let b = wi.y.clamp(-1.0, 1.0).asin();
    let a = (-wi.x).atan2(wi.z) - theta;
    (a, b)
}

/// `int_W g(a, b) da db` over the rectangle `[a0, a1] x [b0, b1]` in polar coordinates about
/// `centre` (inside the rectangle or on its edge) of `(a, b / squeeze)`; calls
/// `g(a, b, weight)` at each node.
fn over_window_polar(
    window: [f64; 4],
    centre: [f64; 2],
    squeeze: f64,
    mut g: impl FnMut(f64, f64, f64),
) {
    let [a0, a1, b0, b1] = [
        window[0],
        window[1],
        window[2] / squeeze,
        window[3] / squeeze,
    ];
    let [ca, cb] = [centre[0], centre[1] / squeeze];
    let corners = [(a0, b0), (a1, b0), (a1, b1), (a0, b1)];
    for k in 0..4 {
        let (p0, p1) = (corners[k], corners[(k + 1) % 4]);
        let length = (p1.0 - p0.0).hypot(p1.1 - p0.1);
        let (ea, eb) = ((p1.0 - p0.0) / length, (p1.1 - p0.1) / length);
        // Distance from the centre to the edge's line: the triangle's height.
        let height = ((p0.0 - ca) * eb - (p0.1 - cb) * ea).abs();
        if height <= 1e-15 {
            continue;
        }
        // Positions along the edge from the foot of the height, in units of the height:
        // tau = tan(psi - psi_foot). Nodes in v = asinh(tau) are even in the polar angle
        // near the foot and in ln(distance) towards far corners, so that neither a narrow
        // lobe about the centre nor a long edge is under-sampled.
        let foot = (ca - p0.0) * ea + (cb - p0.1) * eb;
        let (tau0, tau1) = (-foot / height, (length - foot) / height);
        let pieces = if tau0 < 0.0 && tau1 > 0.0 {
            vec![(tau0, 0.0), (0.0, tau1)]
        } else {
            vec![(tau0, tau1)]
        };
        for (lo, hi) in pieces {
            for (v, w_v) in gauss_legendre(ANGLE_NODES, lo.asinh(), hi.asinh()) {
                let tau = v.sinh();
                let along = foot + tau * height;
                let (da, db) = (p0.0 + along * ea - ca, p0.1 + along * eb - cb);
                let rho = height * v.cosh();
                // dpsi = dv / cosh v.
                let w_psi = w_v / v.cosh();
                let (c, s) = (da / rho, db / rho);
                // int_0^rho g r dr with r = rho e^u: int g r^2 du over [ln eps, 0].
                for (u, w_u) in gauss_legendre(RADIUS_NODES, INNERMOST_RADIUS.ln(), 0.0) {
                    let r = rho * u.exp();
                    g(
                        ca + r * c,
                        squeeze * (cb + r * s),
                        squeeze * w_psi * w_u * r * r,
                    );
                }
            }
        }
    }
}
