//! Fuzz target of the whole-body task JSON (`screwkit ik --tasks FILE`, its batch lines): mutated
//! task lists from the seeded mutation fuzzer of `screwkit_testkit::fuzz`, each parsed, changed
//! by a mutated batch line, resolved against a robot and, when that succeeds, solved (one
//! control step and a short `ik_tasks`): every input gives a result or an error, never a panic,
//! and every answer is finite and within the limits. A few seconds here; `SCREWKIT_FUZZ_SECS=600`
//! runs ten minutes.

use screwkit_model::{urdf, KinematicTree};
use screwkit_service::tasks::{default_seed, resolve_all, TaskList};
use screwkit_solve::tree::differential_ik::{
    ik_step, ik_tasks, DiffIkWorkspace, Limits, TasksOptions,
};
use screwkit_solve::TreeKinematics;
use screwkit_testkit::fuzz;

fn kin() -> TreeKinematics {
    let path = format!(
        "{}/../../assets/urdf/torso_two_arms.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    let tree = urdf::load_file(path).unwrap();
    TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap()
}

const TOKENS: &[&[u8]] = &[
    b"[",
    b"]",
    b"{",
    b"}",
    b",",
    b":",
    b"\"type\"",
    b"\"frame\"",
    b"\"relative\"",
    b"\"axis\"",
    b"\"com\"",
    b"\"posture\"",
    b"\"damping\"",
    b"\"target\"",
    b"\"left_hand\"",
    b"\"right_hand\"",
    b"\"relative_to\"",
    b"\"direction\"",
    b"\"point\"",
    b"\"q_ref\"",
    b"\"gain\"",
    b"\"weight\"",
    b"\"position_weight\"",
    b"\"orientation_weight\"",
    b"\"tol_pos\"",
    b"\"tol_rot\"",
    b"null",
    b"true",
    b"1e308",
    b"1e999",
    b"-0.0",
    b"0",
    b"-1",
    b"1e-320",
    b"\"tasks\"",
    b"\\u0000",
    b"\"",
    b"NaN",
];

#[test]
fn fuzz_task_json() {
    let kin = kin();
    let eye = "[1,0,0,0.3, 0,1,0,0.2, 0,0,1,0.6, 0,0,0,1]";
    let seeds: Vec<Vec<u8>> = [
        format!(
            r#"{{"tasks": [{{"type": "frame", "frame": "left_hand", "target": {eye}, "orientation_weight": 0}}, {{"type": "damping", "weight": 0.001}}]}}"#
        ),
        format!(
            r#"[{{"type": "relative", "frame": "left_hand", "relative_to": "right_hand", "target": {eye}, "position_weight": [1, 1, 0], "gain": 0.5}}]"#
        ),
        r#"[{"type": "axis", "frame": "right_hand", "axis": [0, 0, 1], "direction": [1, 0, 0], "point": [0.3, -0.2, 0.6]}, {"type": "posture", "q_ref": [0, 0, 0, 0, 0, 0, 0], "weight": 0.01}]"#.into(),
        r#"[{"type": "com", "target": [0, 0, 0.5], "position_weight": [1, 1, 0], "tol_pos": 1e-6}]"#.into(),
    ]
    .iter()
    .map(|s| s.as_bytes().to_vec())
    .collect();
    let changes: Vec<serde_json::Value> = vec![
        serde_json::json!({"target": [1, 0, 0, 0.2, 0, 1, 0, 0.3, 0, 0, 1, 0.5, 0, 0, 0, 1]}),
        serde_json::Value::Null,
    ];
    let seed = default_seed(&kin);
    let mut ws = DiffIkWorkspace::new(&kin);
    let opts = TasksOptions {
        max_iterations: 5,
        restarts: 1,
        ..TasksOptions::default()
    };
    let (lo, hi) = (kin.lower(), kin.upper());
    let (mut solved, mut refused) = (0u64, 0u64);
    let n = fuzz::run("task-json", 9, 4.0, &seeds, TOKENS, |input| {
        let Ok(text) = std::str::from_utf8(input) else {
            return;
        };
        let Ok(list) = TaskList::parse(text) else {
            refused += 1;
            return;
        };
        for specs in [Ok(list.specs().to_vec()), list.with_changes(&changes)] {
            let Ok(tasks) = specs.and_then(|s| resolve_all(&s, &kin)) else {
                refused += 1;
                continue;
            };
            if let Ok(v) = ik_step(&kin, &mut ws, &seed, &tasks, 0.01, &Limits::default()) {
                assert!(v.iter().all(|x| x.is_finite()), "{text}: step {v:?}");
            }
            if let Ok(r) = ik_tasks(&kin, &mut ws, &tasks, &seed, &opts) {
                for (i, x) in r.q.iter().enumerate() {
                    assert!(
                        x.is_finite() && *x >= lo[i] - 1e-9 && *x <= hi[i] + 1e-9,
                        "{text}: q[{i}] = {x}"
                    );
                }
                solved += 1;
            }
        }
    });
    eprintln!("fuzz task-json: {n} inputs, {solved} solved, {refused} refused");
    assert!(
        solved > 0 && refused > 0,
        "the fuzzer reaches both outcomes"
    );
}
