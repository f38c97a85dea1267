//! Draws the occlusion model of the default device (or a device TOML) as a map over
//! theta_d x phi_d for a few theta_h: which pairs the device measures at its first position,
//! which only at an alternative position (the other camera side or the light arm tilted the
//! other way), which are occluded at every position and which are out of the axes' ranges.
//! The paper's grid (theta_d = 0, 3, ..., 87; phi_d = 0, 15, ..., 90) is drawn as dots.
//!
//!     cargo run -p specula-acquisition --example occlusion_map -- docs/book/src/occlusion.png [DEVICE.toml]

use plotters::prelude::*;
use specula_acquisition::device::Device;
use specula_acquisition::kinematics::solutions;
use specula_acquisition::occlusion::{blockage_within_accuracy, Blockage};
use specula_core::HalfDiff;
use std::path::Path;

const THETA_H_DEG: [f64; 4] = [0.0, 5.0, 20.0, 40.0];
const PHI_H_DEG: f64 = 45.0;

#[derive(Clone, Copy, PartialEq)]
enum Cell {
    FirstPosition,
    /// The first position is blocked (by this), an alternative is free.
    Alternative(Blockage),
    Occluded,
    Limit,
}

impl Cell {
    const LEGEND: [Cell; 6] = [
        Cell::FirstPosition,
        Cell::Occluded,
        Cell::Alternative(Blockage::View { light_part: 0 }),
        Cell::Limit,
        Cell::Alternative(Blockage::Beam { camera_part: 0 }),
        Cell::Alternative(Blockage::Collision {
            light_part: 0,
            camera_part: 0,
        }),
    ];

    fn colour(self) -> RGBColor {
        match self {
            Cell::FirstPosition => RGBColor(235, 235, 225),
            Cell::Alternative(Blockage::View { .. }) => RGBColor(110, 165, 230),
            Cell::Alternative(Blockage::Beam { .. }) => RGBColor(160, 110, 200),
            Cell::Alternative(Blockage::Collision { .. }) => RGBColor(240, 160, 50),
            Cell::Occluded => RGBColor(215, 40, 40),
            Cell::Limit => RGBColor(90, 90, 90),
        }
    }

    fn label(self) -> &'static str {
        match self {
            Cell::FirstPosition => "measured at the first position",
            Cell::Alternative(Blockage::View { .. }) => {
                "alternative: light head/arm in the camera's view"
            }
            Cell::Alternative(Blockage::Beam { .. }) => {
                "alternative: camera/arm in the light's beam"
            }
            Cell::Alternative(Blockage::Collision { .. }) => "alternative: the arms would collide",
            Cell::Occluded => "occluded at every position",
            Cell::Limit => "out of the axes' ranges",
        }
    }
}

fn classify(device: &Device, hd: HalfDiff) -> Cell {
    let (wi, wo) = hd.to_directions();
    let reachable = solutions(device, wi, wo);
    let Some(first) = reachable.first() else {
        return Cell::Limit;
    };
    match blockage_within_accuracy(device, first) {
        None => Cell::FirstPosition,
        Some(b)
            if reachable[1..]
                .iter()
                .any(|a| blockage_within_accuracy(device, a).is_none()) =>
        {
            Cell::Alternative(b)
        }
        Some(_) => Cell::Occluded,
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args
        .next()
        .unwrap_or_else(|| "docs/book/src/occlusion.png".to_string());
    let device = match args.next() {
        Some(path) => Device::load(Path::new(&path))?,
        None => Device::utia(),
    };
    plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| "the embedded font does not parse")?;

    let (width, panel_height, legend_height) = (900u32, 260u32, 90u32);
    let height = panel_height * THETA_H_DEG.len() as u32 + legend_height;
    let root = BitMapBackend::new(&out, (width, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let (panels_area, legend_area) = root.split_vertically(height - legend_height);
    let panels = panels_area.split_evenly((THETA_H_DEG.len(), 1));

    for (panel, &theta_h) in panels.iter().zip(&THETA_H_DEG) {
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!("theta_h = {theta_h} deg"),
                ("sans-serif", 18).into_font(),
            )
            .margin(6)
            .x_label_area_size(28)
            .y_label_area_size(44)
            .build_cartesian_2d(0.0..360.0f64, 0.0..90.0f64)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("phi_d (deg)")
            .y_desc("theta_d (deg)")
            .x_labels(13)
            .y_labels(4)
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| format!("{y:.0}"))
            .label_style(("sans-serif", 12))
            .draw()?;
        // Cells of 1 deg in phi_d by 0.5 deg in theta_d, classified at their centres.
        let cells = (0..180).flat_map(|td| (0..360).map(move |pd| (td, pd)));
        chart.draw_series(cells.map(|(td, pd)| {
            let (td, pd) = (td as f64 * 0.5, pd as f64);
            let hd = HalfDiff::from_degrees(theta_h, PHI_H_DEG, td + 0.25, pd + 0.5);
            let cell = classify(&device, hd);
            Rectangle::new([(pd, td), (pd + 1.0, td + 0.5)], cell.colour().filled())
        }))?;
        let grid = (0..30).flat_map(|i| (0..7).map(move |j| (j as f64 * 15.0, i as f64 * 3.0)));
        chart.draw_series(grid.map(|(pd, td)| Circle::new((pd, td), 1, BLACK.filled())))?;
    }

    for (i, cell) in Cell::LEGEND.iter().enumerate() {
        let x = 20 + (i as i32 % 2) * 430;
        let y = 10 + (i as i32 / 2) * 26;
        legend_area.draw(&Rectangle::new(
            [(x, y), (x + 18, y + 18)],
            cell.colour().filled(),
        ))?;
        legend_area.draw(&Text::new(
            cell.label(),
            (x + 26, y + 2),
            ("sans-serif", 15).into_font(),
        ))?;
    }
    root.present()?;
    println!("wrote {out}");
    Ok(())
}
