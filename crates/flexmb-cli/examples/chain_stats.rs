use flexmb::analysis::*;
use flexmb::integrate::*;
fn main() {
    let model = flexmb_cli::bench::spherical_chain(20);
    let settings = SimulationSettings { t_end: 5.0, output_step: 0.01, integrator: BdfConfig::default(), assembly: Default::default() };
    let t0 = std::time::Instant::now();
    let r = simulate(&model, &settings, &mut |_f| {}).unwrap();
    println!("{:?} {:?}", t0.elapsed(), r.stats);
}
