//! Many processes loading the same flexible model at once (a sweep's workers, a study's variants)
//! reduce its FE model once: the first takes the cache's lock and reduces, the others wait and read
//! the reduced body from the cache, and every process reports the same model.

use crate::program;

use std::process::{Command, Stdio};

use program::{scratch, text, workspace};

#[test]
fn six_concurrent_checks_reduce_the_door_once_and_agree() {
    let dir = scratch("concurrent-reduction");
    for file in ["door.toml", "door_fe.toml"] {
        std::fs::copy(workspace().join("models/door").join(file), dir.join(file)).unwrap();
    }
    let model = dir.join("door.toml");
    let children: Vec<_> = (0..6)
        .map(|_| {
            Command::new(env!("CARGO_BIN_EXE_flexmb"))
                .arg("check")
                .arg(&model)
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .expect("flexmb starts")
        })
        .collect();
    let outputs: Vec<String> = children
        .into_iter()
        .map(|child| {
            let o = child.wait_with_output().unwrap();
            assert!(o.status.success(), "{}{}", text(&o.stdout), text(&o.stderr));
            text(&o.stdout)
        })
        .collect();
    // The origin is the check's line `flexible body 'door' (4N5S orthonormal): …`.
    let origin = |output: &str| output.lines().find(|l| l.starts_with("flexible body 'door' (")).unwrap().to_string();
    let reduced = outputs.iter().filter(|o| origin(o).contains(": reduced from ")).count();
    let from_cache = outputs.iter().filter(|o| origin(o).contains(": reduction of ") && origin(o).contains(" read from the cache ")).count();
    assert_eq!((reduced, from_cache), (1, 5), "{outputs:#?}");
    // Everything else the checks print (assembly, degrees of freedom, frequencies, mass) is the same;
    // the reduction's warnings (a rigid motion left free by the supports) only the one that reduced
    // prints.
    let rest = |output: &str| {
        let lines = output.lines().filter(|l| !l.starts_with("flexible body 'door' (") && !l.starts_with("warning: door: "));
        lines.collect::<Vec<_>>().join("\n")
    };
    for output in &outputs[1..] {
        assert_eq!(rest(output), rest(&outputs[0]));
    }
    // One cached body, and no lock or temporary file left behind.
    let left: Vec<String> = std::fs::read_dir(dir.join(".flexmb-cache"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(left.len() == 1 && left[0].starts_with("door_fe-4N5S-orthonormal-") && left[0].ends_with(".json"), "{left:?}");
}
