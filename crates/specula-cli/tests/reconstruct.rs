//! `specula reconstruct --method prior` as a user selects it (issue 20): the data-driven
//! prior fills what the device cannot reach when the material's samples trust it, and the
//! sidecar and the summary say which cells came from it.

use assert_cmd::Command;
use predicates::prelude::*;
use specula_reconstruct::provenance::{CellOrigin, Provenance};
use std::path::Path;

fn specula() -> Command {
    Command::cargo_bin("specula").expect("the specula binary is built")
}

fn text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 temporary path")
}

#[test]
fn the_prior_method_marks_the_cells_it_fills() {
    let dir = tempfile::tempdir().unwrap();
    let samples = dir.path().join("samples.csv");
    // A material of the prior's own training set (the MERL-100 SGD fits) on a small plan:
    // its samples trust the prior.
    specula()
        .args([
            "evaluate",
            "--truth",
            "sgd:red-phenolic",
            "--theta-h-samples",
            "8",
        ])
        .args(["--theta-d-step", "6", "--samples-out", text(&samples)])
        .assert()
        .success();
    let reconstruct = |method: &str| {
        let out = dir.path().join(format!("{method}.binary"));
        let assert = specula()
            .args([
                "reconstruct",
                "--samples-csv",
                text(&samples),
                "--method",
                method,
            ])
            .args(["--out", text(&out)])
            .assert()
            .success()
            .stdout(predicate::str::contains(format!("(method {method})")));
        let stdout = String::from_utf8_lossy(&assert.get_output().stdout).into_owned();
        let sidecar = dir.path().join(format!("{method}.provenance.npy"));
        (stdout, Provenance::read(&sidecar).unwrap().cells)
    };
    let (prior_summary, prior) = reconstruct("prior");
    let (lobe_summary, lobe) = reconstruct("lobe");
    assert!(
        prior_summary.contains("of them from the prior"),
        "{prior_summary}"
    );
    assert!(!lobe_summary.contains("from the prior"), "{lobe_summary}");
    // The same cells lie beyond the measured nodes; the prior's are marked 3, the lobe's 2.
    assert!(prior.contains(&CellOrigin::Prior) && !lobe.contains(&CellOrigin::Prior));
    for (p, l) in prior.iter().zip(&lobe) {
        assert_eq!(p.is_extrapolated(), *l == CellOrigin::Extrapolated);
    }
    specula()
        .args(["info", text(&dir.path().join("prior.binary"))])
        .assert()
        .success()
        .stdout(predicate::str::contains("of them from the prior"));
}

#[test]
fn an_unknown_method_lists_the_methods() {
    specula()
        .args(["reconstruct", "--samples-csv", "s.csv", "--method", "cubic"])
        .args(["--out", "o.binary"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "expected linear, log, lobe, prior",
        ));
}
