//! "Did you mean": the names nearest to one the user gave, for the bench commands that take
//! names (an entry of an EDS, a parameter of an ODVA EDS, an assembly member) and the readers'
//! unknown keywords: one edit-distance rule and one listing.

/// How many suggestions a listing shows.
const SHOWN: usize = 8;

/// The candidates whose key is nearest to `wanted` by edit distance, nearest first (ties keep
/// the order given); with `near_only`, only those at most a third of `wanted`'s length away.
pub fn closest<T>(
    wanted: &str,
    candidates: impl IntoIterator<Item = (String, T)>,
    near_only: bool,
) -> Vec<T> {
    let limit = wanted.chars().count().div_ceil(3);
    let mut scored: Vec<(usize, T)> = candidates
        .into_iter()
        .map(|(key, candidate)| (strsim::levenshtein(wanted, &key), candidate))
        .filter(|(distance, _)| !near_only || *distance <= limit)
        .collect();
    scored.sort_by_key(|(distance, _)| *distance);
    scored.into_iter().map(|(_, candidate)| candidate).collect()
}

/// The candidate a misspelt name most likely means, case aside: the nearest whose key is at most
/// two edits (and a third of the name's length) away; `None` when none is. A misspelling is a
/// letter or two away; farther is another name, not a typo.
pub fn misspelt<T>(wanted: &str, candidates: impl IntoIterator<Item = (String, T)>) -> Option<T> {
    let wanted = wanted.to_ascii_lowercase();
    let lowered = candidates
        .into_iter()
        .map(|(key, candidate)| (key.to_ascii_lowercase(), (key, candidate)));
    closest(&wanted, lowered, true)
        .into_iter()
        .find(|(key, _)| strsim::levenshtein(&wanted, &key.to_ascii_lowercase()) <= 2)
        .map(|(_, candidate)| candidate)
}

/// `; did you mean:` and up to eight lines (each indented, then `... and N more`), or nothing.
pub fn listing(lines: &[String]) -> String {
    if lines.is_empty() {
        return String::new();
    }
    let mut list: Vec<String> = lines.iter().take(SHOWN).map(|l| format!("  {l}")).collect();
    if lines.len() > SHOWN {
        list.push(format!("  ... and {} more", lines.len() - SHOWN));
    }
    format!("; did you mean:\n{}", list.join("\n"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_first_ties_in_order_and_a_third_of_the_length() {
        let names = ["speed", "sped up", "spend", "torque"].map(|n| (n.to_owned(), n));
        assert_eq!(closest("sped", names.clone(), true), ["speed", "spend"]);
        assert_eq!(
            closest("sped", names, false),
            ["speed", "spend", "sped up", "torque"]
        );
    }

    #[test]
    fn a_misspelling_is_two_letters_away_at_most_case_aside() {
        let keys = ["VendCode", "VendName", "ProdCode"].map(|k| (k.to_owned(), k));
        assert_eq!(misspelt("vendcod", keys.clone()), Some("VendCode"));
        assert_eq!(misspelt("VENDNAM", keys.clone()), Some("VendName"));
        assert_eq!(misspelt("Vendor", keys.clone()), None);
        assert_eq!(misspelt("X", keys), None);
    }

    #[test]
    fn listing_shows_eight() {
        assert_eq!(listing(&[]), "");
        let lines: Vec<String> = (1..=10).map(|n| format!("Param{n}")).collect();
        let shown = listing(&lines);
        assert!(shown.starts_with("; did you mean:\n  Param1\n  Param2\n"));
        assert!(shown.ends_with("\n  Param8\n  ... and 2 more"));
    }
}
