//! The seed's applications as benchmarks: the door with mode set 4N5S and the windshield wiper with
//! flexible arms, each for 2 s with the BDF and the model file's settings (tolerances, static modal
//! assembly). The seed reports 7281 s of CPU for the 4N5S door (Prime 750); it gives no time for the
//! wiper.

use flexmb::analysis::SimulationSettings;
use flexmb::integrate::Method;
use flexmb::Model;

use flexmb_files::model_file::{LoadOptions, ModelOverrides};
use flexmb_files::SimulationDefaults;

use super::shipped_models::load_shipped;

/// The seed's CPU time for the 4N5S door over 2 s (s).
pub const SEED_DOOR_4N5S_CPU: f64 = 7281.0;

/// A shipped model with the BDF and its file's settings for `t_end`.
fn load(path: &str, overrides: &ModelOverrides, t_end: f64) -> Result<(Model, SimulationSettings), String> {
    let options = LoadOptions { overrides: overrides.clone(), ..crate::limits::load_options() };
    let (model, simulation) = load_shipped(path, &options)?;
    let d = SimulationDefaults { t_end, method: Method::default(), ..simulation };
    let settings = d.settings(&model, d.assembly());
    Ok((model, settings))
}

/// models/door/door.toml with mode set 4N5S, 2 s.
pub fn door_4n5s() -> Result<(Model, SimulationSettings), String> {
    let overrides = ModelOverrides { modes: vec![("door".into(), "4N5S".into())], ..Default::default() };
    load("door/door.toml", &overrides, 2.0)
}

/// models/wiper/wiper.toml (flexible arms, 4N each), 2 s.
pub fn wiper() -> Result<(Model, SimulationSettings), String> {
    load("wiper/wiper.toml", &ModelOverrides::default(), 2.0)
}
