//! Typed indices into the collections of a [`Model`](super::Model).

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub usize);
    };
}

id_type!(
    /// A moving body (ground has no id; see [`BodyRef`]).
    BodyId
);
id_type!(
    /// A marker: a frame fixed on a body or on ground.
    MarkerId
);
id_type!(
    /// A joint, primitive or driver: anything that adds constraint equations.
    JointId
);
id_type!(
    /// A force element.
    ForceId
);
id_type!(
    /// A named measure that expressions may read.
    MeasureId
);
id_type!(
    /// A parameter: a value that may be changed between the steps of a simulation.
    ParameterId
);

/// Where a marker is fixed: on ground or on a moving body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BodyRef {
    /// The inertial frame.
    Ground,
    /// A moving body.
    Body(BodyId),
}

impl BodyRef {
    /// The moving body, if any.
    pub fn body(self) -> Option<BodyId> {
        match self {
            BodyRef::Ground => None,
            BodyRef::Body(b) => Some(b),
        }
    }
}
