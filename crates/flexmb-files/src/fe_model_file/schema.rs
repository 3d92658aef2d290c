//! The FE model file as TOML: one struct per table, every value that is checked after parsing kept
//! with its span so that errors can name its line. See `docs/fe-model-file.md` for the meaning of each
//! key.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

use super::node_ref::NodeRef;
use super::value::{DofsInput, NodeLabel};
use crate::model_file::schema::{Name, Number, Vector};

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FeModelFile {
    pub fe_model: Option<Spanned<FeModelSection>>,
    pub matrices: Option<Spanned<MatricesSection>>,
    #[serde(default)]
    pub parameters: BTreeMap<Name, Number>,
    pub modes: Option<Spanned<ModesSection>>,
    #[serde(default)]
    pub material: Vec<Spanned<MaterialSection>>,
    #[serde(default)]
    pub beam_section: Vec<Spanned<BeamSectionSection>>,
    #[serde(default)]
    pub shell_section: Vec<Spanned<ShellSectionSection>>,
    #[serde(default)]
    pub node: Vec<Spanned<NodeSection>>,
    #[serde(default)]
    pub beam: Vec<Spanned<ElementSection>>,
    #[serde(default)]
    pub shell: Vec<Spanned<ElementSection>>,
    #[serde(default)]
    pub beam_line: Vec<Spanned<BeamLineSection>>,
    #[serde(default)]
    pub plate: Vec<Spanned<PlateSection>>,
    #[serde(default)]
    pub mass: Vec<Spanned<MassSection>>,
    #[serde(default)]
    pub support: Vec<Spanned<SupportSection>>,
    #[serde(default)]
    pub static_load: Vec<Spanned<StaticLoadSection>>,
    #[serde(default)]
    pub interface: Vec<Spanned<InterfaceSection>>,
}

/// `[fe_model]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FeModelSection {
    pub name: Option<Name>,
    pub mesh: Option<Name>,
    pub mass: Option<Name>,
    pub rotary_inertia: Option<Spanned<bool>>,
    pub drilling_stiffness: Option<Number>,
}

/// `[matrices]`: stiffness and mass matrices another program exported, with their nodes and row map.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MatricesSection {
    pub format: Name,
    pub stiffness: Name,
    pub mass: Name,
    pub dofs: Option<Name>,
    pub nodes: Name,
}

/// `[modes]`: defaults for `flexmb modes`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ModesSection {
    pub set: Option<Name>,
    pub basis: Option<Name>,
    pub stresses: Option<Spanned<bool>>,
}

/// `[[material]]`: an isotropic linear-elastic material.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MaterialSection {
    pub name: Name,
    #[serde(rename = "E")]
    pub youngs_modulus: Number,
    pub nu: Number,
    pub rho: Number,
}

/// `[[beam_section]]`: explicit properties or a shape with its dimensions.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamSectionSection {
    pub name: Name,
    pub material: Name,
    pub orientation: Vector,
    pub shear_coefficient: Option<Number>,
    #[serde(rename = "A")]
    pub area: Option<Number>,
    #[serde(rename = "Iy")]
    pub iy: Option<Number>,
    #[serde(rename = "Iz")]
    pub iz: Option<Number>,
    #[serde(rename = "J")]
    pub torsion_constant: Option<Number>,
    pub shape: Option<Name>,
    pub width: Option<Number>,
    pub height: Option<Number>,
    pub radius: Option<Number>,
    pub thickness: Option<Number>,
}

/// `[[shell_section]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ShellSectionSection {
    pub name: Name,
    pub material: Name,
    pub thickness: Number,
}

/// `[[node]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct NodeSection {
    pub label: Spanned<NodeLabel>,
    pub position: Vector,
}

/// `[[beam]]` or `[[shell]]`: elements of one section, each a list of node labels.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ElementSection {
    pub section: Name,
    pub nodes: Spanned<Vec<Spanned<Vec<Spanned<NodeLabel>>>>>,
}

/// `[[beam_line]]`: a straight line of equal beam elements.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamLineSection {
    pub name: Option<Name>,
    pub section: Name,
    pub from: Vector,
    pub to: Vector,
    pub elements: Number,
}

/// `[[plate]]`: a flat parallelogram of shell elements.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PlateSection {
    pub name: Option<Name>,
    pub section: Name,
    pub corner: Vector,
    pub edge_a: Vector,
    pub edge_b: Vector,
    pub elements: Vector,
    pub shape: Option<Name>,
}

/// `[[mass]]`: a concentrated mass at a node.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MassSection {
    pub at: Spanned<NodeRef>,
    pub mass: Number,
    pub rotary_inertia: Option<Vector>,
}

/// `[[support]]`: degrees of freedom held at zero in the mode analysis.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SupportSection {
    pub at: Spanned<NodeRef>,
    pub dofs: Spanned<DofsInput>,
}

/// `[[static_load]]`: the unit load of a static correction mode.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct StaticLoadSection {
    pub name: Name,
    pub at: Spanned<NodeRef>,
    pub force: Option<Vector>,
    pub torque: Option<Vector>,
}

/// `[[interface]]`: nodes where joints and force elements act on the body.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct InterfaceSection {
    pub at: Spanned<NodeRef>,
}
