//! Mode sets named as in the seed: `5S`, `5N`, `9N`, `4N5S` — counts of vibration (N) and static
//! correction (S) modes, in the order written — and `rigid`, no modes: the body moves rigidly with
//! its FE model's mass properties (to compare a flexible model with its rigid counterpart).

use std::fmt;
use std::str::FromStr;

use crate::error::FemError;

/// One group of a mode set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeGroup {
    /// The lowest `n` vibration modes.
    Vibration(usize),
    /// The first `n` static correction modes, in the order the loads are listed.
    Static(usize),
}

/// A mode set: groups of vibration and static correction modes, in basis order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModeSet {
    /// The groups, in basis order.
    pub groups: Vec<ModeGroup>,
}

impl ModeSet {
    /// Number of vibration modes.
    pub fn vibration(&self) -> usize {
        self.groups.iter().map(|g| if let ModeGroup::Vibration(n) = g { *n } else { 0 }).sum()
    }

    /// Number of static correction modes.
    pub fn statics(&self) -> usize {
        self.groups.iter().map(|g| if let ModeGroup::Static(n) = g { *n } else { 0 }).sum()
    }

    /// Total number of modes.
    pub fn len(&self) -> usize {
        self.vibration() + self.statics()
    }

    /// Whether the set has no mode.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl FromStr for ModeSet {
    type Err = FemError;

    fn from_str(text: &str) -> Result<Self, FemError> {
        let error = |message: &str| FemError::ModeSet { text: text.to_string(), message: message.to_string() };
        let expected =
            "expected groups of a count and N (vibration) or S (static correction), e.g. 5S, 9N or 4N5S, or `rigid` for no modes";
        if text.trim().eq_ignore_ascii_case("rigid") {
            return Ok(ModeSet { groups: Vec::new() });
        }
        let mut groups = Vec::new();
        let mut digits = String::new();
        for c in text.trim().chars() {
            match c {
                '0'..='9' => digits.push(c),
                'N' | 'n' | 'S' | 's' => {
                    let count: usize = digits.parse().map_err(|_| error(expected))?;
                    if count == 0 {
                        return Err(error("a group must have at least one mode"));
                    }
                    digits.clear();
                    let group = if c.eq_ignore_ascii_case(&'N') { ModeGroup::Vibration(count) } else { ModeGroup::Static(count) };
                    if groups.iter().any(|g| std::mem::discriminant(g) == std::mem::discriminant(&group)) {
                        return Err(error("each of N and S may appear once"));
                    }
                    groups.push(group);
                }
                _ => return Err(error(expected)),
            }
        }
        if !digits.is_empty() || groups.is_empty() {
            return Err(error(expected));
        }
        Ok(ModeSet { groups })
    }
}

impl fmt::Display for ModeSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.groups.is_empty() {
            return write!(f, "rigid");
        }
        for g in &self.groups {
            match g {
                ModeGroup::Vibration(n) => write!(f, "{n}N")?,
                ModeGroup::Static(n) => write!(f, "{n}S")?,
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_seeds_mode_sets() {
        let set: ModeSet = "4N5S".parse().unwrap();
        assert_eq!(set.groups, vec![ModeGroup::Vibration(4), ModeGroup::Static(5)]);
        assert_eq!((set.vibration(), set.statics(), set.len()), (4, 5, 9));
        assert_eq!(set.to_string(), "4N5S");
        assert_eq!("5s".parse::<ModeSet>().unwrap().to_string(), "5S");
        assert_eq!("12N".parse::<ModeSet>().unwrap().vibration(), 12);
        let rigid: ModeSet = "rigid".parse().unwrap();
        assert!(rigid.is_empty());
        assert_eq!(rigid.to_string(), "rigid");
        for bad in ["", "N", "5", "5X", "0N", "4N4N", "4N 5S", "rigidly"] {
            assert!(bad.parse::<ModeSet>().is_err(), "{bad}");
        }
    }
}
