//! Beyond the paper: the paper's pipeline (exponential theta_h with k-hat, the 30 x 30 x 7
//! plan, linear reconstruction) against ours (the `lobe` method, and smaller plans), averaged
//! over sets of ground-truth materials, each measured without noise on the UTIA device model.
//!
//!     cargo run --release -p specula-accuracy --example accuracy_study -- \
//!         [--set rgl] [--set nbrdf-rgl] [--set builtin] [--set sgd] [--set abc] [--set nbrdf]
//!         [--every N] [--plan HxDxP]... [--trust W,S2]... [--breakdown] [--no-prior]
//!
//! Configurations: `paper` (the paper's pipeline), `paper-plan+lobe` and `paper-plan+log`
//! (the same samples, reconstructed by the `lobe` and `log` methods) and, for each
//! `--plan HxDxP`, `lobe-HxDxP`: H theta_h positions (exponential function, k-hat), theta_d
//! step D and phi_d step P degrees (D may be `STEP:GRAZING_STEP@FROM`, graded theta_d
//! positions, `specula_core::grid::ThetaDSteps`), `lobe`, and `prior-HxDxP`, the `prior` method
//! (`specula_reconstruct::prior_reconstruct`) on the same plan; `paper-plan+prior` on the
//! paper's samples, and for each `--trust W,S2` the same with the prior weight W and noise
//! variance S2 given instead of chosen by cross-validation. Sets: `rgl` (the real RGL measurements in the
//! measured data directory's `rgl_bsdf/`), `nbrdf-rgl` (their 51 neural fits), `builtin`,
//! `sgd`, `abc`, `nbrdf` (the MERL-100 fits); default builtin, sgd and abc.
//!
//! `P` may end in `h` (e.g. `16x3:1@60x30h`, `specula_core::GridSpec::recommended`): phi_d
//! every P degrees over the half turn 0 to 180 (`specula_core::grid::PhiDSpan::HalfTurn`),
//! the halves reconstructed apart (`specula_reconstruct::phi_d_halves`, as
//! `specula_accuracy::evaluate` does whenever the samples measure both). `--no-prior` leaves
//! out the `prior` configurations.
//!
//! `--breakdown` also prints, after each material's row, where its squared error sits
//! (`specula_reconstruct::breakdown`): rows `breakdown,set,material,config,region,cells,
//! share,rel_within` for each region of each partition.
//!
//! Prints one CSV row per material and configuration, then the mean of each configuration
//! per set and over all sets with the ratio of each mean to the paper pipeline's, then the
//! median over each set's materials of the per-material ratio to the paper pipeline's.

use specula_accuracy::merl_prior::merl_prior;
use specula_accuracy::{evaluate, Accuracy, Measurement, PlanSettings};
use specula_acquisition::device::Device;
use specula_core::capture::CaptureResponse;
use specula_core::grid::{PhiDSpan, ThetaDSteps};
use specula_core::materials::builtin_database;
use specula_core::statistics::median;
use specula_core::tabulate::tabulate;
use specula_core::Brdf;
use specula_core::{GridSpec, Sample};
use specula_formats::fits::{load_model, FitModel};
use specula_formats::input::measured_data_dir;
use specula_formats::load_brdfs;
use specula_formats::nbrdf::NbrdfSet;
use specula_reconstruct::breakdown::{error_by_region, Partition};
use specula_reconstruct::phi_d_halves::reconstruct_halves_with;
use specula_reconstruct::prior_reconstruct::reconstruct_with_prior;
use specula_reconstruct::Method;
use std::collections::BTreeMap;
use std::error::Error;
use std::sync::Arc;

/// A reconstruction: a [`Method`] or the `prior` method with its trust given as prior
/// weight and noise variance.
#[derive(Clone, Copy)]
enum Recon {
    Method(Method),
    ForcedPrior(f64, f64),
}

/// A plan and a reconstruction.
#[derive(Clone)]
struct Config {
    name: String,
    plan: PlanSettings,
    method: Recon,
}

/// A material measured on a plan: the sample count, the samples and k (when a sampling
/// function placed theta_h).
type Measured = (usize, Vec<Sample>, Option<f64>);

impl Config {
    /// The material measured on this configuration's plan.
    fn measure(&self, truth: &dyn Brdf, device: &Device) -> Result<Measured, Box<dyn Error>> {
        let m = Measurement::simulate(truth, &self.plan, device)?;
        Ok((m.samples.len(), m.samples, m.k))
    }
}

/// The paper's pipeline, our method on its samples, and our method on each smaller plan.
fn configs(
    plans: &[String],
    trusts: &[(f64, f64)],
    with_prior: bool,
) -> Result<Vec<Config>, Box<dyn Error>> {
    let paper = PlanSettings::paper();
    let mut out = vec![
        Config {
            name: "paper".into(),
            plan: paper,
            method: Recon::Method(Method::Linear),
        },
        Config {
            name: "paper-plan+lobe".into(),
            plan: paper,
            method: Recon::Method(Method::Lobe),
        },
        Config {
            name: "paper-plan+log".into(),
            plan: paper,
            method: Recon::Method(Method::Log),
        },
        Config {
            name: "paper-plan+prior".into(),
            plan: paper,
            method: Recon::Method(Method::Prior),
        },
    ];
    for &(w, s2) in trusts {
        out.push(Config {
            name: format!("paper-plan+prior-w{w}-s{s2}"),
            plan: paper,
            method: Recon::ForcedPrior(w, s2),
        });
    }
    if !with_prior {
        out.retain(|c| {
            !matches!(
                c.method,
                Recon::ForcedPrior(..) | Recon::Method(Method::Prior)
            )
        });
    }
    for spec in plans {
        let plan = PlanSettings {
            grid: grid_of(spec, &paper.grid)?,
            ..paper
        };
        out.push(Config {
            name: format!("lobe-{spec}"),
            plan,
            method: Recon::Method(Method::Lobe),
        });
        if with_prior {
            out.push(Config {
                name: format!("prior-{spec}"),
                plan,
                method: Recon::Method(Method::Prior),
            });
        }
    }
    Ok(out)
}

/// The grid of a `--plan HxDxP[h]`: H theta_h, theta_d D (`STEP` or `STEP:GRAZING@FROM`),
/// phi_d step P, over the half turn with `h`; phi_h as `base`.
fn grid_of(spec: &str, base: &GridSpec) -> Result<GridSpec, Box<dyn Error>> {
    let bad = || format!("--plan {spec}: expected HxDxP[h], e.g. 24x4x22.5 or 16x3:1@60x30h");
    let (spec_p, phi_d_span) = match spec.strip_suffix('h') {
        Some(rest) => (rest, PhiDSpan::HalfTurn),
        None => (spec, PhiDSpan::Quarter),
    };
    let [h, d, p] = spec_p.split('x').collect::<Vec<_>>()[..] else {
        return Err(bad().into());
    };
    let theta_d: ThetaDSteps = d.parse().map_err(|e| format!("--plan {spec}: {e}"))?;
    Ok(GridSpec {
        theta_h_samples: h.parse().map_err(|_| bad())?,
        theta_d,
        phi_d_step_deg: p.parse().map_err(|_| bad())?,
        phi_d_span,
        ..*base
    })
}

fn truths(set: &str) -> Result<Vec<Arc<dyn Brdf>>, Box<dyn Error>> {
    Ok(match set {
        "rgl" => load_brdfs(&measured_data_dir().join("rgl_bsdf").to_string_lossy())?,
        "nbrdf-rgl" => NbrdfSet::RglIsotropic.load_all()?,
        "builtin" => builtin_database()
            .into_iter()
            .map(|m| Arc::new(m) as Arc<dyn Brdf>)
            .collect(),
        "sgd" => load_model(FitModel::Sgd)?,
        "abc" => load_model(FitModel::Abc)?,
        "nbrdf" => NbrdfSet::Merl100.load_all()?,
        other => {
            return Err(
                format!("unknown set {other} (rgl, nbrdf-rgl, builtin, sgd, abc, nbrdf)").into(),
            )
        }
    })
}

#[derive(Default, Clone, Copy)]
struct Sums {
    n: usize,
    measured: f64,
    max_measured: usize,
    figures: [f64; 6],
}

impl Sums {
    fn add(&mut self, measured: usize, a: &Accuracy) {
        self.n += 1;
        self.measured += measured as f64;
        self.max_measured = self.max_measured.max(measured);
        for (sum, f) in self.figures.iter_mut().zip(figures(a)) {
            *sum += f;
        }
    }
    fn mean(&self) -> (f64, [f64; 6]) {
        let n = self.n.max(1) as f64;
        (self.measured / n, self.figures.map(|v| v / n))
    }
}

fn figures(a: &Accuracy) -> [f64; 6] {
    [
        a.within.relative_rmse,
        a.within.log_rmse,
        a.within.slice_mae,
        a.all.relative_rmse,
        a.all.log_rmse,
        a.all.slice_mae,
    ]
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut sets = Vec::new();
    let mut every = 1usize;
    let mut plans = Vec::new();
    let mut trusts = Vec::new();
    let mut breakdown = false;
    let mut with_prior = true;
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "--set" => {
                sets.push(args.get(i + 1).cloned().unwrap_or_default());
                i += 1;
            }
            "--every" => {
                every = args
                    .get(i + 1)
                    .and_then(|v| v.parse().ok())
                    .unwrap_or(1)
                    .max(1);
                i += 1;
            }
            "--trust" => {
                let spec = args.get(i + 1).cloned().unwrap_or_default();
                let parts: Vec<f64> = spec.split(',').filter_map(|v| v.parse().ok()).collect();
                let [w, s2] = parts[..] else {
                    return Err(format!("--trust {spec}: expected W,S2, e.g. 0.5,0.1").into());
                };
                trusts.push((w, s2));
                i += 1;
            }
            "--breakdown" => breakdown = true,
            "--no-prior" => with_prior = false,
            "--plan" => {
                plans.push(args.get(i + 1).cloned().unwrap_or_default());
                i += 1;
            }
            other => return Err(format!("unknown argument {other}").into()),
        }
        i += 1;
    }
    if sets.is_empty() {
        sets = vec!["builtin".into(), "sgd".into(), "abc".into()];
    }
    let device = Device::utia();
    let configs = configs(&plans, &trusts, with_prior)?;
    let basis = if with_prior {
        Some(merl_prior()?)
    } else {
        None
    };
    let mut sums: BTreeMap<(String, String), Sums> = BTreeMap::new();
    // Per set and configuration, each material's ratios to the paper pipeline's figures.
    let mut ratios: BTreeMap<(String, String), Vec<[f64; 4]>> = BTreeMap::new();
    println!(
        "set,material,config,k,measured,rel_within,log_within,mae_within,rel_all,log_all,mae_all"
    );
    for set in &sets {
        for truth in truths(set)?.iter().step_by(every) {
            let table = tabulate(
                truth.as_ref(),
                PlanSettings::paper().grid.phi_h_deg.to_radians(),
            );
            let mut paper_figures = None;
            for config in &configs {
                let (count, samples, k) = config.measure(truth.as_ref(), &device)?;
                let (reconstruction, a) = match config.method {
                    Recon::Method(method) => {
                        evaluate(&samples, method, &table, 75.0, basis.as_deref())?
                    }
                    Recon::ForcedPrior(w, s2) => {
                        let basis = basis.as_ref().expect("prior configurations need the basis");
                        let r = reconstruct_halves_with(&samples, |half| {
                            let none = None::<&dyn CaptureResponse>;
                            let given = Some((w, s2));
                            reconstruct_with_prior(half, basis, "prior", given, none)
                                .map(|(r, _)| r)
                        })?;
                        let a = Accuracy::of(&r.brdf, &table, 75.0);
                        (r, a)
                    }
                };
                let f = figures(&a);
                let paper = *paper_figures.get_or_insert(f);
                ratios
                    .entry((set.clone(), config.name.clone()))
                    .or_default()
                    .push([0, 1, 3, 4].map(|i| f[i] / paper[i]));
                println!(
                    "{set},{},{},{},{},{:.5},{:.5},{:.4e},{:.5},{:.5},{:.4e}",
                    truth.name(),
                    config.name,
                    k.map_or(String::new(), |k| format!("{k:.3}")),
                    count,
                    f[0],
                    f[1],
                    f[2],
                    f[3],
                    f[4],
                    f[5]
                );
                if breakdown {
                    for partition in Partition::ALL {
                        let regions = error_by_region(
                            &reconstruction.brdf,
                            &table,
                            &reconstruction.provenance,
                            75.0,
                            partition,
                        );
                        for r in regions {
                            println!(
                                "breakdown,{set},{},{},{},{},{:.4},{:.5}",
                                truth.name(),
                                config.name,
                                r.name,
                                r.cells,
                                r.share,
                                r.relative_rmse
                            );
                        }
                    }
                }
                for key in [set.clone(), "all".into()] {
                    sums.entry((key, config.name.clone()))
                        .or_default()
                        .add(count, &a);
                }
            }
        }
    }
    println!("\nset,config,materials,mean_measured,max_measured,rel_within,log_within,mae_within,rel_all,log_all,mae_all,ratio_rel_within,ratio_log_within,ratio_rel_all,ratio_log_all");
    for ((set, config), s) in &sums {
        let (measured, f) = s.mean();
        let (_, paper) = sums[&(set.clone(), "paper".to_string())].mean();
        println!(
            "{set},{config},{},{measured:.0},{},{:.5},{:.5},{:.4e},{:.5},{:.5},{:.4e},{:.3},{:.3},{:.3},{:.3}",
            s.n, s.max_measured, f[0], f[1], f[2], f[3], f[4], f[5],
            f[0] / paper[0], f[1] / paper[1], f[3] / paper[3], f[4] / paper[4]
        );
    }
    println!("\nset,config,materials,median_ratio_rel_within,median_ratio_log_within,median_ratio_rel_all,median_ratio_log_all,max_ratio_rel_within,max_ratio_log_within");
    for ((set, config), per_material) in &ratios {
        let column = |i: usize| per_material.iter().map(|r| r[i]).collect::<Vec<f64>>();
        let max = |i: usize| column(i).into_iter().fold(0.0, f64::max);
        println!(
            "{set},{config},{},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3}",
            per_material.len(),
            median(&mut column(0)),
            median(&mut column(1)),
            median(&mut column(2)),
            median(&mut column(3)),
            max(0),
            max(1)
        );
    }
    Ok(())
}
