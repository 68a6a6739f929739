//! Runs the real `screwkit` binary on the bundled robots, in both formats, and the error cases.

use std::io::Write;
use std::process::{Command, Stdio};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn asset(name: &str) -> String {
    format!("{}/../../assets/urdf/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// (file, tip) of every bundled robot (a tip where the tree has several leaves).
const ROBOTS: &[(&str, Option<&str>)] = &[
    ("planar_3r.urdf", None),
    ("ur5.urdf", None),
    ("panda.urdf", None),
    ("iiwa14.urdf", None),
    ("scara.urdf", None),
    ("tricky.urdf", None),
    ("torso_two_arms.urdf", Some("right_hand")),
    ("gripper_arm.urdf", Some("right_finger")),
];

struct Out {
    code: i32,
    stdout: String,
    stderr: String,
}

fn run(args: &[&str], stdin: Option<&str>) -> Out {
    let mut child = Command::new(BIN)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    if let Some(s) = stdin {
        child.stdin.take().unwrap().write_all(s.as_bytes()).unwrap();
    }
    drop(child.stdin.take());
    let o = child.wait_with_output().unwrap();
    Out {
        code: o.status.code().unwrap_or(-1),
        stdout: String::from_utf8(o.stdout).unwrap(),
        stderr: String::from_utf8(o.stderr).unwrap(),
    }
}

fn ok(args: &[&str]) -> String {
    let o = run(args, None);
    assert_eq!(o.code, 0, "{args:?}: {}", o.stderr);
    assert!(!o.stderr.contains("panicked"));
    o.stdout
}

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&ok(args)).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

fn chain(file: &str, tip: Option<&str>) -> (screwkit_model::Chain, screwkit_solve::Kinematics) {
    let c = screwkit_model::load_chain(asset(file), None, tip).unwrap();
    let k = screwkit_solve::Kinematics::new(&c);
    (c, k)
}

/// The library's FK with a fresh workspace.
fn fk1(
    kin: &screwkit_solve::Kinematics,
    q: &[f64],
) -> Result<screwkit_lie::Se3, screwkit_solve::SolveError> {
    screwkit_solve::fk::fk(kin, &mut screwkit_solve::Workspace::new(kin), q)
}

fn q_arg(q: &[f64]) -> String {
    q.iter()
        .map(|x| format!("{x:?}"))
        .collect::<Vec<_>>()
        .join(",")
}

fn matrix(v: &Value) -> nalgebra::Matrix4<f64> {
    let rows = v.as_array().unwrap();
    nalgebra::Matrix4::from_fn(|i, j| rows[i][j].as_f64().unwrap())
}

fn with_tip<'a>(mut args: Vec<&'a str>, tip: Option<&'a str>) -> Vec<&'a str> {
    if let Some(t) = tip {
        args.push("--tip");
        args.push(t);
    }
    args
}

#[test]
fn every_subcommand_on_every_bundled_robot() {
    for &(file, tip) in ROBOTS {
        let path = asset(file);
        let (c, kin) = chain(file, tip);
        // info
        let text = ok(&["info", &path]);
        assert!(text.contains(&format!("Robot `{}`", c.robot)));
        let info = json(&["info", &path, "--format", "json"]);
        let tree = screwkit_model::urdf::load_file(&path).unwrap();
        assert_eq!(info["links"].as_array().unwrap().len(), tree.links.len());
        assert_eq!(info["joints"].as_array().unwrap().len(), tree.joints.len());
        assert_eq!(info["root"], tree.links[tree.root].as_str());
        // table: md, csv, json
        let md = ok(&with_tip(vec!["table", &path], tip));
        assert!(md.contains("Space screw axes") && md.contains("Body screw axes"));
        let csv = ok(&with_tip(
            vec!["table", &path, "--format", "csv", "--frame", "space"],
            tip,
        ));
        assert_eq!(csv.lines().count(), 1 + c.joints.len() + 4);
        let tj = json(&with_tip(vec!["table", &path, "--format", "json"], tip));
        assert_eq!(tj["tip"], c.tip.as_str());
        assert_eq!(tj["joints"].as_array().unwrap().len(), c.joints.len());
        let s0 = &tj["joints"][0]["screw_space"];
        let want = c.joints[0].s_space.twist().to_vector();
        for i in 0..6 {
            assert_eq!(s0[i].as_f64().unwrap(), want[i] + 0.0);
        }
        // fk at a configuration inside the limits
        let q: Vec<f64> = kin
            .lower()
            .iter()
            .zip(kin.upper())
            .map(|(&l, &u)| {
                if l.is_finite() {
                    l + 0.37 * (u - l)
                } else {
                    0.4
                }
            })
            .collect();
        let qa = q_arg(&q);
        let fj = json(&with_tip(
            vec!["fk", &path, "--q", &qa, "--format", "json"],
            tip,
        ));
        let want = fk1(&kin, &q).unwrap().to_homogeneous();
        assert!(
            (matrix(&fj["pose"]) - want).amax() == 0.0,
            "{file}: full precision JSON"
        );
        let ft = ok(&with_tip(vec!["fk", &path, "--q", &qa, "--all-links"], tip));
        assert!(ft.contains("quaternion (x,y,z,w)") && ft.contains(&c.base));
        // jacobian, both frames, with analysis
        for frame in ["space", "body"] {
            let jj = json(&with_tip(
                vec![
                    "jacobian",
                    &path,
                    "--q",
                    &qa,
                    "--frame",
                    frame,
                    "--analyze",
                    "--format",
                    "json",
                ],
                tip,
            ));
            assert_eq!(jj["jacobian"].as_array().unwrap().len(), 6);
            assert_eq!(jj["jacobian"][0].as_array().unwrap().len(), kin.dof());
            assert!(jj["analysis"]["verdict"].as_str().is_some());
            let jt = ok(&with_tip(
                vec!["jacobian", &path, "--q", &qa, "--frame", frame, "--analyze"],
                tip,
            ));
            assert!(jt.contains("verdict"));
        }
        // ik to the FK of q: converged, and the solution reproduces the pose
        let t = fk1(&kin, &q).unwrap().to_homogeneous();
        let m: Vec<String> = (0..4)
            .flat_map(|i| (0..4).map(move |j| (i, j)))
            .map(|(i, j)| format!("{:?}", t[(i, j)]))
            .collect();
        let ma = m.join(",");
        let ij = json(&with_tip(
            vec![
                "ik",
                &path,
                "--target-matrix",
                &ma,
                "--format",
                "json",
                "--timeout-ms",
                "0",
            ],
            tip,
        ));
        assert_eq!(ij["converged"], true, "{file}: {ij}");
        let qs: Vec<f64> = ij["q"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let back = fk1(&kin, &qs).unwrap().to_homogeneous();
        assert!((back - t).amax() < 1e-8, "{file}");
        let it = ok(&with_tip(
            vec!["ik", &path, "--target-matrix", &ma, "--timeout-ms", "0"],
            tip,
        ));
        assert!(it.contains("converged          yes"));
        // bench (small)
        let bj = json(&with_tip(
            vec!["bench", &path, "--n", "20", "--format", "json"],
            tip,
        ));
        assert_eq!(bj["queries"], 20);
        assert!(bj["solve_rate"].as_f64().unwrap() > 0.8);
        assert!(ok(&with_tip(vec!["bench", &path, "--n", "5"], tip)).contains("solved"));
    }
}

#[test]
fn ik_target_forms_agree() {
    let path = asset("ur5.urdf");
    let xyz_rpy = json(&[
        "ik",
        &path,
        "--target-xyz-rpy",
        "0.4,0.1,0.3,3.0,0.1,-0.2",
        "--format",
        "json",
        "--timeout-ms",
        "0",
    ]);
    let (_, kin) = chain("ur5.urdf", None);
    let target = screwkit_lie::Se3::from_xyz_rpy([0.4, 0.1, 0.3], [3.0, 0.1, -0.2]).unwrap();
    let q: Vec<f64> = xyz_rpy["q"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(fk1(&kin, &q).unwrap().max_abs_diff(&target) < 1e-8);
    let quat = target.quaternion();
    let qa = format!(
        "0.4,0.1,0.3,{:?},{:?},{:?},{:?}",
        quat[0], quat[1], quat[2], quat[3]
    );
    let xyz_quat = json(&[
        "ik",
        &path,
        "--target-xyz-quat",
        &qa,
        "--format",
        "json",
        "--timeout-ms",
        "0",
    ]);
    assert_eq!(xyz_quat["converged"], true);
    // Position only: any orientation.
    let po = json(&[
        "ik",
        &path,
        "--target-xyz-rpy",
        "0.4,0.1,0.3,0,0,0",
        "--position-only",
        "--format",
        "json",
        "--timeout-ms",
        "0",
    ]);
    assert_eq!(po["converged"], true);
    for m in ["nr", "dls", "lm"] {
        let r = json(&[
            "ik",
            &path,
            "--target-xyz-rpy",
            "0.4,0.1,0.3,3.0,0.1,-0.2",
            "--method",
            m,
            "--format",
            "json",
            "--timeout-ms",
            "0",
        ]);
        assert_eq!(r["converged"], true, "{m}");
    }
}

#[test]
fn exp_and_log_calculator() {
    // The textbook example: T_sb = [[0,−1,0,3],[0,0,−1,0],[1,0,0,0]] → S, θ = 2π/3, h, q = (1, 1, 0).
    let v = json(&[
        "log",
        "--matrix",
        "0,-1,0,3,0,0,-1,0,1,0,0,0,0,0,0,1",
        "--format",
        "json",
    ]);
    assert!((v["theta"].as_f64().unwrap() - 2.0 * std::f64::consts::PI / 3.0).abs() < 1e-14);
    assert!((v["pitch"].as_f64().unwrap() - 0.826_993_343_132_688_2).abs() < 1e-13);
    let p = v["point"].as_array().unwrap();
    assert!(
        (p[0].as_f64().unwrap() - 1.0).abs() < 1e-13
            && (p[1].as_f64().unwrap() - 1.0).abs() < 1e-13
    );
    assert_eq!(v["pure_translation"], false);
    let t = json(&[
        "log",
        "--matrix",
        "1,0,0,3,0,1,0,4,0,0,1,0,0,0,0,1",
        "--format",
        "json",
    ]);
    assert_eq!(t["pure_translation"], true);
    assert_eq!(t["theta"], 5.0);
    assert_eq!(t["pitch"], Value::Null);
    assert_eq!(t["point"], Value::Null);
    let text = ok(&["log", "--matrix", "1,0,0,3,0,1,0,4,0,0,1,0,0,0,0,1"]);
    assert!(text.contains("Pure translation"));
    // exp of Sθ = (0,1,2,3,0,0): the textbook's second example, exact.
    let e = json(&["exp", "--twist", "0,1,2,3,0,0", "--format", "json"]);
    let m = matrix(&e["pose"]);
    assert!((m[(0, 0)] + 0.617_272_876_457_166_4).abs() < 1e-14);
    assert!((m[(0, 3)] - 1.055_534_723_627_097).abs() < 1e-14);
    // A unit screw with --theta equals the scaled twist.
    let e2 = json(&[
        "exp",
        "--twist",
        "0,0,1,0,-1,0",
        "--theta",
        "1.5707963267948966",
        "--format",
        "json",
    ]);
    let m2 = matrix(&e2["pose"]);
    assert!((m2[(0, 3)] - 1.0).abs() < 1e-15 && (m2[(1, 3)] + 1.0).abs() < 1e-15);
}

#[test]
fn batch_mode() {
    let path = asset("panda.urdf");
    let (_, kin) = chain("panda.urdf", None);
    let qs = [
        [0.1, 0.2, 0.3, -1.5, 0.1, 1.5, 0.2],
        [0.0, -0.3, 0.1, -2.0, 0.3, 1.9, -0.4],
    ];
    let mut input = String::new();
    for q in &qs {
        input.push_str(&format!("{{\"q\": {:?}}}\n", q));
    }
    input.push_str("{\"q\": [1, 2]}\nnonsense\n");
    let o = run(&["fk", &path, "--input", "-"], Some(&input));
    assert_eq!(o.code, 1, "failed lines make the run fail");
    let lines: Vec<Value> = o
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 4);
    for (k, q) in qs.iter().enumerate() {
        let want = fk1(&kin, q).unwrap().to_homogeneous();
        assert_eq!(matrix(&lines[k]["pose"]), want);
    }
    assert_eq!(lines[2]["line"], 3);
    assert!(lines[2]["error"]
        .as_str()
        .unwrap()
        .contains("expected 7 joint values"));
    assert_eq!(lines[3]["line"], 4);
    assert!(o.stderr.contains("4 lines, 2 failed"), "{}", o.stderr);
    // IK batch from a file: targets from FK, with and without seeds; jacobian batch.
    let mut ik_in = String::new();
    for (k, q) in qs.iter().enumerate() {
        let t = fk1(&kin, q).unwrap().to_homogeneous();
        let rows: Vec<Vec<f64>> = (0..4)
            .map(|i| (0..4).map(|j| t[(i, j)]).collect())
            .collect();
        if k == 0 {
            ik_in.push_str(&format!("{{\"target\": {rows:?}}}\n"));
        } else {
            ik_in.push_str(&format!("{{\"target\": {rows:?}, \"seed\": {:?}}}\n", q));
        }
    }
    let file = std::env::temp_dir().join(format!("screwkit_batch_{}.jsonl", std::process::id()));
    std::fs::write(&file, &ik_in).unwrap();
    let o = run(
        &[
            "ik",
            &path,
            "--input",
            file.to_str().unwrap(),
            "--timeout-ms",
            "0",
        ],
        None,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    let lines: Vec<Value> = o
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    assert!(lines.iter().all(|l| l["converged"] == true));
    assert_eq!(lines[1]["iterations"], 0, "seeded at the answer");
    let o = run(
        &["jacobian", &path, "--input", "-", "--frame", "body"],
        Some(&input[..input.find("{\"q\": [1").unwrap()]),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert_eq!(o.stdout.lines().count(), 2);
    std::fs::remove_file(file).ok();
}

#[test]
fn errors_are_one_line_with_the_right_exit_code() {
    let ur5 = asset("ur5.urdf");
    let cases: &[(&[&str], i32, &str)] = &[
        (&["fk", &ur5, "--q", "1,2,3"], 1, "expected 6 joint values"),
        (
            &["fk", &ur5, "--q", "1,2,x,4,5,6"],
            2,
            "\"x\" is not a number",
        ),
        (
            &["fk", &ur5, "--q", "1,2,nan,4,5,6"],
            2,
            "not a finite number",
        ),
        (
            &["fk", &ur5, "--tip", "nope", "--q", "1"],
            1,
            "unknown link \"nope\"",
        ),
        (
            &["fk", "/no/such.urdf", "--q", "1"],
            1,
            "/no/such.urdf: cannot read",
        ),
        (
            &["table", &asset("torso_two_arms.urdf")],
            1,
            "cannot choose a tip link",
        ),
        (
            &["table", &ur5, "--base", "tool0", "--tip", "base_link"],
            1,
            "is not an ancestor",
        ),
        (
            &[
                "ik",
                &ur5,
                "--target-xyz-rpy",
                "5,0,0,0,0,0",
                "--max-iter",
                "300",
            ],
            1,
            "IK did not converge",
        ),
        (&["ik", &ur5], 1, "give exactly one target"),
        (
            &["ik", &ur5, "--target-xyz-rpy", "1,2,3"],
            1,
            "needs 6 numbers",
        ),
        (
            &[
                "ik",
                &ur5,
                "--target-matrix",
                "1,0,0,0,0,2,0,0,0,0,1,0,0,0,0,1",
            ],
            1,
            "not a rotation matrix",
        ),
        (&["exp", "--twist", "1,2,3"], 1, "needs 6 numbers"),
        (&["log", "--matrix", "1,2,3"], 1, "needs 16 numbers"),
        (
            &["fk", &ur5, "--q", "0,0,0,0,0,0", "--format", "csv"],
            1,
            "only available for `table`",
        ),
        (&["bogus"], 2, "unrecognized subcommand"),
        (&["fk", &ur5], 2, "--q"),
    ];
    for (args, code, words) in cases {
        let o = run(args, None);
        assert_eq!(o.code, *code, "{args:?}: {}", o.stderr);
        assert!(o.stderr.contains(words), "{args:?}: {}", o.stderr);
        assert!(
            !o.stderr.contains("panicked") && !o.stderr.contains("backtrace"),
            "{args:?}"
        );
        if *code == 1 {
            assert_eq!(o.stderr.trim().lines().count(), 1, "{args:?}: {}", o.stderr);
        }
    }
    // A bad URDF.
    let bad = std::env::temp_dir().join(format!("screwkit_bad_{}.urdf", std::process::id()));
    std::fs::write(&bad, "<robot name=\"r\"><link name=\"a\"/><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>").unwrap();
    let o = run(&["table", bad.to_str().unwrap()], None);
    assert_eq!(o.code, 1);
    assert!(
        o.stderr
            .contains("joint \"j\" names child link \"b\", which is not defined"),
        "{}",
        o.stderr
    );
    std::fs::remove_file(bad).ok();
}

/// A chain with only fixed joints: zero variables, `--q ""`.
#[test]
fn zero_dof_chain() {
    let path = asset("tricky.urdf");
    let v = json(&[
        "fk", &path, "--base", "l1", "--tip", "l1b", "--q", "", "--format", "json",
    ]);
    assert_eq!(v["q"].as_array().unwrap().len(), 0);
    let m = matrix(&v["pose"]);
    // mid_fixed: xyz (0, 0.15, 0.1), roll 1.570796325 as written.
    assert!((m[(1, 3)] - 0.15).abs() < 1e-15 && (m[(2, 3)] - 0.1).abs() < 1e-15);
    assert!((m[(2, 1)] - 1.570796325f64.sin()).abs() < 1e-15);
    let j = json(&[
        "jacobian",
        &path,
        "--base",
        "l1",
        "--tip",
        "l1b",
        "--q",
        "",
        "--analyze",
        "--format",
        "json",
    ]);
    assert_eq!(j["analysis"]["rank"], 0);
}

/// Human-readable output pinned once (reviewed by hand: the UR5 numbers are the Modern
/// Robotics Example 4.5 values; the log output is the textbook example T_sb → (S, θ = 2π/3)).
#[test]
fn human_output_snapshots() {
    insta::assert_snapshot!(
        "table_ur5_space",
        ok(&["table", &asset("ur5.urdf"), "--frame", "space"])
    );
    insta::assert_snapshot!(
        "fk_planar",
        ok(&["fk", &asset("planar_3r.urdf"), "--q", "0.5,-0.25,1.0"])
    );
    insta::assert_snapshot!(
        "log_lesson",
        ok(&["log", "--matrix", "0,-1,0,3,0,0,-1,0,1,0,0,0,0,0,0,1"])
    );
    insta::assert_snapshot!(
        "jacobian_ur5_wrist_singular",
        ok(&[
            "jacobian",
            &asset("ur5.urdf"),
            "--q",
            "0,-1.5707963267948966,1.5707963267948966,0,0,0",
            "--analyze"
        ])
    );
}

/// One path: IK rows give the same answers from the CLI batch, the library batch and single
/// solves seeded with the row seed — bit for bit, with a bad line in the middle (rows are the
/// non-blank lines, numbered from 0, so the rows after it keep their seeds) and a blank line.
/// The targets are far from the seed, so restarts (which the row seed drives) happen.
#[test]
fn cli_batch_equals_library_batch_and_single_calls() {
    use screwkit_solve::batch::{ik_batch, row_seed};
    use screwkit_solve::ik::{solve, IkOptions, IkStatus};
    let path = asset("ur5.urdf");
    let (_, kin) = chain("ur5.urdf", None);
    let n = kin.dof();
    let rows = 40;
    let qs = screwkit_solve::sample::configurations(&kin, rows, 1234);
    let mut input = String::new();
    let mut targets = Vec::new();
    for (k, q) in qs.chunks(n).enumerate() {
        let t = fk1(&kin, q).unwrap().to_homogeneous();
        let m: Vec<Vec<f64>> = (0..4)
            .map(|i| (0..4).map(|j| t[(i, j)]).collect())
            .collect();
        input.push_str(&format!("{{\"target\": {m:?}}}\n"));
        targets.extend((0..16).map(|i| t[(i / 4, i % 4)]));
        if k == 10 {
            input.push_str("{\"target\": [[1, 2]]}\n\n"); // a bad row, then a blank line
            targets.extend([f64::NAN; 16]);
        }
    }
    let o = run(
        &[
            "ik",
            &path,
            "--input",
            "-",
            "--timeout-ms",
            "0",
            "--random-seed",
            "5",
        ],
        Some(&input),
    );
    assert_eq!(o.code, 1, "the bad line fails the run: {}", o.stderr);
    let lines: Vec<Value> = o
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), rows + 1);
    assert_eq!(lines[11]["line"], 12);
    let opts = IkOptions {
        timeout: None,
        seed: 5,
        ..IkOptions::default()
    };
    let (mut q, mut st) = (
        vec![0.0; (rows + 1) * n],
        vec![IkStatus::default(); rows + 1],
    );
    let _bad_row = ik_batch(&kin, &targets, None, &opts, &mut q, &mut st, None).unwrap_err();
    let mut ws = screwkit_solve::Workspace::new(&kin);
    let mut restarted = 0;
    for (k, line) in lines.iter().enumerate() {
        if k == 11 {
            assert!(line["error"].as_str().unwrap().contains("4 rows of 4"));
            continue;
        }
        let cli_q: Vec<f64> = line["q"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(
            cli_q,
            q[k * n..(k + 1) * n],
            "row {k}: CLI vs library batch"
        );
        assert_eq!(line["iterations"], st[k].iterations);
        assert_eq!(line["restarts"], st[k].restarts);
        let t = screwkit_lie::Se3::from_row_major(&targets[16 * k..16 * (k + 1)], 1e-6).unwrap();
        let o = IkOptions {
            seed: row_seed(5, k),
            ..opts.clone()
        };
        let single = solve(&kin, &mut ws, &t, &kin.midpoint(), &o).unwrap();
        assert_eq!(single.q, cli_q, "row {k}: single call vs batch");
        assert_eq!(single.status, st[k]);
        restarted += usize::from(st[k].restarts > 0);
    }
    assert!(restarted > 0, "some rows restart, so the row seeds matter");
}

/// `draw` and `view` write to stdout with `-o -` (the same bytes as to a file), and fail in one
/// line naming what is wrong.
#[test]
fn draw_and_view_outputs_and_errors() {
    let ur5 = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/ur5.urdf");
    let svg = ok(&["draw", ur5, "--q", "0.1,0.2,0.3,0.4,0.5,0.6", "-o", "-"]);
    assert!(svg.starts_with("<?xml") && svg.contains("<svg") && svg.trim_end().ends_with("</svg>"));
    let file = std::env::temp_dir().join(format!("screwkit-cli-draw-{}.svg", std::process::id()));
    ok(&[
        "draw",
        ur5,
        "--q",
        "0.1,0.2,0.3,0.4,0.5,0.6",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), svg);
    let _ = std::fs::remove_file(&file);
    let page = ok(&["view", ur5, "-o", "-"]);
    assert!(page.starts_with("<!DOCTYPE html>"));
    // An unknown option word is a usage error (exit 2) listing the words, from the floor.
    let o = run(&["draw", ur5, "--view", "back", "-o", "-"], None);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert_eq!(o.stderr.lines().count(), 1, "{}", o.stderr);
    assert!(
        o.stderr.contains("invalid value 'back'")
            && o.stderr
                .contains("[possible values: iso, front, side, top, all]"),
        "{}",
        o.stderr
    );
    for (args, message) in [
        (
            vec!["draw", ur5, "--q", "1,2", "-o", "-"],
            "expected 6 joint values",
        ),
        (
            vec!["view", ur5, "-o", "/nonexistent/x.html"],
            "/nonexistent/x.html: cannot write",
        ),
        (
            vec!["draw", ur5, "--format", "json", "-o", "-"],
            "--format does not apply",
        ),
        (vec!["draw", "missing.urdf", "-o", "-"], "missing.urdf"),
    ] {
        let o = run(&args, None);
        assert_eq!(o.code, 1, "{args:?}");
        assert_eq!(o.stderr.lines().count(), 1, "{args:?}: {}", o.stderr);
        assert!(o.stderr.contains(message), "{args:?}: {}", o.stderr);
    }
}

/// `-` reads the robot from standard input; a xacro file is read directly, with package paths
/// and arguments; `screwkit xacro` prints the expansion.
#[test]
fn stdin_and_xacro_inputs() {
    let planar = asset("planar_3r.urdf");
    let text = std::fs::read_to_string(&planar).unwrap();
    let from_file = ok(&["fk", &planar, "--q", "0.1,0.2,0.3", "--format", "json"]);
    let o = run(
        &["fk", "-", "--q", "0.1,0.2,0.3", "--format", "json"],
        Some(&text),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert_eq!(o.stdout, from_file);
    let both = run(&["fk", "-", "--input", "-"], Some(&text));
    assert_eq!(both.code, 1);
    assert!(both.stderr.contains("cannot both come from standard input"));

    let cases = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../screwkit-model/tests/xacro_cases"
    );
    let includes = format!("{cases}/includes.xacro");
    let pkgs = format!("{cases}/pkgs");
    let urdf = ok(&["xacro", &includes, "--package-path", &pkgs]);
    assert!(
        urdf.contains("<joint name=\"wrist_joint\" type=\"continuous\">"),
        "{urdf}"
    );
    let t = json(&[
        "table",
        &includes,
        "--package-path",
        &pkgs,
        "--format",
        "json",
    ]);
    assert_eq!(t["joints"].as_array().unwrap().len(), 2);
    let missing = run(&["table", &includes], None);
    assert_eq!(missing.code, 1);
    assert!(
        missing.stderr.contains("$(find my_pkg): package not found"),
        "{}",
        missing.stderr
    );
    let expr = format!("{cases}/expressions.xacro");
    let with_tool = json(&["info", &expr, "--format", "json"]);
    let without = json(&[
        "info",
        &expr,
        "--xacro-arg",
        "with_tool:=false",
        "--format",
        "json",
    ]);
    assert_ne!(with_tool, without);
}

/// `info --chains` lists every root → leaf chain with its DoF, sensor-like leaves last; `ik`
/// takes `--weights`, and a short chain given a full pose is told what to do.
#[test]
fn chains_weights_and_the_short_chain_hint() {
    let urdf = r#"<robot name="r"><link name="base"/><link name="cam_optical_frame"/><link name="a"/><link name="tool"/>
      <joint name="cam" type="fixed"><parent link="base"/><child link="cam_optical_frame"/></joint>
      <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
        <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="j2" type="revolute"><parent link="a"/><child link="tool"/><origin xyz="1 0 0"/>
        <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>"#;
    let o = run(&["info", "-", "--chains", "--format", "json"], Some(urdf));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: Value = serde_json::from_str(&o.stdout).unwrap();
    let tips: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["tip"].as_str().unwrap())
        .collect();
    assert_eq!(tips, ["tool", "cam_optical_frame"]);
    assert_eq!(v[0]["dof"], 2);
    assert_eq!(v[1]["sensor_like"], true);

    let planar = asset("planar_3r.urdf");
    let full = run(
        &[
            "ik",
            &planar,
            "--target-xyz-rpy",
            "1,1,0,0.3,0.2,0.1",
            "--restarts",
            "2",
        ],
        None,
    );
    assert_eq!(full.code, 1);
    assert!(
        full.stderr.contains("try --position-only"),
        "{}",
        full.stderr
    );
    let masked = run(
        &[
            "ik",
            &planar,
            "--target-xyz-rpy",
            "1,1,0,0,0,0.3",
            "--weights",
            "0,0,1,1,1,0",
            "--format",
            "json",
        ],
        None,
    );
    assert_eq!(masked.code, 0, "{}", masked.stderr);
    let bad = run(
        &[
            "ik",
            &planar,
            "--target-xyz-rpy",
            "1,1,0,0,0,0",
            "--weights",
            "1,1",
        ],
        None,
    );
    assert!(
        bad.stderr.contains("--weights: needs 6 numbers"),
        "{}",
        bad.stderr
    );
}

/// Every kind of bad line gets its own error object with the right words; the others run.
#[test]
fn every_kind_of_bad_line_is_reported_alone() {
    let planar = asset("planar_3r.urdf");
    let mut input: Vec<u8> = Vec::new();
    input.extend_from_slice(b"{\"q\":[0.1,0.2,0.3]}\n");
    input.extend_from_slice(b"{\"q\":[0.1,\"a\",0.3]}\n");
    input.extend_from_slice(b"{\"q\":[0.1,null,0.3]}\n");
    input.extend_from_slice(b"{\"q\":[0.1,0.2]}\n");
    input.extend_from_slice(b"not json\n");
    input.extend_from_slice(b"\xff\xfe{\"q\":[1,2,3]}\n\n");
    input.extend_from_slice(b"{\"x\":1}\n");
    input.extend_from_slice(b"{\"q\":[0.3,0.2,0.1]}\n");
    let mut child = std::process::Command::new(BIN)
        .args(["fk", &planar, "--input", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(&input).unwrap();
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    let lines: Vec<Value> = String::from_utf8(o.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let expected: [(Option<&str>, usize); 8] = [
        (None, 1),
        (Some("\"q\"[1] is not a number: \"a\""), 2),
        (Some("\"q\"[1] is not a number: null"), 3),
        (Some("expected 3 joint values"), 4),
        (Some("invalid JSON"), 5),
        (Some("not valid UTF-8"), 6),
        (Some("missing \"q\""), 8),
        (None, 9),
    ];
    assert_eq!(lines.len(), expected.len());
    for (v, (err, line)) in lines.iter().zip(expected) {
        match err {
            None => assert!(v["pose"].is_array(), "{v}"),
            Some(e) => {
                assert!(v["error"].as_str().unwrap().contains(e), "{v} vs {e}");
                assert_eq!(v["line"], line, "{v}");
            }
        }
    }
    assert!(String::from_utf8(o.stderr)
        .unwrap()
        .contains("8 lines, 6 failed"));
}

/// `--tool` moves the tip frame (fk, table, ik); `ik --target-frame` takes the target in
/// another frame of the tree rigidly attached to the base, and names a joint that moves.
#[test]
fn tool_and_target_frame() {
    let ur5 = asset("ur5.urdf");
    let q = "0.1,-0.5,1.0,0.2,0.3,-0.4";
    let plain = json(&["fk", &ur5, "--q", q, "--format", "json"]);
    let tool = json(&[
        "fk",
        &ur5,
        "--q",
        q,
        "--tool",
        "0,0,0.1,0,0,0",
        "--format",
        "json",
    ]);
    // The tool is 0.1 m along the tip's z axis: p_tool = p + 0.1 R e_z.
    for r in 0..3 {
        let p = plain["pose"][r][3].as_f64().unwrap();
        let z = plain["pose"][r][2].as_f64().unwrap();
        let pt = tool["pose"][r][3].as_f64().unwrap();
        assert!((pt - (p + 0.1 * z)).abs() < 1e-14);
    }
    let table = json(&["table", &ur5, "--tool", "0,0,0.1,0,0,0", "--format", "json"]);
    assert_eq!(table["tip"], "tool0+tool");
    // IK of the tool frame reaches the tool pose.
    let m: Vec<String> = (0..4)
        .flat_map(|r| (0..4).map(move |c| (r, c)))
        .map(|(r, c)| format!("{:?}", tool["pose"][r][c].as_f64().unwrap()))
        .collect();
    let ik = json(&[
        "ik",
        &ur5,
        "--tool",
        "0,0,0.1,0,0,0",
        "--target-matrix",
        &m.join(","),
        "--format",
        "json",
    ]);
    assert_eq!(ik["converged"], true);
    // --target-frame: a target in a frame fixed 0.5 m above the base (a URDF made here).
    let urdf = std::fs::read_to_string(&ur5).unwrap().replacen(
        "</robot>",
        r#"<link name="table"/><joint name="table_mount" type="fixed"><parent link="base_link"/><child link="table"/><origin xyz="0 0 0.5"/></joint></robot>"#,
        1,
    );
    let o = run(
        &[
            "ik",
            "-",
            "--tip",
            "tool0",
            "--target-frame",
            "table",
            "--target-xyz-rpy",
            "0.4,0.1,-0.2,3.1,0,0",
            "--format",
            "json",
        ],
        Some(&urdf),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(v["converged"], true);
    let qs: Vec<String> = v["q"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| format!("{:?}", x.as_f64().unwrap()))
        .collect();
    let reached = run(
        &[
            "fk",
            "-",
            "--tip",
            "tool0",
            "--q",
            &qs.join(","),
            "--format",
            "json",
        ],
        Some(&urdf),
    );
    let r: Value = serde_json::from_str(&reached.stdout).unwrap();
    // In the base frame the target is 0.5 m higher than given in the table frame.
    assert!(
        (r["pose"][2][3].as_f64().unwrap() - 0.3).abs() < 1e-8,
        "{r}"
    );
    let moving = run(
        &[
            "ik",
            &asset("torso_two_arms.urdf"),
            "--tip",
            "left_hand",
            "--target-frame",
            "right_hand",
            "--target-xyz-rpy",
            "0,0,0,0,0,0",
        ],
        None,
    );
    assert_eq!(moving.code, 1);
    assert!(
        moving.stderr.contains("not rigidly attached"),
        "{}",
        moving.stderr
    );
}

/// `ik --all`: every analytic solution, nearest to the seed first; each reaches the target.
#[test]
fn ik_all_lists_every_solution() {
    let ur5 = asset("ur5.urdf");
    let q = "0.3,-1.0,1.4,-0.8,-1.2,0.4";
    let t = json(&["fk", &ur5, "--q", q, "--format", "json"]);
    let m: Vec<String> = (0..16)
        .map(|i| format!("{:?}", t["pose"][i / 4][i % 4].as_f64().unwrap()))
        .collect();
    let matrix = m.join(",");
    let args = [
        "ik",
        &ur5,
        "--target-matrix",
        &matrix,
        "--all",
        "--seed",
        q,
        "--format",
        "json",
    ];
    let v = json(&args);
    assert_eq!(v["family"], "three_parallel_two_intersecting");
    assert_eq!(v["reversed"], false);
    assert_eq!(v["exact"], true);
    let sols = v["solutions"].as_array().unwrap();
    assert!(sols.len() >= 8, "{}", sols.len());
    // One row per posture by default (the UR5's ±2π limits would give up to 2⁶ each).
    assert_eq!(v["postures"].as_u64().unwrap() as usize, sols.len());
    let every = json(&[&args[..], &["--representatives", "all"]].concat());
    assert!(every["solutions"].as_array().unwrap().len() > 4 * sols.len());
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_screwkit"))
        .args([
            "ik",
            &ur5,
            "--target-matrix",
            &m.join(","),
            "--all",
            "--representatives",
            "some",
        ])
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("representatives"));
    let first: Vec<f64> = serde_json::from_value(sols[0]["q"].clone()).unwrap();
    assert!(sols.iter().all(|s| s["exact"] == true));
    assert!(sols.iter().all(|s| s["residual"].as_f64().unwrap() < 1e-12));
    let want: Vec<f64> = q.split(',').map(|x| x.parse().unwrap()).collect();
    assert!(
        first.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-8),
        "{first:?}"
    );
    for s in sols.iter().take(16) {
        assert_reaches(&ur5, &s["q"], &t["pose"]);
    }
    // A 7R arm: joint 7 locked at the seed's value by default, or swept, or another joint.
    let panda = asset("panda.urdf");
    let seed = "0,-0.5,0,-2,0,1.6,0.8";
    let target = ["--target-xyz-rpy", "0.4,0.1,0.5,3.14,0,0"];
    let base = [
        "ik", &panda, target[0], target[1], "--all", "--format", "json",
    ];
    let v = json(&[&base[..], &["--seed", seed]].concat());
    assert_eq!(v["family"], "spherical_wrist_two_intersecting");
    assert_eq!(v["reversed"], true);
    assert_eq!(v["locked"]["index"], 6);
    assert_eq!(v["locked"]["joint"], "panda_joint7");
    assert_eq!(v["locked"]["values"][0], 0.8);
    let sols = v["solutions"].as_array().unwrap();
    assert!(!sols.is_empty());
    assert!(sols.iter().all(|s| s["q"][6] == 0.8 && s["exact"] == true));
    let v = json(&[&base[..], &["--lock", "panda_joint7", "--sweep", "5"]].concat());
    assert_eq!(v["locked"]["values"].as_array().unwrap().len(), 5);
    let sevens: std::collections::BTreeSet<String> = v["solutions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["q"][6].to_string())
        .collect();
    assert!(sevens.len() >= 2, "{sevens:?}");
    // Joints by name or by their index in q, counted from 0 as everywhere.
    let v = json(&[&base[..], &["--lock", "5=1.5"]].concat());
    assert_eq!(v["locked"]["joint"], "panda_joint6");
    assert_eq!(v["locked"]["index"], 5);
    let by_name = json(&[&base[..], &["--lock", "panda_joint6=1.5"]].concat());
    assert_eq!(by_name, v);
    for (args, msg) in [
        (&["--lock", "1", "--sweep", "0"][..], "at least one value"),
        (&["--lock", "wrist"][..], "no joint \"wrist\""),
        (&["--lock", "6=9"][..], "outside its limits"),
        (&["--lock", "7=0.1"][..], "joint index 7 out of range"),
        (
            &["--lock", "6=0.1", "--sweep", "3"][..],
            "exclude each other",
        ),
    ] {
        let o = run(&[&base[..], args].concat(), None);
        assert_eq!(o.code, 1, "{args:?}");
        assert!(o.stderr.contains(msg), "{args:?}: {}", o.stderr);
    }
}

/// `fk FILE --q q` (a separate call) gives `pose` to 1e-10.
fn assert_reaches(file: &str, q: &Value, pose: &Value) {
    let qs: Vec<String> = q
        .as_array()
        .unwrap()
        .iter()
        .map(|x| format!("{:?}", x.as_f64().unwrap()))
        .collect();
    let reached = json(&["fk", file, "--q", &qs.join(","), "--format", "json"]);
    for i in 0..16 {
        let (a, b) = (
            reached["pose"][i / 4][i % 4].as_f64().unwrap(),
            pose[i / 4][i % 4].as_f64().unwrap(),
        );
        assert!((a - b).abs() < 1e-10, "{q}: {a} vs {b}");
    }
}

#[test]
fn ik_all_by_the_arm_angle() {
    // The iiwa at the seed's arm angle: the seed's own configuration comes back first, every
    // solution reaches the target (fk, a separate call) and the report says the angle.
    let iiwa = asset("iiwa14.urdf");
    let seed = "0.3,0.6,-0.4,-1.2,0.5,0.8,-0.2";
    let t = json(&["fk", &iiwa, "--q", seed, "--format", "json"]);
    let pose = t["pose"].to_string();
    let input = format!("{{\"target\": {pose}, \"seed\": [{seed}]}}\n");
    let o = run(
        &["ik", &iiwa, "--all", "--lock", "arm_angle", "--input", "-"],
        Some(&input),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: Value = serde_json::from_str(o.stdout.lines().next().unwrap()).unwrap();
    assert!(v["locked"].is_null());
    let psi = v["arm_angle"]["values"][0].as_f64().unwrap();
    assert!(psi.is_finite());
    let sols = v["solutions"].as_array().unwrap();
    let first: Vec<f64> = sols[0]["q"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let want: Vec<f64> = seed.split(',').map(|x| x.parse().unwrap()).collect();
    assert!(first.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-7));
    for s in sols {
        assert_reaches(&iiwa, &s["q"], &t["pose"]);
    }
    // A given angle, in words; a sweep; an arm without a spherical shoulder and wrist.
    let o = run(
        &[
            "ik",
            &iiwa,
            "--all",
            "--lock",
            "arm_angle=0.25",
            "--seed",
            seed,
            "--target-xyz-rpy",
            "0.4,0.2,0.6,3.1,0.2,0.1",
        ],
        None,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("; at arm angle 0.25,"), "{}", o.stdout);
    let v = json(&[
        "ik",
        &iiwa,
        "--all",
        "--lock",
        "arm_angle",
        "--sweep",
        "6",
        "--format",
        "json",
        "--target-xyz-rpy",
        "0.4,0.2,0.6,3.1,0.2,0.1",
    ]);
    assert!(v["arm_angle"]["values"].as_array().unwrap().len() >= 6);
    let o = run(
        &[
            "ik",
            &asset("panda.urdf"),
            "--all",
            "--lock",
            "arm_angle=0.1",
            "--target-xyz-rpy",
            "0.4,0.2,0.6,3.1,0.2,0.1",
        ],
        None,
    );
    assert_eq!(o.code, 1);
    assert!(
        o.stderr.contains("no arm angle for this chain"),
        "{}",
        o.stderr
    );
    assert_eq!(o.stderr.lines().count(), 1);
}

#[test]
fn ik_all_batch_one_line_per_target() {
    let ur5 = asset("ur5.urdf");
    let qs = ["0.3,-1.0,1.4,-0.8,-1.2,0.4", "-1.1,-2.0,0.7,0.4,1.9,-2.5"];
    let mut input = String::new();
    for q in qs {
        let t = json(&["fk", &ur5, "--q", q, "--format", "json"]);
        input.push_str(&format!("{{\"target\": {}, \"seed\": [{q}]}}\n", t["pose"]));
    }
    input.push_str("{\"target\": [[1, 0]]}\n");
    let o = run(&["ik", &ur5, "--all", "--input", "-"], Some(&input));
    assert_eq!(o.code, 1, "{}", o.stderr);
    let lines: Vec<Value> = o
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 3);
    for (line, q) in lines.iter().zip(qs) {
        let want: Vec<f64> = q.split(',').map(|x| x.parse().unwrap()).collect();
        let first: Vec<f64> = serde_json::from_value(line["solutions"][0]["q"].clone()).unwrap();
        assert!(
            first.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-8),
            "{first:?}"
        );
        assert_eq!(line["exact"], true);
    }
    assert_eq!(lines[2]["line"], 3);
    assert!(lines[2]["error"].as_str().unwrap().contains("target"));
}

/// The screw table `table --format json|csv` writes is a robot file for every subcommand: the
/// JSON one gives the same robot bit for bit (FK and the table itself, mimic joints included),
/// the CSV one to its six decimals; a table that is not one is a one-line error.
#[test]
fn screw_tables_are_robot_files() {
    let dir = std::env::temp_dir().join(format!("screwkit-tables-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (file, tip) in ROBOTS {
        let urdf = asset(file);
        for format in ["json", "csv"] {
            let table = ok(&with_tip(vec!["table", &urdf, "--format", format], *tip));
            let path = dir.join(format!("{file}.{format}"));
            std::fs::write(&path, &table).unwrap();
            let path = path.to_str().unwrap();
            let (_, kin) = chain(file, *tip);
            // Every subcommand that takes a robot file takes the table.
            assert!(ok(&["info", path]).contains("tip"), "{file}");
            let q: Vec<f64> = (0..kin.dof()).map(|k| 0.3 - 0.17 * k as f64).collect();
            let q = q_arg(&q);
            let a = json(&with_tip(
                vec!["fk", &urdf, "--q", &q, "--format", "json"],
                *tip,
            ));
            let b = json(&["fk", path, "--q", &q, "--format", "json"]);
            let (ma, mb) = (matrix(&a["pose"]), matrix(&b["pose"]));
            if format == "json" {
                assert_eq!(ma, mb, "{file}");
                let again = ok(&["table", path, "--format", "json"]);
                let t0: Value = serde_json::from_str(&table).unwrap();
                let t1: Value = serde_json::from_str(&again).unwrap();
                assert_eq!(t0["joints"], t1["joints"], "{file}");
                assert_eq!(t0["home"], t1["home"], "{file}");
            } else {
                // Six decimals (three for a mimic joint's multiplier and offset).
                assert!((ma - mb).amax() < 1e-5, "{file}: {}", (ma - mb).amax());
                // The types come back (no limits in the CSV: revolute joints unbounded, so
                // continuous), mimic joints with their leader.
                let read: Value =
                    serde_json::from_str(&ok(&["table", path, "--format", "json"])).unwrap();
                let want = json(&with_tip(vec!["table", &urdf, "--format", "json"], *tip));
                let kinds = |t: &Value| -> Vec<String> {
                    t["joints"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|j| {
                            let k = j["type"].as_str().unwrap();
                            let k = if k == "revolute" { "continuous" } else { k };
                            format!("{k} {}", j["mimic"]["leader"])
                        })
                        .collect()
                };
                assert_eq!(kinds(&read), kinds(&want), "{file}");
            }
        }
    }
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        r#"{"home": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "joints": [{"name": "a", "screw": [0,0,2,0,0,0]}]}"#,
    )
    .unwrap();
    let o = run(&["fk", bad.to_str().unwrap(), "--q", "0"], None);
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert_eq!(o.stderr.lines().count(), 1, "{}", o.stderr);
    assert!(
        o.stderr
            .contains("bad.json: screw row 0 (joint \"a\"): ‖ω‖ = 2"),
        "{}",
        o.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
