//! "Did you mean …?" hints: the known name closest to a misspelt one.

/// The candidate closest to `name` by edit distance, if it is close enough to be a likely typo.
pub(crate) fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let length = name.chars().count();
    let limit = if length <= 3 { 1 } else { (length / 3).max(2) };
    candidates
        .into_iter()
        .map(|c| (strsim::levenshtein(&name.to_lowercase(), &c.to_lowercase()), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// `"; did you mean `x`?"`, or nothing.
pub(crate) fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    closest(name, candidates).map(|c| format!("; did you mean `{c}`?")).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_near_names_only() {
        let names = ["crank", "rod", "slider"];
        assert_eq!(closest("crnak", names), Some("crank"));
        assert_eq!(closest("slidr", names), Some("slider"));
        assert_eq!(closest("pendulum", names), None);
        assert_eq!(closest("sitting", ["kitten"]), None, "3 edits is too far for a 7-letter name");
        assert_eq!(closest("sittin", ["kitten"]), Some("kitten"), "2 edits is near enough for 6 letters");
    }
}
