//! Thousands of bodies through the initial-condition analyses, which are sparse: with the constraint
//! Jacobians dense, the 5,000-body chain needed 11.5 GiB and minutes (work growing with the cube of
//! the bodies); sparse, its estimate is 111 MiB and it is checked against a limit of 256 MiB here.
//! Counted, not timed: the redundant rows named, the degrees of freedom, the assembly's iterations.

use flexmb::analysis::{analysis_bytes, assemble, format_bytes, velocity_analysis, AssemblySettings, MemoryLimit, State};
use flexmb::analysis::test_models::{spherical_chain, spherical_pendulums_hung_twice};
use flexmb::Data;

fn limited() -> AssemblySettings {
    AssemblySettings { memory_limit: MemoryLimit::Bytes(256 << 20), ..Default::default() }
}

#[test]
fn a_chain_of_5000_rods_assembles_within_a_memory_limit_the_dense_analyses_exceeded_fifty_times() {
    let model = spherical_chain(5000);
    let l = model.layout();
    // The dense working set: Φ̂_q, B and Φ̂_q Φ̂_qᵀ.
    let (nc, nb, nq, nv) = (l.nc as u64, 5000u64, l.nq as u64, l.nv as u64);
    let dense = 8 * ((nc + nb) * nq + nc * nv + (nc + nb) * (nc + nb));
    assert_eq!(format_bytes(dense), "11.5 GiB");
    assert!(analysis_bytes(&model) < dense / 50, "{}", format_bytes(analysis_bytes(&model)));
    let mut data = Data::new(&model);
    let mut state = State::initial(&model);
    let report = assemble(&model, &mut data, &mut state, limited()).unwrap();
    assert_eq!(report.degrees_of_freedom, 3 * 5000);
    assert!(report.redundant.is_empty());
    // The rods are placed end to end: the joints hold from the start.
    assert_eq!(report.iterations, 0);
    velocity_analysis(&model, &mut data, &mut state).unwrap();
}

#[test]
fn of_4000_pendulums_the_ones_hung_twice_have_their_second_joint_named_redundant() {
    // Every 400th pendulum gets a second, identical spherical joint: its 3 rows repeat the first's.
    let model = spherical_pendulums_hung_twice(4000, 400);
    let mut data = Data::new(&model);
    let mut state = State::initial(&model);
    // Start off the assembled configuration, every rod 5 cm too high, so that the assembly moves them.
    for b in 0..4000 {
        let qo = 7 * b;
        state.q[qo + 2] += 0.05;
    }
    let report = assemble(&model, &mut data, &mut state, limited()).unwrap();
    assert_eq!(report.redundant.len(), 3 * 10);
    for (k, r) in report.redundant.iter().enumerate() {
        let pendulum = 400 * (k / 3);
        assert!(r.description.starts_with(&format!("joint 's{pendulum}_again' (spherical), equation {}", k % 3 + 1)), "{}", r.description);
    }
    assert_eq!(report.degrees_of_freedom, 3 * 4000);
    assert!(report.residual <= 1e-10 && report.iterations > 0 && report.iterations < 10, "{report:?}");
}

