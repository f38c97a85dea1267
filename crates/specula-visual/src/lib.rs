//! Pictures of BRDFs: renders of a material on a sphere or a speedshape (paper Fig. 16, 17),
//! the characteristic slice and the raw samples (Fig. 11, 15), the probe against the adaptive
//! samples (Fig. 13), side-by-side grids, a self-contained HTML report and the interactive
//! viewer drawn in the browser.

pub mod camera;
pub mod canvas;
pub mod color;
pub mod distribution;
pub mod environment;
pub mod error;
pub mod font;
pub mod frame;
pub mod grid;
pub mod heatmap;
pub mod hit;
pub mod linear_image;
pub mod lobe;
pub mod nearest_bin_table;
pub mod plot;
pub mod render;
mod render_request;
pub mod report;
pub mod shape;
pub mod speedshape;
pub mod viewer;

pub use environment::Environment;
pub use image::RgbImage;
pub use linear_image::LinearImage;
pub use render::{render, Lighting, RenderSettings, Scene};
pub use render_request::{render_pictures, LightKind, RenderRequest, Rendered};
pub use shape::ShapeKind;
