//! One module per subcommand: its arguments (with the `--help` text) and its `run`.

pub mod analyze;
pub mod appearance;
pub mod calibrate;
pub mod check;
pub mod compare;
pub mod convert;
pub mod demo;
pub mod device;
pub mod eval;
pub mod evaluate;
pub mod fit;
pub mod fit_k;
pub mod grid_args;
pub mod info;
pub mod materials;
pub mod measure;
pub mod placement;
pub mod plan;
pub mod plot;
pub mod probe;
pub mod reconstruct;
pub mod render;
pub mod report;
pub mod session;
pub mod tabulate;

/// Refuses an output path whose extension is not `.binary`, for the commands that write a
/// MERL table (`specula convert` writes the other formats).
pub fn require_merl_out(path: &std::path::Path) -> anyhow::Result<()> {
    let is_merl = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("binary"));
    if !is_merl {
        anyhow::bail!(
            "{}: this command writes a MERL table, so --out must end in .binary (`specula convert` turns it into .bin or .csv)",
            path.display()
        );
    }
    Ok(())
}
pub mod token_args;
