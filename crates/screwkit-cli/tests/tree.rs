//! The CLI on the whole tree (a file with several leaves, no tip): `fk` (every leaf,
//! `--frames`, `--all-links`, `--floating-base`), `jacobian --of [--relative-to]`, `info`'s
//! `"variables"` and `"frames"` — each against the library's tree algorithms.

use std::process::Command;

use screwkit_model::{urdf, KinematicTree};
use screwkit_solve::tree::{fk, jacobian};
use screwkit_solve::{JacobianKind, TreeKinematics, TreeWorkspace};
use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn asset(name: &str) -> String {
    format!("{}/../../assets/urdf/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn run(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(BIN).args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn json(args: &[&str]) -> Value {
    let (code, out, err) = run(args);
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap()
}

fn model(floating: bool) -> TreeKinematics {
    let tree = urdf::load_file(asset("torso_two_arms.urdf")).unwrap();
    TreeKinematics::new(
        &KinematicTree::from_tree(&tree)
            .unwrap()
            .with_floating_base(floating),
    )
    .unwrap()
}

const Q: &str = "0.1,0.2,0.3,0.4,0.5,0.6,0.7";
const QF: &str = "0.5,-0.2,1,0.1,0.2,0.3,0.927362,0.1,0.2,0.3,0.4,0.5,0.6,0.7";

fn parse(q: &str) -> Vec<f64> {
    q.split(',').map(|x| x.parse().unwrap()).collect()
}

fn pose_of(v: &Value) -> [f64; 16] {
    let mut m = [0.0; 16];
    for (i, row) in v.as_array().unwrap().iter().enumerate() {
        for (j, x) in row.as_array().unwrap().iter().enumerate() {
            m[4 * i + j] = x.as_f64().unwrap();
        }
    }
    m
}

#[test]
fn fk_gives_every_leaf_or_the_named_frames() {
    let file = asset("torso_two_arms.urdf");
    for (floating, q) in [(false, Q), (true, QF)] {
        let kin = model(floating);
        let mut ws = TreeWorkspace::new(&kin);
        let qv = parse(q);
        let mut args = vec!["fk", file.as_str(), "--q", q, "--format", "json"];
        if floating {
            args.push("--floating-base");
        }
        let leaves = json(&args);
        let names: Vec<&str> = leaves["frames"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["name"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["head", "left_hand", "right_hand"]);
        args.extend(["--frames", "right_hand,torso"]);
        let named = json(&args);
        for f in named["frames"].as_array().unwrap() {
            let i = kin.frame(f["name"].as_str().unwrap()).unwrap();
            let mut want = [0.0; 16];
            fk::fk_frame(&kin, &mut ws, &qv, i)
                .unwrap()
                .write_row_major(&mut want);
            let got = pose_of(&f["pose"]);
            for (a, b) in got.iter().zip(want) {
                assert!((a - b).abs() < 1e-15, "{a} {b}");
            }
        }
        assert_eq!(named["frames"].as_array().unwrap().len(), 2);
    }
    let all = json(&["fk", &file, "--q", Q, "--all-links", "--format", "json"]);
    assert_eq!(all["frames"].as_array().unwrap().len(), 11);
    // Errors: one line, non-zero.
    let (code, _, err) = run(&["fk", &file, "--q", "0,1"]);
    assert_eq!(code, 1);
    assert!(
        err.contains("expected 7 configuration values") && err.lines().count() == 1,
        "{err}"
    );
    let (code, _, err) = run(&["fk", &file, "--q", Q, "--frames", "left_hnd"]);
    assert_eq!(code, 1);
    assert!(
        err.contains("unknown frame \"left_hnd\"") && err.contains("left_hand"),
        "{err}"
    );
    let bad = "0,0,0,0,0,0,0.5,0.1,0.2,0.3,0.4,0.5,0.6,0.7";
    let (code, _, err) = run(&[
        "fk",
        &file,
        "--q",
        bad,
        "--floating-base",
        "--frames",
        "head",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("quaternion"), "{err}");
}

#[test]
fn jacobian_of_a_frame_and_relative() {
    let file = asset("torso_two_arms.urdf");
    let kin = model(false);
    let mut ws = TreeWorkspace::new(&kin);
    let q = parse(Q);
    for (form, word) in [
        (JacobianKind::Space, "space"),
        (JacobianKind::Body, "body"),
        (JacobianKind::WorldAligned, "world-aligned"),
    ] {
        for relative in [None, Some("head")] {
            let mut args = vec![
                "jacobian",
                file.as_str(),
                "--q",
                Q,
                "--of",
                "left_hand",
                "--frame",
                word,
                "--format",
                "json",
            ];
            if let Some(r) = relative {
                args.extend(["--relative-to", r]);
            }
            let v = json(&args);
            let a = kin.frame("left_hand").unwrap();
            let j = match relative {
                Some(r) => {
                    let b = kin.frame(r).unwrap();
                    jacobian::relative_jacobian(&kin, &mut ws, &q, a, b, form)
                        .unwrap()
                        .jacobian
                        .clone()
                }
                None => jacobian::frame_jacobian(&kin, &mut ws, &q, a, form)
                    .unwrap()
                    .clone(),
            };
            let rows = v["jacobian"].as_array().unwrap();
            assert_eq!(v["columns"].as_array().unwrap().len(), 7);
            for (r, row) in rows.iter().enumerate() {
                for (c, x) in row.as_array().unwrap().iter().enumerate() {
                    assert!((x.as_f64().unwrap() - j[(r, c)]).abs() < 1e-15);
                }
            }
        }
    }
    let (code, _, err) = run(&["jacobian", &file, "--q", Q]);
    assert_eq!(code, 1);
    assert!(err.contains("--of"), "{err}");
}

#[test]
fn info_lists_variables_and_frames() {
    let file = asset("gripper_arm.urdf");
    let v = json(&["info", &file, "--format", "json"]);
    let names: Vec<&str> = v["variables"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x["name"].as_str().unwrap())
        .collect();
    // File order, mimic followers (coupled_joint, right_finger_joint) excluded.
    assert_eq!(
        names,
        ["shoulder_joint", "elbow_joint", "left_finger_joint"]
    );
    assert_eq!(v["variables"][2]["type"], "prismatic");
    assert_eq!(v["variables"][2]["upper"].as_f64(), Some(0.04));
    let frames = v["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 7);
    assert_eq!(frames[0]["name"], "base_link");
    assert_eq!(frames[0]["home"][0][0].as_f64(), Some(1.0));
}

/// `fk` and `jacobian --of` on the whole tree with `--input` JSON lines: every good line is
/// exactly the single call's answer (`--analyze` included), a bad line is its error with its
/// line number, the others are answered, and the run fails.
#[test]
fn tree_batches_answer_each_line_as_the_single_call() {
    let file = asset("torso_two_arms.urdf");
    let dir = std::env::temp_dir().join(format!("screwkit-tree-batch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let qs = [Q, "0.3,-0.2,0.1,0.9,-0.4,0.2,-0.6", "0,0,0,0,0,0,0"];
    let mut text = String::new();
    for (k, q) in qs.iter().enumerate() {
        text.push_str(&format!("{{\"q\": [{q}]}}\n"));
        if k == 0 {
            text.push_str("{\"q\": [1, 2]}\n\nnot json\n");
        }
    }
    let input = dir.join("q.jsonl");
    std::fs::write(&input, text).unwrap();
    let input = input.to_str().unwrap();
    let requests: [&[&str]; 4] = [
        &["fk", &file],
        &["fk", &file, "--frames", "left_hand,head"],
        &["fk", &file, "--all-links"],
        &[
            "jacobian",
            &file,
            "--of",
            "left_hand",
            "--relative-to",
            "head",
            "--frame",
            "body",
            "--analyze",
        ],
    ];
    for request in requests {
        let mut args = request.to_vec();
        args.extend(["--input", input]);
        let (code, out, err) = run(&args);
        assert_eq!(code, 1, "{args:?}: two bad lines fail the run");
        assert!(err.contains("5 lines, 2 failed"), "{err}");
        let lines: Vec<Value> = out
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 5);
        assert_eq!(lines[1]["line"], 2);
        assert!(
            lines[1]["error"].as_str().unwrap().contains("expected 7"),
            "{}",
            lines[1]
        );
        assert_eq!(lines[2]["line"], 4);
        assert!(lines[2]["error"].as_str().unwrap().contains("invalid JSON"));
        for (k, q) in [(0, qs[0]), (3, qs[1]), (4, qs[2])] {
            let mut single = request.to_vec();
            single.extend(["--q", q, "--format", "json"]);
            assert_eq!(lines[k], json(&single), "{args:?} line {k}");
        }
    }
    // The analysis is of the library's relative Jacobian.
    let kin = model(false);
    let mut ws = TreeWorkspace::new(&kin);
    let (a, b) = (kin.frame("left_hand").unwrap(), kin.frame("head").unwrap());
    let j = jacobian::relative_jacobian(&kin, &mut ws, &parse(Q), a, b, JacobianKind::Body)
        .unwrap()
        .jacobian
        .clone();
    let want = screwkit_solve::analysis::analyze_jacobian(&j).unwrap();
    let v = json(&[
        "jacobian",
        &file,
        "--of",
        "left_hand",
        "--relative-to",
        "head",
        "--frame",
        "body",
        "--analyze",
        "--q",
        Q,
        "--format",
        "json",
    ]);
    assert_eq!(v["analysis"]["rank"], want.rank);
    let got: Vec<f64> = serde_json::from_value(v["analysis"]["singular_values"].clone()).unwrap();
    for (g, w) in got.iter().zip(&want.singular_values) {
        assert!((g - w).abs() < 1e-14, "{g} vs {w}");
    }
    // Text output with the analysis.
    let (code, out, err) = run(&[
        "jacobian",
        &file,
        "--of",
        "left_hand",
        "--analyze",
        "--q",
        Q,
    ]);
    assert_eq!(code, 0, "{err}");
    // Four joints (waist, the left arm) move the left hand: rank 4.
    assert!(out.contains("rank                  4 of 6"), "{out}");
    let _ = std::fs::remove_dir_all(dir);
}
