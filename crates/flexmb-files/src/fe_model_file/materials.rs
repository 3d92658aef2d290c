//! `[[material]]`: isotropic linear-elastic materials, E > 0, 0 ≤ ν < 0.5, ρ ≥ 0.

use toml::Spanned;

use flexmb_fem::Material;
use flexmb_fem::input::Quantity;

use super::build::Builder;
use super::schema::MaterialSection;
use crate::model_file::key_path::KeyPath;
use crate::model_file::ModelFileError;

pub(crate) fn add_materials(b: &mut Builder, tables: &[Spanned<MaterialSection>]) -> Result<(), ModelFileError> {
    for (k, table) in tables.iter().enumerate() {
        let element = KeyPath::root().key("material").index(k);
        let m = table.get_ref();
        b.materials.check_new(&m.name, &element, b.source())?;
        let youngs_modulus = b.positive(&m.youngs_modulus, &element.key("E"), "Young's modulus E", Quantity::Modulus)?;
        let nu_key = element.key("nu");
        let poisson_ratio = b.ctx.number(&m.nu, &nu_key)?;
        if !(0.0..0.5).contains(&poisson_ratio) {
            return Err(b.ctx.invalid(
                &m.nu.span(),
                &nu_key,
                format!("Poisson's ratio nu must be at least 0 and less than 0.5, got {poisson_ratio}"),
            ));
        }
        let density = b.non_negative(&m.rho, &element.key("rho"), "the density rho", Quantity::Density)?;
        let mesh = &mut b.model.mesh;
        mesh.materials.push(Material { name: m.name.get_ref().clone(), youngs_modulus, poisson_ratio, density });
        let index = mesh.materials.len() - 1;
        b.materials.define(&m.name, &element, index);
    }
    Ok(())
}
