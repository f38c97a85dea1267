//! A database of materials to analyse: MERL files (read one pass each, only their slice),
//! folders of them, and BRDFs already in memory (analytic materials, model fits), processed
//! in parallel with bounded memory: each task reads one material's slice, analyses it and
//! keeps only the small result.

use crate::error::SamplingError;
use crate::merl_slice::read_merl_slice;
use crate::slice::CharacteristicSlice;
use rayon::prelude::*;
use specula_core::Brdf;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// One material of a database.
#[derive(Clone)]
pub enum SliceSource {
    /// A MERL `.binary` file, of which only the characteristic slice is kept.
    MerlFile(PathBuf),
    /// Any BRDF, evaluated on the slice's nodes.
    Brdf(Arc<dyn Brdf>),
}

impl SliceSource {
    /// The material's name (the file stem, or the BRDF's name).
    pub fn name(&self) -> String {
        match self {
            SliceSource::MerlFile(path) => path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| path.display().to_string()),
            SliceSource::Brdf(brdf) => brdf.name(),
        }
    }

    /// Reads the characteristic slice of a MERL file (its 90 bins), or evaluates a BRDF's on
    /// `nodes` square-root-spaced theta_h nodes.
    pub fn slice(&self, nodes: usize) -> Result<CharacteristicSlice, SamplingError> {
        match self {
            SliceSource::MerlFile(path) => read_merl_slice(path),
            SliceSource::Brdf(brdf) => Ok(CharacteristicSlice::of(brdf.as_ref(), nodes)),
        }
    }
}

/// The MERL files of a folder (`*.binary`, sorted by name), or the path itself when it is a
/// file. The error names the path.
pub fn merl_files(path: &Path) -> Result<Vec<PathBuf>, SamplingError> {
    if !path.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let mut files = Vec::new();
    for entry in std::fs::read_dir(path).map_err(SamplingError::io(path, "list the folder"))? {
        let file = entry
            .map_err(SamplingError::io(path, "list the folder"))?
            .path();
        let is_merl = file
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("binary"));
        if is_merl && file.is_file() {
            files.push(file);
        }
    }
    if files.is_empty() {
        return Err(SamplingError::NoMerlFiles {
            path: path.to_path_buf(),
        });
    }
    files.sort();
    Ok(files)
}

/// Runs `work` on every source's slice (BRDFs evaluated on `nodes` theta_h nodes) in
/// parallel, calling `done` after each, and returns the results in the sources' order. Only
/// one slice per worker thread is alive at a time. A slice that cannot be read gives its
/// [`SamplingError`] as `work`'s error type.
pub fn map_slices<T, E, W, D>(
    sources: &[SliceSource],
    nodes: usize,
    work: W,
    done: D,
) -> Vec<Result<T, E>>
where
    T: Send,
    E: From<SamplingError> + Send,
    W: Fn(&CharacteristicSlice) -> Result<T, E> + Sync,
    D: Fn(&SliceSource) + Sync,
{
    sources
        .par_iter()
        .with_max_len(1)
        .map(|source| {
            let result = source
                .slice(nodes)
                .map_err(E::from)
                .and_then(|slice| work(&slice));
            done(source);
            result
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::merl_slice::SLICE_PHI_D_BIN;
    use crate::slice::THETA_H_NODES;
    use glam::DVec3;
    use specula_core::merl::{Bin, MerlBrdf};
    use specula_core::Rgb;
    use std::sync::atomic::{AtomicUsize, Ordering};

    struct Flat(f64);
    impl Brdf for Flat {
        fn eval(&self, _: DVec3, _: DVec3) -> Option<Rgb> {
            Some(Rgb::splat(self.0))
        }
        fn name(&self) -> String {
            format!("flat-{}", self.0)
        }
    }

    #[test]
    fn folders_list_their_merl_files_and_every_source_is_mapped_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let mut table = MerlBrdf::empty("x");
        let bin = Bin {
            theta_h_i: 10,
            theta_d_i: 40,
            phi_d_i: SLICE_PHI_D_BIN,
        };
        table.set_cell(bin.index(), Some(Rgb::splat(2.0)));
        table.write(&dir.path().join("b.binary")).unwrap();
        std::fs::write(dir.path().join("notes.txt"), "not a table").unwrap();
        std::fs::copy(dir.path().join("b.binary"), dir.path().join("a.BINARY")).unwrap();

        let files = merl_files(dir.path()).unwrap();
        let names: Vec<_> = files
            .iter()
            .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["a.BINARY", "b.binary"]);

        let mut sources: Vec<SliceSource> = files.into_iter().map(SliceSource::MerlFile).collect();
        sources.push(SliceSource::Brdf(Arc::new(Flat(0.5))));
        let count = AtomicUsize::new(0);
        let results = map_slices(
            &sources,
            THETA_H_NODES,
            |s| Ok::<_, SamplingError>((s.name().to_string(), s.value(40, 10))),
            |_| {
                count.fetch_add(1, Ordering::Relaxed);
            },
        );
        assert_eq!(count.load(Ordering::Relaxed), 3);
        let got: Vec<_> = results.into_iter().map(Result::unwrap).collect();
        assert_eq!(got[0], ("a".to_string(), Some(2.0)));
        assert_eq!(got[1].0, "b");
        assert_eq!(got[2], ("flat-0.5".to_string(), Some(0.5)));
    }

    #[test]
    fn errors_name_their_source() {
        let dir = tempfile::tempdir().unwrap();
        assert!(merl_files(dir.path())
            .unwrap_err()
            .to_string()
            .contains("no MERL"));
        let bad = dir.path().join("bad.binary");
        std::fs::write(&bad, b"short").unwrap();
        let results = map_slices(
            &[SliceSource::MerlFile(bad)],
            THETA_H_NODES,
            |_| Ok::<_, SamplingError>(()),
            |_| {},
        );
        assert!(format!("{:#}", results[0].as_ref().unwrap_err()).contains("bad.binary"));
    }
}
