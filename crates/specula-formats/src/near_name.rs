//! Near-name suggestions for a name that was not found: a leaf that the catalogue and every
//! named source (fits, neural fits, the resolver) share.

/// `; did you mean A, B?` with the names nearest `wanted` (by Jaro-Winkler similarity, and
/// any name that contains it), or nothing when none is near.
pub fn did_you_mean(wanted: &str, names: &[String]) -> String {
    let near = nearest(wanted, names);
    if near.is_empty() {
        String::new()
    } else {
        format!("; did you mean {}?", near.join(", "))
    }
}

/// Up to three names near `wanted`, the nearest first.
pub fn nearest(wanted: &str, names: &[String]) -> Vec<String> {
    let mut scored: Vec<(f64, &String)> = names
        .iter()
        .map(|name| {
            let contains = name.contains(wanted) || wanted.contains(name.as_str());
            let score = strsim::jaro_winkler(wanted, name) + if contains { 0.2 } else { 0.0 };
            (score, name)
        })
        .filter(|(score, _)| *score >= 0.85)
        .collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    scored.into_iter().take(3).map(|(_, n)| n.clone()).collect()
}
