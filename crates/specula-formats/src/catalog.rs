//! Every BRDF Specula knows by name, grouped by where it comes from, and near-name
//! suggestions for a name it does not know.

use crate::fits::{load_model, FitModel};
use crate::input::Result;
use crate::nbrdf::NbrdfSet;
use specula_core::materials::{builtin_database, preset_names};

/// A group of named BRDFs and where they come from.
pub struct Group {
    /// How to name one in a BRDF argument (`NAME`, `sgd:NAME`, ...).
    pub pattern: String,
    /// Where the group comes from: the model, the paper or table, the licence.
    pub provenance: &'static str,
    /// The full names, as BRDF arguments take them.
    pub names: Vec<String>,
}

/// Every group: the presets, the rest of the built-in database, the fits built into the
/// program, and the Lafortune fits when the measured data directory holds their table.
pub fn groups() -> Result<Vec<Group>> {
    let presets: Vec<String> = preset_names().into_iter().map(String::from).collect();
    let database: Vec<String> = builtin_database()
        .into_iter()
        .map(|m| m.name)
        .filter(|name| !presets.contains(name))
        .collect();
    let mut groups = vec![
        Group {
            pattern: "NAME".into(),
            provenance: "analytic presets: the paper's materials (section 4.2) and MERL's chrome and steel, literature optical constants (docs/book/src/materials.md)",
            names: presets,
        },
        Group {
            pattern: "NAME".into(),
            provenance: "the built-in database of specular and glossy materials: analytic metals and clear-coated paints (docs/book/src/materials.md)",
            names: database,
        },
    ];
    for (model, provenance) in [
        (FitModel::Sgd, "shifted-gamma microfacet fits of the 100 MERL materials, Bagher, Soler & Holzschuch 2012 (dj_brdf table, public domain; built in)"),
        (FitModel::Abc, "ABC model fits of the 100 MERL materials, Löw et al. 2012 (dj_brdf table, public domain; built in)"),
    ] {
        groups.push(Group {
            pattern: format!("{}:NAME", model.prefix()),
            provenance,
            names: load_model(model)?.iter().map(|f| f.name()).collect(),
        });
    }
    for (set, provenance) in [
        (NbrdfSet::Merl100, "neural BRDFs of the 100 MERL materials, Sztrajman et al. 2021 (MIT; built in; smooths the sharpest mirror peaks)"),
        (NbrdfSet::RglIsotropic, "neural BRDFs of 51 isotropic RGL materials, Sztrajman et al. 2021 (MIT; built in)"),
        (NbrdfSet::Nielsen2015, "neural BRDFs of 8 materials of Nielsen et al. 2015, Sztrajman et al. 2021 (MIT; built in)"),
    ] {
        groups.push(Group {
            pattern: format!("{}:NAME", set.prefix()),
            provenance,
            names: set
                .names()?
                .into_iter()
                .map(|n| format!("{}:{n}", set.prefix()))
                .collect(),
        });
    }
    let lafortune = crate::input::measured_data_dir().join(crate::lafortune::TABLE);
    if lafortune.is_file() {
        groups.push(Group {
            pattern: "lafortune:NAME".into(),
            provenance: "Lafortune fits of MERL/MIT materials, Ngan et al. 2005 (GPL-3.0 table, read from the measured data directory, not built in)",
            names: crate::lafortune::Lafortune::read_table(&lafortune)?
                .into_iter()
                .map(|f| format!("lafortune:{}", f.name))
                .collect(),
        });
    }
    Ok(groups)
}

/// Every name of every group (for suggestions).
pub fn all_names() -> Vec<String> {
    groups()
        .map(|groups| groups.into_iter().flat_map(|g| g.names).collect())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::near_name::{did_you_mean, nearest};

    #[test]
    fn a_near_name_is_suggested() {
        let names = all_names();
        assert!(nearest("paint-red", &names).contains(&"paint-red-gloss".to_string()));
        assert!(nearest("silver925", &names).contains(&"silver-925".to_string()));
        assert!(did_you_mean("qqqqqq", &names).is_empty());
    }

    #[test]
    fn every_group_has_names_and_provenance() {
        for group in groups().unwrap() {
            assert!(!group.names.is_empty(), "{}", group.pattern);
            assert!(!group.provenance.is_empty());
        }
    }
}
