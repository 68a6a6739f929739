//! MJCF robots from the command line: every command reads them as it reads URDF (by
//! content), and `screwkit urdf` writes one as URDF that gives the same FK.

use std::process::Command;

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn asset() -> String {
    format!(
        "{}/../../assets/mjcf/two_arm_constructs.xml",
        env!("CARGO_MANIFEST_DIR")
    )
}

fn run(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(BIN).args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn frames(file: &str, q: &str) -> Vec<(String, Vec<f64>)> {
    let (code, out, err) = run(&["--format", "json", "fk", file, "--q", q, "--all-links"]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    v["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let pose = f["pose"]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
                .collect();
            (f["name"].as_str().unwrap().to_string(), pose)
        })
        .collect()
}

#[test]
fn commands_read_mjcf_and_urdf_writes_the_same_robot() {
    let file = asset();
    let (code, out, err) = run(&["info", &file]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("Robot `two_arm_constructs`"), "{out}");
    let (code, out, err) = run(&["table", &file, "--tip", "left_hand"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("left_slide | prismatic"), "{out}");
    let dir = std::env::temp_dir().join(format!("sk-cli-mjcf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("two_arm.urdf");
    let urdf = urdf.to_str().unwrap();
    let (code, _, err) = run(&["urdf", &file, "-o", urdf]);
    assert_eq!(code, 0, "{err}");
    let q = "0.3,-0.4,0.5,-1.0,0.05,0.2,-0.7";
    let (a, b) = (frames(&file, q), frames(urdf, q));
    assert_eq!(a.len(), b.len());
    for ((na, pa), (nb, pb)) in a.iter().zip(&b) {
        assert_eq!(na, nb);
        for (x, y) in pa.iter().zip(pb) {
            assert!((x - y).abs() < 1e-12, "{na}: {x} vs {y}");
        }
    }
    let (code, _, err) = run(&["urdf", "/nonexistent.xml", "-o", "-"]);
    assert_eq!(code, 1);
    assert_eq!(err.lines().count(), 1, "{err}");
    let bad = dir.join("bad.xml");
    std::fs::write(
        &bad,
        "<mujoco>\n<worldbody>\n<body><joint type=\"ball\"/></body>\n</worldbody>\n</mujoco>",
    )
    .unwrap();
    let (code, _, err) = run(&["fk", bad.to_str().unwrap(), "--q", "0"]);
    assert_eq!(code, 1);
    assert!(
        err.contains("bad.xml:3") && err.contains("ball joints"),
        "{err}"
    );
    // What is read past that changes kinematics: a warning line, and the command still runs.
    let tendon = dir.join("tendon.xml");
    std::fs::write(
        &tendon,
        "<mujoco>\n<worldbody><body name=\"b\"><joint name=\"j\"/></body></worldbody>\n<tendon><fixed><joint joint=\"j\" coef=\"1\"/></fixed></tendon>\n</mujoco>",
    )
    .unwrap();
    let (code, out, err) = run(&["fk", tendon.to_str().unwrap(), "--q", "0.5"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("Pose of `b`"), "{out}");
    assert!(
        err.starts_with("screwkit: warning: ")
            && err.contains("tendon.xml: line 3: 1 tendon(s) read past"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
