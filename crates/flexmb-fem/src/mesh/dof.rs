//! The six degrees of freedom of a node and sets of them.

use std::fmt;

/// A nodal degree of freedom: translations along and rotations about the body axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Dof {
    /// Translation along x.
    Ux,
    /// Translation along y.
    Uy,
    /// Translation along z.
    Uz,
    /// Rotation about x.
    Rx,
    /// Rotation about y.
    Ry,
    /// Rotation about z.
    Rz,
}

impl Dof {
    /// The six, in the order of a node's degrees of freedom.
    pub const ALL: [Dof; 6] = [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz];

    /// Position 0..6 within a node's degrees of freedom.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The name used in input files: `x y z rx ry rz`.
    pub fn name(self) -> &'static str {
        ["x", "y", "z", "rx", "ry", "rz"][self.index()]
    }

    /// Reads `x y z rx ry rz` (also `ux uy uz`).
    pub fn parse(name: &str) -> Option<Dof> {
        match name {
            "x" | "ux" => Some(Dof::Ux),
            "y" | "uy" => Some(Dof::Uy),
            "z" | "uz" => Some(Dof::Uz),
            "rx" => Some(Dof::Rx),
            "ry" => Some(Dof::Ry),
            "rz" => Some(Dof::Rz),
            _ => None,
        }
    }
}

/// A set of a node's degrees of freedom.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DofSet(u8);

impl DofSet {
    /// No degree of freedom.
    pub const EMPTY: DofSet = DofSet(0);
    /// The three translations.
    pub const TRANSLATIONS: DofSet = DofSet(0b000111);
    /// The three rotations.
    pub const ROTATIONS: DofSet = DofSet(0b111000);
    /// All six.
    pub const ALL: DofSet = DofSet(0b111111);

    /// This set and `dof`.
    pub fn with(self, dof: Dof) -> DofSet {
        DofSet(self.0 | 1 << dof.index())
    }

    /// The dofs in either set.
    pub fn union(self, other: DofSet) -> DofSet {
        DofSet(self.0 | other.0)
    }

    /// Whether `dof` is in the set.
    pub fn contains(self, dof: Dof) -> bool {
        self.0 & (1 << dof.index()) != 0
    }

    /// Whether the set is empty.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The dofs of the set in the order of [`Dof::ALL`].
    pub fn iter(self) -> impl Iterator<Item = Dof> {
        Dof::ALL.into_iter().filter(move |d| self.contains(*d))
    }

    /// The set of the 1-based Abaqus degree-of-freedom range `first..=last` (1–3 translations, 4–6
    /// rotations); `None` when out of range.
    pub fn from_abaqus_range(first: usize, last: usize) -> Option<DofSet> {
        if first < 1 || last > 6 || first > last {
            return None;
        }
        Some((first..=last).fold(DofSet::EMPTY, |s, k| s.with(Dof::ALL[k - 1])))
    }
}

impl FromIterator<Dof> for DofSet {
    fn from_iter<T: IntoIterator<Item = Dof>>(iter: T) -> Self {
        iter.into_iter().fold(DofSet::EMPTY, DofSet::with)
    }
}

impl fmt::Display for DofSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.iter().map(Dof::name).collect();
        write!(f, "{}", names.join(" "))
    }
}
