//! Mode sets named as in the seed: `5S`, `5N`, `9N`, `4N5S` — counts of vibration (N) and static
//! correction (S) modes, in the order written — and `rigid`, no modes: the body moves rigidly with
//! its FE model's mass properties (to compare a flexible model with its rigid counterpart).
//!
//! Two more groups make the interface sets, whose interface is the degrees of freedom the supports
//! hold ([`interface_modes`](super::interface_modes)): `C`, the constraint modes of Craig–Bampton
//! (with `N` the fixed-interface modes: `20N12C`), and `F` with `A`, the free-free vibration modes and
//! the residual attachment modes of the free-interface (Herting-like) set (`20F12A`).

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
    /// The `n` constraint modes of Craig–Bampton, one per held dof (all of them).
    Constraint(usize),
    /// The lowest `n` free-free vibration modes (free interface).
    FreeVibration(usize),
    /// The `n` residual attachment modes of the free-interface set, one per held dof (all of them).
    Attachment(usize),
}

impl ModeGroup {
    /// The group's letter.
    pub fn letter(self) -> char {
        match self {
            ModeGroup::Vibration(_) => 'N',
            ModeGroup::Static(_) => 'S',
            ModeGroup::Constraint(_) => 'C',
            ModeGroup::FreeVibration(_) => 'F',
            ModeGroup::Attachment(_) => 'A',
        }
    }

    /// The number of modes.
    pub fn count(self) -> usize {
        match self {
            ModeGroup::Vibration(n) | ModeGroup::Static(n) | ModeGroup::Constraint(n) | ModeGroup::FreeVibration(n) | ModeGroup::Attachment(n) => n,
        }
    }
}

/// A mode set: groups of vibration and static correction modes, in basis order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModeSet {
    /// The groups, in basis order.
    pub groups: Vec<ModeGroup>,
}

impl ModeSet {
    fn count_of(&self, letter: char) -> usize {
        self.groups.iter().filter(|g| g.letter() == letter).map(|g| g.count()).sum()
    }

    /// Number of vibration modes (of the supported model: fixed-interface in a Craig–Bampton set).
    pub fn vibration(&self) -> usize {
        self.count_of('N')
    }

    /// Number of static correction modes.
    pub fn statics(&self) -> usize {
        self.count_of('S')
    }

    /// Number of Craig–Bampton constraint modes.
    pub fn constraint(&self) -> usize {
        self.count_of('C')
    }

    /// Number of free-free vibration modes.
    pub fn free_vibration(&self) -> usize {
        self.count_of('F')
    }

    /// Number of residual attachment modes.
    pub fn attachment(&self) -> usize {
        self.count_of('A')
    }

    /// Whether the set is a Craig–Bampton or free-interface one, reduced on the unsupported model.
    pub fn uses_interface(&self) -> bool {
        self.constraint() + self.free_vibration() + self.attachment() > 0
    }

    /// Total number of modes asked for (an interface set's orthonormalization drops the rigid
    /// motions its span holds).
    pub fn len(&self) -> usize {
        self.groups.iter().map(|g| g.count()).sum()
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
        let expected = "expected groups of a count and N (vibration) or S (static correction), e.g. 5S, 9N or 4N5S; C (Craig–Bampton constraint modes, e.g. 20N12C); F and A (free-interface: free-free and attachment modes, e.g. 20F12A); or `rigid` for no modes";
        if text.trim().eq_ignore_ascii_case("rigid") {
            return Ok(ModeSet { groups: Vec::new() });
        }
        let mut groups = Vec::new();
        let mut digits = String::new();
        for c in text.trim().chars() {
            match c {
                '0'..='9' => digits.push(c),
                'N' | 'n' | 'S' | 's' | 'C' | 'c' | 'F' | 'f' | 'A' | 'a' => {
                    let count: usize = digits.parse().map_err(|_| error(expected))?;
                    if count == 0 {
                        return Err(error("a group must have at least one mode"));
                    }
                    digits.clear();
                    let group = match c.to_ascii_uppercase() {
                        'N' => ModeGroup::Vibration(count),
                        'S' => ModeGroup::Static(count),
                        'C' => ModeGroup::Constraint(count),
                        'F' => ModeGroup::FreeVibration(count),
                        _ => ModeGroup::Attachment(count),
                    };
                    if groups.iter().any(|g| std::mem::discriminant(g) == std::mem::discriminant(&group)) {
                        return Err(error("each of N, S, C, F and A may appear once"));
                    }
                    groups.push(group);
                }
                _ => return Err(error(expected)),
            }
        }
        if !digits.is_empty() || groups.is_empty() {
            return Err(error(expected));
        }
        let set = ModeSet { groups };
        if set.free_vibration() + set.attachment() > 0 && set.vibration() + set.statics() + set.constraint() > 0 {
            return Err(error("a free-interface set has F and A modes only (e.g. 20F12A); N, S and C belong to the seed's and Craig–Bampton's sets"));
        }
        Ok(set)
    }
}

impl fmt::Display for ModeSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.groups.is_empty() {
            return write!(f, "rigid");
        }
        for g in &self.groups {
            write!(f, "{}{}", g.count(), g.letter())?;
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
        let cb: ModeSet = "20N12C".parse().unwrap();
        assert_eq!((cb.vibration(), cb.constraint(), cb.len(), cb.uses_interface()), (20, 12, 32, true));
        assert_eq!("20f12a".parse::<ModeSet>().unwrap().to_string(), "20F12A");
        assert!(!set.uses_interface());
        for bad in ["", "N", "5", "5X", "0N", "4N4N", "4N 5S", "rigidly", "4N4F", "4F2S", "2C2C"] {
            assert!(bad.parse::<ModeSet>().is_err(), "{bad}");
        }
    }
}
