//! From cards to an [`FeModel`]: the keywords flexmb reads, set bookkeeping, and the final
//! resolution of labels, sets, sections, materials and supports.

use std::collections::{HashMap, HashSet};

use nalgebra::Vector3;

use super::lexer::{parse_label, parse_real, Card, DataLine, Loc};
use super::sections::{self, SectionProperties};
use super::{InpError, InpModel};
use crate::input::Quantity;
use crate::mesh::{
    BeamSection, DofSet, Element, ElementKind, FeModel, Material, Mesh, Node, PointMass,
    DistributingCoupling, RigidCoupling, ShellSection, SolidFormulation, SolidSection, Support,
};

/// The element types flexmb reads, as listed in messages.
pub(super) const SUPPORTED_TYPES: &str =
    "B31, B31H, B33, B33H, S3, S3R, S4, S4R, C3D4, C3D10, C3D6, C3D15, C3D8, C3D8I, C3D20, C3D20R, MASS, ROTARYI, DCOUP3D";

/// Abaqus' default first section direction n₁ of beams, used when `*BEAM SECTION` gives none.
pub const DEFAULT_N1: [f64; 3] = [0.0, 0.0, -1.0];

/// `GENERATE` ranges longer than this are refused (a typo such as `1, 1000000000`).
const MAX_GENERATE: u64 = 50_000_000;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Beam,
    Shell,
    Solid(SolidFormulation),
    Mass,
    RotaryInertia,
    /// `DCOUP3D`: the reference node of a `*DISTRIBUTING COUPLING`.
    DistributingCoupling,
}

impl Kind {
    /// Nodes an element of this kind needs (a beam may have one more, its orientation node).
    fn nodes(self, type_name: &str) -> usize {
        match self {
            Kind::Beam => 2,
            Kind::Shell if type_name.starts_with("S3") => 3,
            Kind::Shell => 4,
            Kind::Solid(formulation) => formulation.node_count(),
            Kind::Mass | Kind::RotaryInertia | Kind::DistributingCoupling => 1,
        }
    }
}

fn element_kind(type_name: &str) -> Result<Kind, String> {
    match type_name {
        "B31" | "B31H" | "B33" | "B33H" => Ok(Kind::Beam),
        "S3" | "S3R" | "S4" | "S4R" => Ok(Kind::Shell),
        "MASS" => Ok(Kind::Mass),
        "ROTARYI" => Ok(Kind::RotaryInertia),
        "DCOUP3D" => Ok(Kind::DistributingCoupling),
        _ => {
            if let Some(formulation) = SolidFormulation::from_abaqus_name(type_name) {
                return Ok(Kind::Solid(formulation));
            }
            let t = type_name;
            let hint = if t.starts_with("B2") || t.starts_with("B3") || t.starts_with("PIPE") {
                " (other beam types are not supported: use B31 or B33)"
            } else if (t.starts_with('S') && !t.starts_with("SPRING") && !t.starts_with("SAX"))
                || t.starts_with("M3D")
            {
                " (other shell types are not supported: use S3, S3R, S4 or S4R)"
            } else if t == "C3D8R" {
                " (C3D8R's hourglass control is not supported: use C3D8I, incompatible modes, or C3D8)"
            } else if t.starts_with('C') {
                " (other continuum elements are not supported: use C3D4, C3D10, C3D6, C3D15, C3D8, C3D8I, C3D20 or C3D20R)"
            } else {
                ""
            };
            Err(format!(
                "unknown element type {type_name}{hint}; flexmb reads {SUPPORTED_TYPES}"
            ))
        }
    }
}

struct RawElement {
    label: u64,
    type_name: String,
    kind: Kind,
    nodes: Vec<u64>,
    loc: Loc,
    /// Index into `Reader::sections` of the beam or shell section.
    section: Option<usize>,
    /// Of `MASS` and `ROTARYI` elements: from `*MASS` and `*ROTARY INERTIA`, with the index of the
    /// section that gave them.
    mass: Option<(f64, usize)>,
    rotary_inertia: Option<(Vector3<f64>, usize)>,
}

struct RawMaterial {
    name: String,
    loc: Loc,
    youngs_modulus: Option<f64>,
    poisson_ratio: Option<f64>,
    density: Option<f64>,
}

/// A named set: members (labels, with the line that put them there) in order of addition.
#[derive(Default)]
struct NamedSet {
    name: String,
    members: Vec<(u64, Loc)>,
}

#[derive(Default)]
struct Sets {
    sets: Vec<NamedSet>,
    index: HashMap<String, usize>,
}

impl Sets {
    fn get(&self, name: &str) -> Option<&NamedSet> {
        self.index.get(&name.to_uppercase()).map(|&i| &self.sets[i])
    }

    fn entry(&mut self, name: &str) -> &mut NamedSet {
        let key = name.to_uppercase();
        let i = *self.index.entry(key).or_insert_with(|| {
            self.sets.push(NamedSet {
                name: name.to_string(),
                members: Vec::new(),
            });
            self.sets.len() - 1
        });
        &mut self.sets[i]
    }
}

enum MaterialRef {
    /// `MATERIAL=name`.
    Named(String),
    /// The moduli given on a `*BEAM GENERAL SECTION`'s third data line, and its `DENSITY=`.
    Own(Material),
}

enum SectionDef {
    Beam {
        props: SectionProperties,
        material: MaterialRef,
        n1: Option<Vector3<f64>>,
    },
    Shell {
        thickness: f64,
        material: String,
    },
    Solid {
        material: String,
    },
    Mass(f64),
    RotaryInertia(Vector3<f64>),
}

struct RawSection {
    keyword: String,
    elset: String,
    loc: Loc,
    def: SectionDef,
}

enum Target {
    Node(u64),
    Set(String),
}

struct RawBoundary {
    target: Target,
    dofs: DofSet,
    loc: Loc,
}

/// A `*DISTRIBUTING COUPLING, ELSET=…`: the element set of its `DCOUP3D` element (the reference
/// node), and the coupled nodes or node sets with their weights.
struct RawDistributingCoupling {
    elset: String,
    targets: Vec<(Target, f64, Loc)>,
    loc: Loc,
}

/// A `*KINEMATIC COUPLING` or `*RIGID BODY`: the reference node, the coupled nodes and sets, and
/// whether the coupled nodes' rotations are tied too.
struct RawCoupling {
    keyword: String,
    reference: u64,
    targets: Vec<(Target, Loc)>,
    rotations: bool,
    loc: Loc,
}

#[derive(Default)]
struct Reader {
    warnings: Vec<String>,
    warned: HashSet<String>,
    nodes: Vec<Node>,
    node_index: HashMap<u64, usize>,
    node_loc: Vec<Loc>,
    elements: Vec<RawElement>,
    element_index: HashMap<u64, usize>,
    nsets: Sets,
    elsets: Sets,
    materials: Vec<RawMaterial>,
    material_index: HashMap<String, usize>,
    current_material: Option<usize>,
    sections: Vec<RawSection>,
    boundaries: Vec<RawBoundary>,
    couplings: Vec<RawCoupling>,
    distributing_couplings: Vec<RawDistributingCoupling>,
    in_step: bool,
}

/// Reads the cards of a deck into a model.
pub(super) fn read(cards: &[Card]) -> Result<InpModel, InpError> {
    let mut r = Reader::default();
    for card in cards {
        r.card(card)?;
    }
    r.finish()
}

fn real(line: &DataLine, index: usize, what: &str, keyword: &str) -> Result<f64, InpError> {
    match line.fields.get(index).map(String::as_str) {
        None | Some("") => Err(line
            .loc
            .error(format!("*{keyword}: missing {what} (field {})", index + 1))),
        Some(f) => parse_real(f).ok_or_else(|| {
            line.loc.error(format!(
                "*{keyword}: expected a number for {what} (field {}), got '{f}'",
                index + 1
            ))
        }),
    }
}

fn optional_real(
    line: &DataLine,
    index: usize,
    what: &str,
    keyword: &str,
    default: f64,
) -> Result<f64, InpError> {
    match line.fields.get(index).map(String::as_str) {
        None | Some("") => Ok(default),
        Some(_) => real(line, index, what, keyword),
    }
}

fn label(line: &DataLine, index: usize, what: &str, keyword: &str) -> Result<u64, InpError> {
    match line.fields.get(index).map(String::as_str) {
        None | Some("") => Err(line
            .loc
            .error(format!("*{keyword}: missing {what} (field {})", index + 1))),
        Some(f) => parse_label(f).ok_or_else(|| {
            line.loc.error(format!(
                "*{keyword}: expected a positive integer for {what} (field {}), got '{f}'",
                index + 1
            ))
        }),
    }
}

/// Field `index` of a data line: a number of `quantity`, within its window.
fn quantity(line: &DataLine, index: usize, what: &str, keyword: &str, quantity: Quantity) -> Result<f64, InpError> {
    let x = real(line, index, what, keyword)?;
    quantity
        .check(x)
        .map_err(|message| line.loc.error(format!("*{keyword}: {what} (field {}): {message}", index + 1)))
}

/// The three components of a direction on a data line (fields 1–3), not zero.
fn direction(line: &DataLine, keyword: &str) -> Result<Vector3<f64>, InpError> {
    let v = Vector3::new(
        real(line, 0, "the direction's x component", keyword)?,
        real(line, 1, "the direction's y component", keyword)?,
        real(line, 2, "the direction's z component", keyword)?,
    );
    if v.norm() == 0.0 {
        return Err(line.loc.error(format!(
            "*{keyword}: the first section direction n1 is zero"
        )));
    }
    Ok(v)
}

impl Reader {
    fn warn(&mut self, loc: &Loc, message: &str) {
        self.warnings.push(loc.message(message));
    }

    /// A warning given once per `key`.
    fn warn_once(&mut self, key: &str, loc: &Loc, message: &str) {
        if self.warned.insert(key.to_string()) {
            self.warn(loc, message);
        }
    }

    /// Warns about parameters of `card` other than `known` (and errors for those in `refused`).
    fn check_params(
        &mut self,
        card: &Card,
        known: &[&str],
        refused: &[(&str, &str)],
    ) -> Result<(), InpError> {
        for p in &card.params {
            if let Some((_, why)) = refused.iter().find(|(k, _)| *k == p.key) {
                return Err(card.error(format!("parameter {} is not supported: {why}", p.key)));
            }
            if !known.contains(&p.key.as_str()) {
                let message = format!("*{}: parameter {} ignored", card.keyword, p.key);
                self.warn_once(
                    &format!("param {} {}", card.keyword, p.key),
                    &card.loc,
                    &message,
                );
            }
        }
        Ok(())
    }

    fn card(&mut self, card: &Card) -> Result<(), InpError> {
        if !is_material_option(&card.keyword) {
            self.current_material = None;
        }
        match card.keyword.as_str() {
            "NODE" => self.node(card),
            "ELEMENT" => self.element(card),
            "NSET" => self.set(card, true),
            "ELSET" => self.set(card, false),
            "MATERIAL" => self.material(card),
            "ELASTIC" => self.elastic(card),
            "DENSITY" => self.density(card),
            "BEAM SECTION" => self.beam_section(card, false),
            "BEAM GENERAL SECTION" => self.beam_section(card, true),
            "SHELL SECTION" => self.shell_section(card),
            "SOLID SECTION" => self.solid_section(card),
            "MASS" => self.mass(card),
            "ROTARY INERTIA" => self.rotary_inertia(card),
            "BOUNDARY" => self.boundary(card),
            "KINEMATIC COUPLING" => self.kinematic_coupling(card),
            "RIGID BODY" => self.rigid_body(card),
            "DISTRIBUTING COUPLING" => self.distributing_coupling(card),
            "COUPLING" | "KINEMATIC" | "DISTRIBUTING" => Err(card.error(format!(
                "*{} is not read by flexmb: write a rigid coupling as *KINEMATIC COUPLING, REF NODE=… (or *RIGID BODY) and a distributing one as *DISTRIBUTING COUPLING, ELSET=… with a DCOUP3D element for the reference node",
                card.keyword
            ))),
            "HEADING" => Ok(()),
            keyword => {
                match keyword {
                    "STEP" => self.in_step = true,
                    "END STEP" => self.in_step = false,
                    _ => {}
                }
                let message = format!("*{keyword} is not read by flexmb: skipped (warned once)");
                self.warn_once(&format!("keyword {keyword}"), &card.loc, &message);
                Ok(())
            }
        }
    }

    fn node(&mut self, card: &Card) -> Result<(), InpError> {
        if let Some(system) = card.param("SYSTEM") {
            if !system.eq_ignore_ascii_case("R") {
                return Err(card.error(format!(
                    "SYSTEM={system} is not supported: give rectangular coordinates"
                )));
            }
        }
        self.check_params(
            card,
            &["NSET", "SYSTEM"],
            &[("INPUT", "put the nodes in the deck or use *INCLUDE")],
        )?;
        let nset = card
            .param("NSET")
            .filter(|s| !s.is_empty())
            .map(str::to_string);
        for line in card.lines() {
            let label = label(line, 0, "the node label", "NODE")?;
            let fields = line.trimmed_fields();
            let mut xyz = [0.0; 3];
            for (k, c) in xyz.iter_mut().enumerate() {
                let what = ["x", "y", "z"][k];
                *c = optional_real(line, k + 1, what, "NODE", 0.0)?;
                Quantity::Length.check(*c).map_err(|message| {
                    line.loc.error(format!("*NODE: node {label}: {what} (field {}): {message}", k + 2))
                })?;
            }
            if fields.len() > 4 {
                self.warn_once(
                    "node extra fields",
                    &line.loc,
                    "*NODE: fields after the z coordinate (normal directions) ignored",
                );
            }
            if let Some(&first) = self.node_index.get(&label) {
                let at = &self.node_loc[first];
                return Err(line.loc.error(format!(
                    "*NODE: node {label} is defined twice (first at {}:{})",
                    at.file, at.line
                )));
            }
            self.node_index.insert(label, self.nodes.len());
            self.nodes.push(Node {
                label,
                position: Vector3::from(xyz),
            });
            self.node_loc.push(line.loc.clone());
            if let Some(name) = &nset {
                self.nsets
                    .entry(name)
                    .members
                    .push((label, line.loc.clone()));
            }
        }
        Ok(())
    }

    fn element(&mut self, card: &Card) -> Result<(), InpError> {
        let type_name = card.required("TYPE")?.to_uppercase();
        let kind = element_kind(&type_name).map_err(|m| card.error(m))?;
        self.check_params(
            card,
            &["TYPE", "ELSET"],
            &[("INPUT", "put the elements in the deck or use *INCLUDE")],
        )?;
        let elset = card
            .param("ELSET")
            .filter(|s| !s.is_empty())
            .map(str::to_string);
        let needed = kind.nodes(&type_name);
        let mut lines = card.lines();
        while let Some(first) = lines.next() {
            // A line ending in a comma continues on the next one while nodes are missing.
            let mut fields: Vec<String> = first.fields.clone();
            while fields.last().is_some_and(String::is_empty) && fields.len() - 2 < needed {
                let Some(next) = lines.next() else { break };
                fields.pop();
                fields.extend(next.fields.iter().cloned());
            }
            let line = DataLine {
                loc: first.loc.clone(),
                fields,
            };
            let label = label(&line, 0, "the element label", "ELEMENT")?;
            let mut nodes = Vec::new();
            for k in 1..line.trimmed_fields().len() {
                nodes.push(self::label(&line, k, "a node label", "ELEMENT")?);
            }
            let extra_ok = kind == Kind::Beam && nodes.len() == needed + 1;
            if nodes.len() != needed && !extra_ok {
                return Err(line.loc.error(format!(
                    "*ELEMENT: element {label} has {} nodes; a {type_name} has {needed}{}",
                    nodes.len(),
                    if kind == Kind::Beam {
                        " (and optionally an orientation node)"
                    } else {
                        ""
                    }
                )));
            }
            if let Some(&first) = self.element_index.get(&label) {
                let at = &self.elements[first].loc;
                return Err(line.loc.error(format!(
                    "*ELEMENT: element {label} is defined twice (first at {}:{})",
                    at.file, at.line
                )));
            }
            self.element_index.insert(label, self.elements.len());
            self.elements.push(RawElement {
                label,
                type_name: type_name.clone(),
                kind,
                nodes,
                loc: line.loc.clone(),
                section: None,
                mass: None,
                rotary_inertia: None,
            });
            if let Some(name) = &elset {
                self.elsets
                    .entry(name)
                    .members
                    .push((label, line.loc.clone()));
            }
        }
        Ok(())
    }

    /// `*NSET` (`nodes`) or `*ELSET`: labels and names of sets defined before, or `GENERATE` ranges.
    fn set(&mut self, card: &Card, nodes: bool) -> Result<(), InpError> {
        let (key, what) = if nodes {
            ("NSET", "node")
        } else {
            ("ELSET", "element")
        };
        let name = card.required(key)?.to_string();
        let generate = card.has_param("GENERATE");
        let refused: &[(&str, &str)] = if nodes {
            &[("ELSET", "list the nodes, or name node sets")]
        } else {
            &[]
        };
        self.check_params(
            card,
            &[key, "GENERATE", "UNSORTED", "INTERNAL", "INSTANCE"],
            refused,
        )?;
        let mut members: Vec<(u64, Loc)> = Vec::new();
        for line in card.lines() {
            let fields = line.trimmed_fields();
            if generate {
                let first = label(line, 0, "the first label", &card.keyword)?;
                let last = label(line, 1, "the last label", &card.keyword)?;
                let step = match fields.get(2) {
                    None => 1,
                    Some(_) => label(line, 2, "the increment", &card.keyword)?,
                };
                if last < first {
                    return Err(line.loc.error(format!(
                        "*{}, GENERATE: the last label {last} is less than the first {first}",
                        card.keyword
                    )));
                }
                if (last - first) / step > MAX_GENERATE {
                    return Err(line.loc.error(format!(
                        "*{}, GENERATE: {first} to {last} is more than {MAX_GENERATE} labels",
                        card.keyword
                    )));
                }
                members.extend(
                    (first..=last)
                        .step_by(step as usize)
                        .map(|l| (l, line.loc.clone())),
                );
                continue;
            }
            for field in fields {
                if field.is_empty() {
                    continue;
                }
                if let Some(l) = parse_label(field) {
                    members.push((l, line.loc.clone()));
                } else if field.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+') {
                    return Err(line.loc.error(format!(
                        "*{}: '{field}' is neither a {what} label nor a set name",
                        card.keyword
                    )));
                } else {
                    let sets = if nodes { &self.nsets } else { &self.elsets };
                    let Some(set) = sets.get(field) else {
                        return Err(line.loc.error(format!(
                            "*{}: unknown {what} set {field} (sets must be defined before they are used)",
                            card.keyword
                        )));
                    };
                    members.extend(set.members.iter().cloned());
                }
            }
        }
        let sets = if nodes {
            &mut self.nsets
        } else {
            &mut self.elsets
        };
        sets.entry(&name).members.extend(members);
        Ok(())
    }

    fn material(&mut self, card: &Card) -> Result<(), InpError> {
        let name = card.required("NAME")?.to_string();
        self.check_params(card, &["NAME"], &[])?;
        let key = name.to_uppercase();
        if let Some(&i) = self.material_index.get(&key) {
            let at = &self.materials[i].loc;
            return Err(card.error(format!(
                "material {name} is defined twice (first at {}:{})",
                at.file, at.line
            )));
        }
        self.material_index.insert(key, self.materials.len());
        self.current_material = Some(self.materials.len());
        self.materials.push(RawMaterial {
            name,
            loc: card.loc.clone(),
            youngs_modulus: None,
            poisson_ratio: None,
            density: None,
        });
        Ok(())
    }

    fn material_data<'c>(&mut self, card: &'c Card) -> Result<(usize, &'c DataLine), InpError> {
        let Some(m) = self.current_material else {
            return Err(card.error("must follow a *MATERIAL"));
        };
        let mut lines = card.lines();
        let Some(line) = lines.next() else {
            return Err(card.error("missing data line"));
        };
        if lines.next().is_some() {
            let message = format!(
                "*{}: temperature-dependent data: the first line is used",
                card.keyword
            );
            self.warn(&card.loc, &message);
        }
        Ok((m, line))
    }

    fn elastic(&mut self, card: &Card) -> Result<(), InpError> {
        if let Some(t) = card.param("TYPE") {
            if !t.eq_ignore_ascii_case("ISOTROPIC") && !t.eq_ignore_ascii_case("ISO") {
                return Err(card.error(format!(
                    "TYPE={t} is not supported: flexmb's materials are isotropic"
                )));
            }
        }
        self.check_params(card, &["TYPE"], &[])?;
        let (m, line) = self.material_data(card)?;
        let e = quantity(line, 0, "Young's modulus E", "ELASTIC", Quantity::Modulus)?;
        let nu = real(line, 1, "Poisson's ratio", "ELASTIC")?;
        if e <= 0.0 {
            return Err(line.loc.error(format!(
                "*ELASTIC: Young's modulus must be positive, got {e}"
            )));
        }
        if nu <= -1.0 || nu >= 0.5 {
            return Err(line.loc.error(format!(
                "*ELASTIC: Poisson's ratio must lie in (-1, 0.5), got {nu}"
            )));
        }
        self.materials[m].youngs_modulus = Some(e);
        self.materials[m].poisson_ratio = Some(nu);
        Ok(())
    }

    fn density(&mut self, card: &Card) -> Result<(), InpError> {
        self.check_params(card, &[], &[])?;
        let (m, line) = self.material_data(card)?;
        let rho = quantity(line, 0, "the density", "DENSITY", Quantity::Density)?;
        if rho < 0.0 {
            return Err(line.loc.error(format!(
                "*DENSITY: the density must not be negative, got {rho}"
            )));
        }
        self.materials[m].density = Some(rho);
        Ok(())
    }

    fn beam_section(&mut self, card: &Card, general: bool) -> Result<(), InpError> {
        let kw = card.keyword.as_str();
        let elset = card.required("ELSET")?.to_string();
        let default_section = if general { "GENERAL" } else { "" };
        let section = card
            .param("SECTION")
            .unwrap_or(default_section)
            .to_uppercase();
        let known: &[&str] = if general {
            &["ELSET", "SECTION", "DENSITY", "POISSON", "LUMPED"]
        } else {
            &[
                "ELSET",
                "SECTION",
                "MATERIAL",
                "POISSON",
                "LUMPED",
                "TEMPERATURE",
            ]
        };
        let refused = [
            (
                "ORIENTATION",
                "give the first section direction n1 on the second data line",
            ),
            ("OFFSET1", "flexmb's beam axis is the section's centroid"),
            ("OFFSET2", "flexmb's beam axis is the section's centroid"),
            ("DEPENDENCIES", "flexmb's sections are linear and constant"),
            ("NODAL THICKNESS", "give the dimensions on the data line"),
        ];
        self.check_params(card, known, &refused)?;
        // Positional data lines: blank lines count (a blank second line is the default n1).
        let data = &card.data;
        let Some(dims) = data.first().filter(|d| !d.is_blank()) else {
            return Err(card.error("missing the first data line (section dimensions)"));
        };
        let length = |index, what: &str| quantity(dims, index, what, kw, Quantity::Length);
        let (props, offset) = match section.as_str() {
            "RECT" => (sections::rect(length(0, "a")?, length(1, "b")?).map_err(|e| e.to_string()), None),
            "CIRC" => (sections::circ(length(0, "r")?).map_err(|e| e.to_string()), None),
            "PIPE" => (sections::pipe(length(0, "r")?, length(1, "t")?).map_err(|e| e.to_string()), None),
            "BOX" => {
                let mut t = [0.0; 4];
                for (k, tk) in t.iter_mut().enumerate() {
                    *tk = length(k + 2, &format!("t{}", k + 1))?;
                }
                match sections::boxed(length(0, "a")?, length(1, "b")?, t) {
                    Ok((p, offset)) => (Ok(p), Some(offset)),
                    Err(e) => (Err(e.to_string()), None),
                }
            }
            "GENERAL" if general => {
                let i12 = real(dims, 2, "I12", kw)?;
                let second_moment = |index, what| quantity(dims, index, what, kw, Quantity::SecondMoment);
                let (i11, i22) = (second_moment(1, "I11")?, second_moment(3, "I22")?);
                if i12.abs() > 1e-9 * i11.abs().max(i22.abs()) {
                    return Err(dims.loc.error(format!(
                        "*{kw}: I12 = {i12} is not zero: flexmb's beams need principal axes (rotate n1 to a principal axis and give I12 = 0)"
                    )));
                }
                let props = SectionProperties {
                    area: quantity(dims, 0, "A", kw, Quantity::Area)?,
                    iy: i11,
                    iz: i22,
                    torsion_constant: second_moment(4, "J")?,
                    outline: crate::mesh::SectionOutline::Equivalent,
                };
                let bad = [
                    ("A", props.area),
                    ("I11", props.iy),
                    ("I22", props.iz),
                    ("J", props.torsion_constant),
                ]
                .into_iter()
                .find(|(_, v)| *v <= 0.0)
                .map(|(n, v)| format!("{n} must be positive, got {v}"));
                (bad.map_or(Ok(props), Err), None)
            }
            "" => return Err(card.error("missing parameter SECTION=…")),
            other => {
                let list = if general {
                    "GENERAL, RECT, CIRC, PIPE, BOX"
                } else {
                    "RECT, CIRC, PIPE, BOX"
                };
                return Err(card.error(format!(
                    "SECTION={other} is not supported; flexmb reads {list}"
                )));
            }
        };
        let props = props.map_err(|m| dims.loc.error(format!("*{kw}, SECTION={section}: {m}")))?;
        if let Some([c1, c2]) = offset {
            if c1 != 0.0 || c2 != 0.0 {
                let message = format!(
                    "*{kw}, SECTION=BOX: unequal opposite walls move the centroid by ({c1:.3e}, {c2:.3e}) from the box centre; flexmb puts the beam axis at the centroid"
                );
                self.warn(&dims.loc, &message);
            }
        }
        let n1 = match data.get(1) {
            Some(line) if !line.is_blank() => Some(direction(line, kw)?),
            _ => None,
        };
        let material = if general {
            let Some(moduli) = data.get(2).filter(|d| !d.is_blank()) else {
                return Err(card.error("missing the third data line (E, G) of the general section"));
            };
            let e = quantity(moduli, 0, "Young's modulus E", kw, Quantity::Modulus)?;
            let g = quantity(moduli, 1, "the shear modulus G", kw, Quantity::Modulus)?;
            if e <= 0.0 || g <= 0.0 {
                return Err(moduli.loc.error(format!(
                    "*{kw}: E and G must be positive, got E = {e}, G = {g}"
                )));
            }
            let nu = e / (2.0 * g) - 1.0;
            if nu <= -1.0 || nu >= 0.5 {
                return Err(moduli.loc.error(format!(
                    "*{kw}: E = {e} and G = {g} give Poisson's ratio {nu}, outside (-1, 0.5)"
                )));
            }
            let density = match card.param("DENSITY") {
                Some(d) => {
                    let density = parse_real(d).filter(|d| *d >= 0.0).ok_or_else(|| {
                        card.error(format!("DENSITY={d} is not a non-negative number"))
                    })?;
                    Quantity::Density.check(density).map_err(|m| card.error(format!("DENSITY={d}: {m}")))?
                }
                None => {
                    return Err(card
                        .error("missing parameter DENSITY=… (flexmb needs the mass of the beams)"))
                }
            };
            MaterialRef::Own(Material {
                name: format!("{elset} (*BEAM GENERAL SECTION)"),
                youngs_modulus: e,
                poisson_ratio: nu,
                density,
            })
        } else {
            MaterialRef::Named(card.required("MATERIAL")?.to_string())
        };
        self.sections.push(RawSection {
            keyword: card.keyword.clone(),
            elset,
            loc: card.loc.clone(),
            def: SectionDef::Beam {
                props,
                material,
                n1,
            },
        });
        Ok(())
    }

    fn shell_section(&mut self, card: &Card) -> Result<(), InpError> {
        let elset = card.required("ELSET")?.to_string();
        let material = card.required("MATERIAL")?.to_string();
        if let Some(offset) = card.param("OFFSET") {
            let mid = offset.eq_ignore_ascii_case("MIDSURFACE") || parse_real(offset) == Some(0.0);
            if !mid {
                return Err(card.error(format!("OFFSET={offset} is not supported: flexmb's shell reference surface is the mid-surface")));
            }
        }
        let refused = [
            ("COMPOSITE", "flexmb's shells are homogeneous"),
            ("NODAL THICKNESS", "give the thickness on the data line"),
        ];
        self.check_params(
            card,
            &[
                "ELSET",
                "MATERIAL",
                "OFFSET",
                "ORIENTATION",
                "SECTION INTEGRATION",
                "POISSON",
            ],
            &refused,
        )?;
        let Some(line) = card.lines().next() else {
            return Err(card.error("missing the data line (thickness)"));
        };
        let thickness = quantity(line, 0, "the thickness", "SHELL SECTION", Quantity::Length)?;
        if thickness <= 0.0 {
            return Err(line.loc.error(format!(
                "*SHELL SECTION: the thickness must be positive, got {thickness}"
            )));
        }
        self.sections.push(RawSection {
            keyword: card.keyword.clone(),
            elset,
            loc: card.loc.clone(),
            def: SectionDef::Shell {
                thickness,
                material,
            },
        });
        Ok(())
    }

    fn solid_section(&mut self, card: &Card) -> Result<(), InpError> {
        let elset = card.required("ELSET")?.to_string();
        let material = card.required("MATERIAL")?.to_string();
        self.check_params(
            card,
            &["ELSET", "MATERIAL", "ORIENTATION", "CONTROLS"],
            &[("COMPOSITE", "flexmb's solids are homogeneous")],
        )?;
        if card.params.iter().any(|p| p.key == "ORIENTATION") {
            let message = "*SOLID SECTION: ORIENTATION ignored (flexmb's materials are isotropic)";
            self.warn_once("solid orientation", &card.loc, message);
        }
        self.sections.push(RawSection {
            keyword: card.keyword.clone(),
            elset,
            loc: card.loc.clone(),
            def: SectionDef::Solid { material },
        });
        Ok(())
    }

    /// `*KINEMATIC COUPLING, REF NODE=r` with data lines `node or node set, first dof, last dof`:
    /// a rigid coupling of all three translations (1–3), and the rotations too with 1–6.
    fn kinematic_coupling(&mut self, card: &Card) -> Result<(), InpError> {
        let reference = parse_label(card.required("REF NODE")?)
            .ok_or_else(|| card.error("REF NODE must be a node label"))?;
        self.check_params(card, &["REF NODE", "ORIENTATION"], &[("SURFACE", "name the coupled nodes on the data lines (a node set)")])?;
        let mut targets = Vec::new();
        let mut rotations = false;
        for line in card.lines() {
            let target = self.target(line, "KINEMATIC COUPLING")?;
            let first = label(line, 1, "the first degree of freedom", "KINEMATIC COUPLING")?;
            let last = match line.fields.get(2).map(String::as_str) {
                None | Some("") => first,
                Some(_) => label(line, 2, "the last degree of freedom", "KINEMATIC COUPLING")?,
            };
            if first != 1 || !(3..=6).contains(&last) {
                return Err(line.loc.error(format!(
                    "*KINEMATIC COUPLING: degrees of freedom {first} to {last}: flexmb's coupling is rigid in all three translations (give 1, 3) and optionally the rotations (1, 6)"
                )));
            }
            rotations |= last == 6;
            targets.push((target, line.loc.clone()));
        }
        if targets.is_empty() {
            return Err(card.error("missing data lines (the coupled nodes or node set, first and last dof)"));
        }
        self.couplings.push(RawCoupling { keyword: card.keyword.clone(), reference, targets, rotations, loc: card.loc.clone() });
        Ok(())
    }

    /// `*DISTRIBUTING COUPLING, ELSET=e` with data lines `node or node set, weight` (CalculiX's and
    /// Abaqus' form): the element set holds one `DCOUP3D` element, whose node is the reference node.
    fn distributing_coupling(&mut self, card: &Card) -> Result<(), InpError> {
        let elset = card.required("ELSET")?.to_string();
        self.check_params(card, &["ELSET"], &[])?;
        let mut targets = Vec::new();
        for line in card.lines() {
            let target = self.target(line, "DISTRIBUTING COUPLING")?;
            let weight = match line.fields.get(1).map(String::as_str) {
                None | Some("") => 1.0,
                Some(_) => real(line, 1, "the weight", "DISTRIBUTING COUPLING")?,
            };
            if !(weight.is_finite() && weight > 0.0) {
                return Err(line.loc.error(format!("*DISTRIBUTING COUPLING: the weight must be positive, got {weight}")));
            }
            targets.push((target, weight, line.loc.clone()));
        }
        if targets.is_empty() {
            return Err(card.error("missing data lines (the coupled nodes or node sets and their weights)"));
        }
        self.distributing_couplings.push(RawDistributingCoupling { elset, targets, loc: card.loc.clone() });
        Ok(())
    }

    /// `*RIGID BODY, NSET=set, REF NODE=r`: the nodes of the set tied rigidly to the reference node.
    fn rigid_body(&mut self, card: &Card) -> Result<(), InpError> {
        let reference = parse_label(card.required("REF NODE")?)
            .ok_or_else(|| card.error("REF NODE must be a node label"))?;
        let set = card.required("NSET")?.to_string();
        self.check_params(card, &["NSET", "REF NODE", "ROT NODE"], &[("ELSET", "give the tied nodes as a node set (NSET=)")])?;
        self.couplings.push(RawCoupling {
            keyword: card.keyword.clone(),
            reference,
            targets: vec![(Target::Set(set), card.loc.clone())],
            rotations: true,
            loc: card.loc.clone(),
        });
        Ok(())
    }

    /// Field 1 of a data line: a node label or a node set name.
    fn target(&self, line: &DataLine, keyword: &str) -> Result<Target, InpError> {
        let Some(field) = line.fields.first().filter(|f| !f.is_empty()) else {
            return Err(line.loc.error(format!("*{keyword}: missing the node or node set (field 1)")));
        };
        match parse_label(field) {
            Some(l) => Ok(Target::Node(l)),
            None if field.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+') => {
                Err(line.loc.error(format!("*{keyword}: '{field}' is neither a node label nor a node set name")))
            }
            None => Ok(Target::Set(field.clone())),
        }
    }

    fn mass(&mut self, card: &Card) -> Result<(), InpError> {
        let elset = card.required("ELSET")?.to_string();
        self.check_params(card, &["ELSET", "ALPHA", "TYPE"], &[])?;
        let Some(line) = card.lines().next() else {
            return Err(card.error("missing the data line (mass)"));
        };
        let mass = quantity(line, 0, "the mass", "MASS", Quantity::Mass)?;
        if mass < 0.0 {
            return Err(line
                .loc
                .error(format!("*MASS: the mass must not be negative, got {mass}")));
        }
        self.sections.push(RawSection {
            keyword: card.keyword.clone(),
            elset,
            loc: card.loc.clone(),
            def: SectionDef::Mass(mass),
        });
        Ok(())
    }

    fn rotary_inertia(&mut self, card: &Card) -> Result<(), InpError> {
        let elset = card.required("ELSET")?.to_string();
        self.check_params(
            card,
            &["ELSET", "ALPHA"],
            &[("ORIENTATION", "give the inertia in global axes")],
        )?;
        let Some(line) = card.lines().next() else {
            return Err(card.error("missing the data line (I11, I22, I33)"));
        };
        let kw = "ROTARY INERTIA";
        let diagonal = Vector3::new(
            quantity(line, 0, "I11", kw, Quantity::Inertia)?,
            quantity(line, 1, "I22", kw, Quantity::Inertia)?,
            quantity(line, 2, "I33", kw, Quantity::Inertia)?,
        );
        for (k, name) in ["I12", "I13", "I23"].iter().enumerate() {
            let v = optional_real(line, 3 + k, name, kw, 0.0)?;
            if v != 0.0 {
                return Err(line.loc.error(format!("*{kw}: {name} = {v} is not zero: flexmb's point inertias are diagonal in global axes")));
            }
        }
        if diagonal.iter().any(|&v| v < 0.0) {
            return Err(line.loc.error(format!(
                "*{kw}: the moments of inertia must not be negative"
            )));
        }
        self.sections.push(RawSection {
            keyword: card.keyword.clone(),
            elset,
            loc: card.loc.clone(),
            def: SectionDef::RotaryInertia(diagonal),
        });
        Ok(())
    }

    fn boundary(&mut self, card: &Card) -> Result<(), InpError> {
        if let Some(t) = card.param("TYPE") {
            if !t.eq_ignore_ascii_case("DISPLACEMENT") {
                let message =
                    format!("*BOUNDARY, TYPE={t} skipped (flexmb reads fixed displacements)");
                self.warn(&card.loc, &message);
                return Ok(());
            }
        }
        self.check_params(
            card,
            &["TYPE", "OP", "AMPLITUDE", "FIXED", "USER", "LOAD CASE"],
            &[],
        )?;
        for line in card.lines() {
            let fields = line.trimmed_fields();
            let target = &fields[0];
            if target.is_empty() {
                return Err(line
                    .loc
                    .error("*BOUNDARY: missing the node or node set (field 1)"));
            }
            let target = match parse_label(target) {
                Some(l) => Target::Node(l),
                None if target
                    .starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+') =>
                {
                    return Err(line.loc.error(format!(
                        "*BOUNDARY: '{target}' is neither a node label nor a node set name"
                    )));
                }
                None => Target::Set(target.clone()),
            };
            let Some(first) = fields.get(1) else {
                return Err(line
                    .loc
                    .error("*BOUNDARY: missing the first degree of freedom (field 2)"));
            };
            let dofs = if let Some(set) = named_boundary(first) {
                set
            } else {
                let first = label(line, 1, "the first degree of freedom", "BOUNDARY").map_err(|_| {
                    line.loc.error(format!(
                        "*BOUNDARY: expected a degree of freedom 1–6 or ENCASTRE, PINNED, XSYMM, YSYMM, ZSYMM, XASYMM, YASYMM, ZASYMM (field 2), got '{first}'"
                    ))
                })?;
                let last = match fields.get(2).map(String::as_str) {
                    None | Some("") => first,
                    Some(_) => label(line, 2, "the last degree of freedom", "BOUNDARY")?,
                };
                let value = optional_real(line, 3, "the prescribed value", "BOUNDARY", 0.0)?;
                if last < first {
                    return Err(line.loc.error(format!("*BOUNDARY: the last degree of freedom {last} is less than the first {first}")));
                }
                if value != 0.0 {
                    let message = format!("*BOUNDARY: prescribed value {value} treated as zero (the degrees of freedom are held fixed)");
                    self.warn(&line.loc, &message);
                }
                if last > 6 {
                    let message = format!(
                        "*BOUNDARY: degrees of freedom above 6 ({}..{last}) ignored",
                        first.max(7)
                    );
                    self.warn(&line.loc, &message);
                    if first > 6 {
                        continue;
                    }
                }
                DofSet::from_abaqus_range(first as usize, last.min(6) as usize)
                    .unwrap_or(DofSet::EMPTY)
            };
            self.boundaries.push(RawBoundary {
                target,
                dofs,
                loc: line.loc.clone(),
            });
        }
        Ok(())
    }

    // ---- Resolution -------------------------------------------------------------------------

    fn node_of(&self, label: u64, loc: &Loc, what: &str) -> Result<usize, InpError> {
        self.node_index
            .get(&label)
            .copied()
            .ok_or_else(|| loc.error(format!("{what}: node {label} is not defined")))
    }

    fn finish(mut self) -> Result<InpModel, InpError> {
        let mut mesh = Mesh {
            nodes: std::mem::take(&mut self.nodes),
            ..Mesh::default()
        };

        // Node sets, in order, without repeats.
        for set in &self.nsets.sets {
            let mut seen = HashSet::new();
            let mut members = Vec::new();
            for (label, loc) in &set.members {
                let n = self.node_of(*label, loc, &format!("node set {}", set.name))?;
                if seen.insert(n) {
                    members.push(n);
                }
            }
            mesh.node_sets.insert(set.name.clone(), members);
        }

        // Materials: the complete ones, in order; the others only matter if a section uses them.
        let mut material_of: Vec<Option<usize>> = Vec::new();
        for m in &self.materials {
            match (m.youngs_modulus, m.poisson_ratio, m.density) {
                (Some(e), Some(nu), Some(rho)) => {
                    material_of.push(Some(mesh.materials.len()));
                    mesh.materials.push(Material {
                        name: m.name.clone(),
                        youngs_modulus: e,
                        poisson_ratio: nu,
                        density: rho,
                    });
                }
                _ => material_of.push(None),
            }
        }

        // Sections: assign them to the elements of their sets.
        let mut beam_section_of = vec![usize::MAX; self.sections.len()];
        let mut shell_section_of = vec![usize::MAX; self.sections.len()];
        let mut solid_section_of = vec![usize::MAX; self.sections.len()];
        for (s, section) in self.sections.iter().enumerate() {
            let kw = &section.keyword;
            let Some(set) = self.elsets.get(&section.elset) else {
                return Err(section.loc.error(format!(
                    "*{kw}: element set {} is not defined",
                    section.elset
                )));
            };
            for (label, loc) in &set.members {
                let Some(&e) = self.element_index.get(label) else {
                    return Err(loc.error(format!("element {label} of element set {} (used by *{kw} at line {}) is not defined", set.name, section.loc.line)));
                };
                let element = &mut self.elements[e];
                let fits = matches!(
                    (&section.def, element.kind),
                    (SectionDef::Beam { .. }, Kind::Beam)
                        | (SectionDef::Shell { .. }, Kind::Shell)
                        | (SectionDef::Solid { .. }, Kind::Solid(_))
                        | (SectionDef::Mass(_), Kind::Mass)
                        | (SectionDef::Mass(_), Kind::RotaryInertia)
                        | (SectionDef::RotaryInertia(_), Kind::RotaryInertia)
                        | (SectionDef::RotaryInertia(_), Kind::Mass)
                );
                if !fits {
                    return Err(section.loc.error(format!(
                        "*{kw}: element set {} contains element {label} of type {}",
                        set.name, element.type_name
                    )));
                }
                let already = match section.def {
                    SectionDef::Beam { .. } | SectionDef::Shell { .. } | SectionDef::Solid { .. } => {
                        element.section.replace(s)
                    }
                    SectionDef::Mass(m) => element.mass.replace((m, s)).map(|(_, o)| o),
                    SectionDef::RotaryInertia(j) => {
                        element.rotary_inertia.replace((j, s)).map(|(_, o)| o)
                    }
                };
                if let Some(other) = already {
                    let o = &self.sections[other];
                    return Err(section.loc.error(format!(
                        "*{kw}: element {label} already has one (*{} at {}:{})",
                        o.keyword, o.loc.file, o.loc.line
                    )));
                }
            }
            let material = |name: &str| -> Result<usize, InpError> {
                let Some(&m) = self.material_index.get(&name.to_uppercase()) else {
                    return Err(section
                        .loc
                        .error(format!("*{kw}: material {name} is not defined")));
                };
                let raw = &self.materials[m];
                let missing: Vec<&str> = [
                    (raw.youngs_modulus.is_none(), "*ELASTIC"),
                    (raw.density.is_none(), "*DENSITY"),
                ]
                .into_iter()
                .filter_map(|(missing, what)| missing.then_some(what))
                .collect();
                match material_of[m] {
                    Some(index) => Ok(index),
                    None => Err(section.loc.error(format!(
                        "*{kw}: material {name} (line {}) has no {}",
                        raw.loc.line,
                        missing.join(" and no ")
                    ))),
                }
            };
            match &section.def {
                SectionDef::Beam {
                    props,
                    material: m,
                    n1,
                } => {
                    let material = match m {
                        MaterialRef::Named(name) => material(name)?,
                        MaterialRef::Own(own) => {
                            mesh.materials.push(own.clone());
                            mesh.materials.len() - 1
                        }
                    };
                    beam_section_of[s] = mesh.beam_sections.len();
                    mesh.beam_sections.push(BeamSection {
                        name: section.elset.clone(),
                        material,
                        area: props.area,
                        iy: props.iy,
                        iz: props.iz,
                        torsion_constant: props.torsion_constant,
                        orientation: n1.unwrap_or(Vector3::from(DEFAULT_N1)),
                        shear_coefficient: None,
                        outline: props.outline,
                    });
                }
                SectionDef::Shell {
                    thickness,
                    material: name,
                } => {
                    let material = material(name)?;
                    shell_section_of[s] = mesh.shell_sections.len();
                    mesh.shell_sections.push(ShellSection {
                        name: section.elset.clone(),
                        material,
                        thickness: *thickness,
                    });
                }
                SectionDef::Solid { material: name } => {
                    let material = material(name)?;
                    solid_section_of[s] = mesh.solid_sections.len();
                    mesh.solid_sections.push(SolidSection { name: section.elset.clone(), material });
                }
                SectionDef::Mass(_) | SectionDef::RotaryInertia(_) => {}
            }
        }
        for (m, raw) in self.materials.iter().enumerate() {
            if material_of[m].is_none() {
                let message = format!(
                    "material {} has no *ELASTIC or no *DENSITY; unused, left out",
                    raw.name
                );
                self.warnings.push(raw.loc.message(&message));
            }
        }

        // Elements, in order; point masses.
        let mut variants: HashMap<(usize, [u64; 3]), usize> = HashMap::new();
        let mut degenerate = 0;
        for element in &self.elements {
            let what = format!("element {}", element.label);
            let nodes: Vec<usize> = element
                .nodes
                .iter()
                .map(|&l| self.node_of(l, &element.loc, &what))
                .collect::<Result<_, _>>()?;
            if element.kind == Kind::DistributingCoupling {
                // The reference node of a distributing coupling, read below.
                continue;
            }
            let point = matches!(element.kind, Kind::Mass | Kind::RotaryInertia);
            let section = if point {
                element
                    .mass
                    .map(|(_, o)| o)
                    .or(element.rotary_inertia.map(|(_, o)| o))
            } else {
                element.section
            };
            let Some(s) = section else {
                let hint = match element.kind {
                    Kind::Beam => "*BEAM SECTION or *BEAM GENERAL SECTION",
                    Kind::Shell => "*SHELL SECTION",
                    Kind::Solid(_) => "*SOLID SECTION",
                    Kind::Mass | Kind::RotaryInertia => "*MASS or *ROTARY INERTIA",
                    Kind::DistributingCoupling => "*DISTRIBUTING COUPLING",
                };
                return Err(element.loc.error(format!(
                    "element {} ({}) has no section: no {hint} names an element set that contains it",
                    element.label, element.type_name
                )));
            };
            match element.kind {
                Kind::Beam => {
                    let base = beam_section_of[s];
                    let p0 = mesh.nodes[nodes[0]].position;
                    let axis = mesh.nodes[nodes[1]].position - p0;
                    let (n1, section) = if let Some(&orientation_node) = nodes.get(2) {
                        let n1 = mesh.nodes[orientation_node].position - p0;
                        let key = (base, [n1.x.to_bits(), n1.y.to_bits(), n1.z.to_bits()]);
                        let index = *variants.entry(key).or_insert_with(|| {
                            let mut variant = mesh.beam_sections[base].clone();
                            variant.name =
                                format!("{} (n1 from element {})", variant.name, element.label);
                            variant.orientation = n1;
                            mesh.beam_sections.push(variant);
                            mesh.beam_sections.len() - 1
                        });
                        (n1, index)
                    } else {
                        (mesh.beam_sections[base].orientation, base)
                    };
                    if n1.norm() == 0.0 {
                        return Err(element.loc.error(format!(
                            "element {}: its orientation node coincides with its first node",
                            element.label
                        )));
                    }
                    if axis.norm() == 0.0 {
                        return Err(element
                            .loc
                            .error(format!("element {}: its two nodes coincide", element.label)));
                    }
                    if axis.normalize().cross(&n1.normalize()).norm() < 1e-6 {
                        let sec = &self.sections[s];
                        let source = if nodes.len() > 2 {
                            "given by its orientation node".to_string()
                        } else if matches!(sec.def, SectionDef::Beam { n1: Some(_), .. }) {
                            format!("given on *{} at line {}", sec.keyword, sec.loc.line)
                        } else {
                            format!(
                                "the default (0, 0, -1): give n1 on the second data line of *{} at line {}",
                                sec.keyword, sec.loc.line
                            )
                        };
                        return Err(element.loc.error(format!(
                            "element {} lies along its section's first direction n1 ({source})",
                            element.label
                        )));
                    }
                    mesh.elements.push(Element {
                        label: element.label,
                        kind: ElementKind::Beam { section },
                        nodes: nodes[..2].to_vec(),
                    });
                }
                Kind::Shell => {
                    // A quadrilateral with a repeated node is a triangle.
                    let mut unique = nodes.clone();
                    unique.dedup();
                    if unique.len() > 1 && unique.first() == unique.last() {
                        unique.pop();
                    }
                    let nodes = if unique.len() == 3 && nodes.len() == 4 {
                        degenerate += 1;
                        unique
                    } else if unique.len() != nodes.len()
                        || HashSet::<&usize>::from_iter(&unique).len() != unique.len()
                    {
                        return Err(element
                            .loc
                            .error(format!("element {}: repeated nodes", element.label)));
                    } else {
                        nodes
                    };
                    mesh.elements.push(Element {
                        label: element.label,
                        kind: ElementKind::Shell {
                            section: shell_section_of[s],
                        },
                        nodes,
                    });
                }
                Kind::Solid(formulation) => {
                    if HashSet::<&usize>::from_iter(&nodes).len() != nodes.len() {
                        return Err(element.loc.error(format!(
                            "element {} ({}): repeated nodes (collapsed solids are not supported: use the element type of that shape)",
                            element.label, element.type_name
                        )));
                    }
                    mesh.elements.push(Element {
                        label: element.label,
                        kind: ElementKind::Solid { section: solid_section_of[s], formulation },
                        nodes,
                    });
                }
                Kind::DistributingCoupling => {}
                Kind::Mass | Kind::RotaryInertia => mesh.point_masses.push(PointMass {
                    node: nodes[0],
                    mass: element.mass.map_or(0.0, |(m, _)| m),
                    rotary_inertia: element.rotary_inertia.map_or(Vector3::zeros(), |(j, _)| j),
                }),
            }
        }
        if degenerate > 0 {
            self.warnings.push(format!(
                "{degenerate} quadrilateral shell(s) with a repeated node read as triangles"
            ));
        }
        if mesh.elements.is_empty() && mesh.point_masses.is_empty() {
            self.warnings
                .push("the deck defines no elements".to_string());
        }

        // Rigid couplings.
        for c in &self.couplings {
            let reference = self.node_of(c.reference, &c.loc, &format!("*{} REF NODE", c.keyword))?;
            let mut nodes: Vec<usize> = Vec::new();
            for (target, loc) in &c.targets {
                match target {
                    Target::Node(label) => nodes.push(self.node_of(*label, loc, &format!("*{}", c.keyword))?),
                    Target::Set(name) => match mesh.node_sets.iter().find(|(k, _)| k.eq_ignore_ascii_case(name)) {
                        Some((_, members)) => nodes.extend(members.iter().copied()),
                        None => return Err(loc.error(format!("*{}: node set {name} is not defined", c.keyword))),
                    },
                }
            }
            // The reference node may be in its own set; a node named twice is coupled once.
            let mut seen = HashSet::from([reference]);
            nodes.retain(|&n| seen.insert(n));
            mesh.rigid_couplings.push(RigidCoupling { reference, nodes, rotations: c.rotations });
        }

        // Distributing couplings.
        for c in &self.distributing_couplings {
            let kw = "*DISTRIBUTING COUPLING";
            let Some(set) = self.elsets.get(&c.elset) else {
                return Err(c.loc.error(format!("{kw}: element set {} is not defined", c.elset)));
            };
            let members: Vec<&RawElement> = set.members.iter().filter_map(|(label, _)| self.element_index.get(label).map(|&e| &self.elements[e])).collect();
            let [element] = members.as_slice() else {
                return Err(c.loc.error(format!("{kw}: element set {} must hold exactly one DCOUP3D element (the reference node), it holds {}", c.elset, members.len())));
            };
            if element.kind != Kind::DistributingCoupling {
                return Err(c.loc.error(format!("{kw}: element {} of set {} is a {}, not a DCOUP3D", element.label, c.elset, element.type_name)));
            }
            let reference = self.node_of(element.nodes[0], &element.loc, &format!("element {}", element.label))?;
            let (mut nodes, mut weights): (Vec<usize>, Vec<f64>) = (Vec::new(), Vec::new());
            for (target, weight, loc) in &c.targets {
                let members = match target {
                    Target::Node(label) => vec![self.node_of(*label, loc, kw)?],
                    Target::Set(name) => match mesh.node_sets.iter().find(|(k, _)| k.eq_ignore_ascii_case(name)) {
                        Some((_, members)) => members.clone(),
                        None => return Err(loc.error(format!("{kw}: node set {name} is not defined"))),
                    },
                };
                for node in members {
                    if node == reference || nodes.contains(&node) {
                        return Err(loc.error(format!("{kw}: node {} is named twice (or is the reference node)", mesh.nodes[node].label)));
                    }
                    nodes.push(node);
                    weights.push(*weight);
                }
            }
            mesh.distributing_couplings.push(DistributingCoupling { reference, nodes, weights });
        }

        // Supports, merged per node, in order of first appearance.
        let mut supports: Vec<Support> = Vec::new();
        let mut support_of: HashMap<usize, usize> = HashMap::new();
        for b in &self.boundaries {
            let nodes: Vec<usize> = match &b.target {
                Target::Node(label) => vec![self.node_of(*label, &b.loc, "*BOUNDARY")?],
                Target::Set(name) => match mesh
                    .node_sets
                    .iter()
                    .find(|(k, _)| k.eq_ignore_ascii_case(name))
                {
                    Some((_, members)) => members.clone(),
                    None => {
                        return Err(b
                            .loc
                            .error(format!("*BOUNDARY: node set {name} is not defined")))
                    }
                },
            };
            if b.dofs.is_empty() {
                continue;
            }
            for n in nodes {
                match support_of.get(&n) {
                    Some(&i) => supports[i].dofs = supports[i].dofs.union(b.dofs),
                    None => {
                        support_of.insert(n, supports.len());
                        supports.push(Support {
                            node: n,
                            dofs: b.dofs,
                        });
                    }
                }
            }
        }
        Ok(InpModel {
            model: FeModel {
                mesh,
                supports,
                static_loads: Vec::new(),
                interface_nodes: Vec::new(),
                options: Default::default(),
            },
            warnings: self.warnings,
        })
    }
}

fn is_material_option(keyword: &str) -> bool {
    matches!(
        keyword,
        "ELASTIC"
            | "DENSITY"
            | "EXPANSION"
            | "DAMPING"
            | "PLASTIC"
            | "CONDUCTIVITY"
            | "SPECIFIC HEAT"
            | "HYPERELASTIC"
            | "CREEP"
            | "USER MATERIAL"
            | "DEPVAR"
    )
}

/// Abaqus' named boundary types.
fn named_boundary(field: &str) -> Option<DofSet> {
    let range = |dofs: &[usize]| {
        dofs.iter().fold(DofSet::EMPTY, |s, &k| {
            s.union(DofSet::from_abaqus_range(k, k).unwrap_or_default())
        })
    };
    Some(match field.to_uppercase().as_str() {
        "ENCASTRE" => DofSet::ALL,
        "PINNED" => DofSet::TRANSLATIONS,
        "XSYMM" => range(&[1, 5, 6]),
        "YSYMM" => range(&[2, 4, 6]),
        "ZSYMM" => range(&[3, 4, 5]),
        "XASYMM" => range(&[2, 3, 4]),
        "YASYMM" => range(&[1, 3, 5]),
        "ZASYMM" => range(&[1, 2, 6]),
        _ => return None,
    })
}
