//! Generators of regular meshes (to be written).

/// The element shape of a generated plate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShellShape {
    /// 4-node quadrilaterals.
    #[default]
    Quadrilateral,
    /// 3-node triangles, two per grid cell.
    Triangle,
}
