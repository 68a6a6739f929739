//! `screwkit ik FILE --tasks TASKS.json`: whole-body IK from the command line — one solve (text
//! and JSON), batch lines of task changes (all cores, and `--sequential`), and its errors.
//! Every reported answer is checked by the composition of the URDF joint by joint
//! (`screwkit_testkit::reference::tree_world_poses`), never by the solver itself.

use std::io::Write;
use std::process::{Command, Stdio};

use nalgebra::{Matrix4, Vector3};
use screwkit_model::{urdf, KinematicTree, Tree};
use screwkit_solve::TreeKinematics;
use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn root(rel: &str) -> String {
    format!("{}/../../{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn robot() -> (Tree, TreeKinematics) {
    let tree = urdf::load_file(root("assets/urdf/torso_two_arms.urdf")).unwrap();
    let kin = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
    (tree, kin)
}

fn run(args: &[&str], stdin: &str) -> (i32, String, String) {
    let mut child = Command::new(BIN)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(stdin.as_bytes())
        .unwrap();
    let o = child.wait_with_output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// The hand's world position at q by the composition oracle.
fn hand(tree: &Tree, kin: &TreeKinematics, q: &[f64], name: &str) -> Vector3<f64> {
    let poses: Vec<Matrix4<f64>> = screwkit_testkit::reference::tree_world_poses(tree, kin, q);
    let link = tree.links.iter().position(|l| l == name).unwrap();
    poses[link].fixed_view::<3, 1>(0, 3).into()
}

/// q within the file's limits.
fn assert_within_limits(kin: &TreeKinematics, q: &[f64]) {
    let (lo, hi) = (kin.lower(), kin.upper());
    for i in 0..q.len() {
        assert!(q[i] >= lo[i] && q[i] <= hi[i], "q[{i}] = {}", q[i]);
    }
}

const TASKS: &str = "assets/tasks/torso_two_arms.json";

#[test]
fn one_solve_reaches_both_hands_within_the_limits() {
    let (tree, kin) = robot();
    let file = root("assets/urdf/torso_two_arms.urdf");
    let (code, out, err) = run(
        &["--format", "json", "ik", &file, "--tasks", &root(TASKS)],
        "",
    );
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["converged"], true);
    assert_eq!(v["stop"], "converged");
    let q = numbers(&v["q"]);
    assert_within_limits(&kin, &q);
    for (name, want) in [
        ("left_hand", Vector3::new(0.3, 0.4, 0.95)),
        ("right_hand", Vector3::new(0.35, -0.25, 0.9)),
    ] {
        let got = hand(&tree, &kin, &q, name);
        assert!((got - want).norm() < 1e-9, "{name}: {got:?}");
    }
    let tasks = v["tasks"].as_array().unwrap();
    assert_eq!(tasks.len(), 3);
    assert_eq!(tasks[0]["task"], "frame task on \"left_hand\"");
    assert!(tasks[0]["position_error"].as_f64().unwrap() < 1e-9);
    // The text report says the same.
    let (code, out, _) = run(&["ik", &file, "--tasks", &root(TASKS)], "");
    assert_eq!(code, 0);
    assert!(out.starts_with("converged          yes\n"), "{out}");
    assert!(
        out.contains("task 2             posture task: |q - q_ref|"),
        "{out}"
    );
}

#[test]
fn batch_lines_change_targets_and_sequential_lines_follow_the_previous_answer() {
    let (tree, kin) = robot();
    let file = root("assets/urdf/torso_two_arms.urdf");
    // A small circle of the left hand, the right hand held: a motion clip.
    let targets: Vec<Vector3<f64>> = (0..12)
        .map(|k| {
            let a = k as f64 * 0.5;
            Vector3::new(0.3 + 0.05 * a.cos(), 0.4 + 0.05 * a.sin(), 0.95)
        })
        .collect();
    let mut lines: String = targets
        .iter()
        .map(|p| {
            format!(
                "{{\"tasks\": [{{\"target\": [1,0,0,{}, 0,1,0,{}, 0,0,1,{}, 0,0,0,1]}}]}}\n",
                p.x, p.y, p.z
            )
        })
        .collect();
    lines.push_str("{\"tasks\": [null, {\"frame\": \"nowhere\"}]}\n");
    lines.push_str("{\"seed\": [1, 2]}\n");
    for sequential in [false, true] {
        let tasks = root(TASKS);
        let mut args = vec!["ik", &file, "--tasks", &tasks, "--input", "-"];
        if sequential {
            args.push("--sequential");
        }
        let (code, out, err) = run(&args, &lines);
        assert_eq!(code, 1, "two bad lines: {err}");
        let answers: Vec<Value> = out
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(answers.len(), 14);
        let mut previous: Option<Vec<f64>> = None;
        for (k, p) in targets.iter().enumerate() {
            let a = &answers[k];
            assert_eq!(a["converged"], true, "line {}: {a}", k + 1);
            let q = numbers(&a["q"]);
            assert_within_limits(&kin, &q);
            assert!((hand(&tree, &kin, &q, "left_hand") - p).norm() < 1e-9);
            let right = hand(&tree, &kin, &q, "right_hand");
            assert!((right - Vector3::new(0.35, -0.25, 0.9)).norm() < 1e-9);
            if sequential {
                // Seeded by the previous answer: the single solve from it gives this answer.
                if let Some(prev) = &previous {
                    let seed: Vec<String> = prev.iter().map(|x| format!("{x:e}")).collect();
                    let line = lines.lines().nth(k).unwrap();
                    let dir = std::env::temp_dir().join(format!("sk-wb-{}", std::process::id()));
                    std::fs::create_dir_all(&dir).unwrap();
                    let changed = dir.join("tasks.json");
                    let base: Value =
                        serde_json::from_str(&std::fs::read_to_string(root(TASKS)).unwrap())
                            .unwrap();
                    let mut list = base["tasks"].as_array().unwrap().clone();
                    let change: Value = serde_json::from_str(line).unwrap();
                    for (key, val) in change["tasks"][0].as_object().unwrap() {
                        list[0][key] = val.clone();
                    }
                    std::fs::write(&changed, Value::Array(list).to_string()).unwrap();
                    let (code, out, err) = run(
                        &[
                            "--format",
                            "json",
                            "ik",
                            &file,
                            "--tasks",
                            changed.to_str().unwrap(),
                            "--seed",
                            &seed.join(","),
                        ],
                        "",
                    );
                    assert_eq!(code, 0, "{err}");
                    let single: Value = serde_json::from_str(&out).unwrap();
                    let (a, b) = (numbers(&single["q"]), q.clone());
                    for i in 0..a.len() {
                        assert!(
                            (a[i] - b[i]).abs() < 1e-12,
                            "line {}: {a:?} vs {b:?}",
                            k + 1
                        );
                    }
                }
                previous = Some(q.clone());
            }
        }
        assert_eq!(answers[12]["line"], 13);
        assert!(answers[12]["error"].as_str().unwrap().contains("task 1: "));
        assert!(answers[13]["error"].as_str().unwrap().starts_with("seed: "));
    }
}

#[test]
fn bad_task_files_and_flags_are_one_line_errors() {
    let file = root("assets/urdf/torso_two_arms.urdf");
    let dir = std::env::temp_dir().join(format!("sk-wb-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        ("[{\"type\": \"frame\",\n \"frame\": \"left_hand\", \"target\": [1, 2", "line 2 column"),
        ("[{\"type\": \"frame\", \"frame\": \"nowhere\", \"target\": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]", "task 0: "),
        ("[{\"type\": \"spin\"}]", "task 0: unknown variant"),
        ("[{\"type\": \"damping\", \"wieght\": 1}]", "unknown field"),
        ("{\"tasks\": 3}", "\"tasks\" must be a list"),
        ("[{\"type\": \"posture\", \"q_ref\": [0, 0]}]", "q_ref"),
        ("[{\"type\": \"damping\", \"weight\": 1e308}, {\"type\": \"frame\", \"frame\": \"left_hand\", \"target\": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]", "overflows"),
    ];
    for (i, (text, words)) in cases.iter().enumerate() {
        let path = dir.join(format!("t{i}.json"));
        std::fs::write(&path, text).unwrap();
        let p = path.to_str().unwrap();
        let (code, out, err) = run(&["ik", &file, "--tasks", p], "");
        assert_eq!(code, 1, "{text}: {err}");
        assert!(out.is_empty());
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(words), "{err} (wanted {words})");
        assert!(err.contains(p), "the file is named: {err}");
    }
    let (code, _, err) = run(&["ik", &file, "--tasks", "/nonexistent/t.json"], "");
    assert_eq!(code, 1);
    assert!(err.contains("/nonexistent/t.json"), "{err}");
    let (code, _, err) = run(
        &[
            "ik",
            &file,
            "--tasks",
            &root(TASKS),
            "--target-xyz-rpy",
            "0,0,0,0,0,0",
        ],
        "",
    );
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = run(&["ik", &file, "--tasks", &root(TASKS), "--seed", "1,2"], "");
    assert_eq!(code, 1);
    assert!(err.contains("--seed"), "{err}");
    let (code, _, err) = run(&["ik", &file, "--tasks", "-", "--input", "-"], "[]");
    assert_eq!(code, 1);
    assert!(err.contains("standard input"), "{err}");
}

/// Issue 44, item 6: in `--sequential` mode a line whose seed is bad (outside the limits) is
/// refused alone; the lines after it go on from the last good answer (they all failed with
/// that line's error).
#[test]
fn a_bad_seed_in_sequential_mode_fails_its_line_alone() {
    let file = root("assets/urdf/torso_two_arms.urdf");
    let tasks = root(TASKS);
    let target = |x: f64| {
        format!("{{\"tasks\": [{{\"target\": [1,0,0,{x}, 0,1,0,0.4, 0,0,1,0.95, 0,0,0,1]}}]}}\n")
    };
    let lines = [
        target(0.3),
        "{\"seed\": [9, 9, 9, 9, 9, 9, 9]}\n".to_string(),
        target(0.32),
        target(0.34),
    ]
    .concat();
    let (code, out, err) = run(
        &[
            "ik",
            &file,
            "--tasks",
            &tasks,
            "--input",
            "-",
            "--sequential",
        ],
        &lines,
    );
    assert_eq!(code, 1, "one bad line: {err}");
    let answers: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(answers.len(), 4, "{out}");
    assert_eq!(answers[0]["converged"], true, "{}", answers[0]);
    assert!(
        answers[1]["error"].as_str().unwrap().contains("limits"),
        "{}",
        answers[1]
    );
    assert_eq!(answers[1]["line"], 2);
    for a in &answers[2..] {
        assert_eq!(a["converged"], true, "{a}");
    }
}
