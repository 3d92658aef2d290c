//! A model too large for the memory of the initial-condition analyses ends with an error that says how
//! much it needed, before anything is allocated (a chain of 20,000 bodies aborted with SIGABRT in an
//! allocation of its 58 GB dense Jacobian when the analyses were dense; sparse, they need 446 MiB at
//! most, linear in the bodies).

use crate::program;

use std::process::Command;

use program::{scratch, text, workspace};

/// A chain of `n` rigid links of 1 m on spherical joints, hanging from ground.
fn chain(n: usize) -> String {
    let mut s = String::from("[model]\nname = \"chain\"\ngravity = [0, -9.81, 0]\n\n");
    for i in 0..n {
        s.push_str(&format!("[[body]]\nname = \"link{i}\"\nmass = 1.0\ninertia = [0.01, 0.1, 0.1]\nposition = [{}, 0, 0]\n\n", i as f64 + 0.5));
    }
    for i in 0..n {
        let parent = if i == 0 { "ground".to_string() } else { format!("link{}", i - 1) };
        let parent_origin = if i == 0 { 0.0 } else { 0.5 };
        s.push_str(&format!(
            "[[marker]]\nname = \"p{i}\"\nbody = \"{parent}\"\norigin = [{parent_origin}, 0, 0]\n\n\
             [[marker]]\nname = \"c{i}\"\nbody = \"link{i}\"\norigin = [-0.5, 0, 0]\n\n\
             [[joint]]\nname = \"j{i}\"\ntype = \"spherical\"\ni = \"p{i}\"\nj = \"c{i}\"\n\n"
        ));
    }
    s
}

fn flexmb_with_memory_limit(limit: &str, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_flexmb"))
        .args(args)
        .env("FLEXMB_MEMORY_LIMIT", limit)
        .current_dir(workspace())
        .output()
        .expect("flexmb runs")
}

#[test]
fn a_model_larger_than_the_memory_limit_is_refused_with_what_it_needs() {
    let dir = scratch("model-size");
    let model = dir.join("chain.toml");
    std::fs::write(&model, chain(1000)).unwrap();
    let m = model.to_str().unwrap();
    let out = dir.join("out");
    // 3,000 equations, 6,000 velocities, 7,000 positions; per body 7 rows of Φ̂ (the normalization and two
    // joints') on 7 positions and 6 velocities: 999·(7·13·64 + 7·7²·48 + 17·64) + 4·13·64 + 7·4²·48 +
    // 17·64 bytes = 22.3 MiB (the dense analyses needed 473 MiB).
    for args in [vec!["check", m], vec!["run", m, "--out", out.to_str().unwrap()]] {
        let o = flexmb_with_memory_limit("10M", &args);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: a clean failure: {e}");
        assert!(e.contains("chain.toml") && e.contains("too large"), "{e}");
        assert!(e.contains("need about 22.3 MiB") && e.contains("3000 constraint equations"), "{e}");
        assert!(e.contains("10.0 MiB is the memory limit given"), "{e}");
    }
    // A limit that allows it: the check goes on (a small chain, to keep the test short).
    std::fs::write(&model, chain(20)).unwrap();
    let o = flexmb_with_memory_limit("1G", &["check", m]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("degrees of freedom: 60"), "{}", text(&o.stdout));

    let o = flexmb_with_memory_limit("plenty", &["check", m]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("FLEXMB_MEMORY_LIMIT=\"plenty\": expected a whole number of bytes"), "{}", text(&o.stderr));
}
