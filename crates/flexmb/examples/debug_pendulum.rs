#[path = "../tests/common/mod.rs"]
mod common;
use flexmb::analysis::*;
use flexmb::integrate::*;
fn main() {
    let args: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().unwrap()).collect();
    let mut b = common::pendulum(1.0, 1.0, 1e-3, 1.0, 9.81);
    let bob = b.find_marker("bob_centre").unwrap();
    b.add_output("bob", flexmb::model::OutputKind::MarkerPosition(bob));
    b.add_output("energy", flexmb::model::OutputKind::Energy);
    let model = b.build().unwrap();
    let settings = SimulationSettings { t_end: args[0], output_step: args[1], integrator: BdfConfig { rtol: args[2], atol: args[2], ..Default::default() }, assembly: Default::default() };
    let t0 = std::time::Instant::now();
    let r = simulate(&model, &settings, &mut |_f| {});
    println!("{:?} {:?}", t0.elapsed(), r.map(|r| (r.stats, r.max_position_residual)).map_err(|e| e.to_string()));
}
