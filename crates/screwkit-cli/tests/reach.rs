//! `screwkit reach`: a whole map equals its shards merged (byte for byte, in any order), the
//! SVG slices are written, the summary names the counts, and bad arguments end in one line.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn ur5() -> String {
    format!("{}/../../assets/urdf/ur5.urdf", env!("CARGO_MANIFEST_DIR"))
}

fn run(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(BIN).args(args).output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn shards_merge_into_the_whole_map() {
    let dir = std::env::temp_dir().join(format!("screwkit-cli-reach-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = |n: &str| dir.join(n).to_string_lossy().into_owned();
    let spec = ["--resolution", "0.25", "--orientations", "6"];
    let ur5 = ur5();
    let mut whole = vec!["reach", ur5.as_str()];
    whole.extend(spec);
    let (whole_npz, whole_svg) = (p("whole.npz"), p("whole.svg"));
    whole.extend(["-o", &whole_npz, "--svg", &whole_svg]);
    let (ok, out, err) = run(&whole);
    assert!(ok, "{err}");
    // "N voxels × 6 orientations = 6N poses (… solved in reach), R reached (x %), …"
    assert!(
        out.contains("× 6 orientations") && out.contains("analytic IK"),
        "{out}"
    );
    let mut shards = Vec::new();
    for i in [1, 0] {
        let name = p(&format!("s{i}.npz"));
        let shard = format!("{i}/2");
        let mut a = vec!["reach", ur5.as_str()];
        a.extend(spec);
        a.extend(["--shard", &shard, "-o", &name]);
        let (ok, out, err) = run(&a);
        assert!(ok && out.contains(&format!("shard {i}/2")), "{out}{err}");
        shards.push(name);
    }
    let merged = p("merged.npz");
    let (ok, out, err) = run(&["reach", "merge", "-o", &merged, &shards[0], &shards[1]]);
    assert!(ok && out.contains("2 shards"), "{out}{err}");
    assert!(std::fs::read(&merged).unwrap() == std::fs::read(&whole_npz).unwrap());
    let svg = std::fs::read_to_string(&whole_svg).unwrap();
    assert!(svg.starts_with("<svg") && svg.matches("class=\"panel\"").count() == 3);

    // Small maps as text: one CSV line per voxel, JSON per voxel and pose, equal to the .npz.
    let map = screwkit_reach::read(&whole_npz).unwrap();
    let (csv, json) = (p("whole.csv"), p("whole.json"));
    for out in [&csv, &json] {
        let mut a = vec!["reach", ur5.as_str()];
        a.extend(spec);
        a.extend(["-o", out.as_str()]);
        let (ok, _, err) = run(&a);
        assert!(ok, "{err}");
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "x,y,z,index,best_manipulability");
    assert_eq!(lines.len(), map.index.len() + 1);
    for (line, want) in lines[1..].iter().zip(&map.index) {
        let index: f64 = line.split(',').nth(3).unwrap().parse().unwrap();
        assert_eq!(index, *want);
    }
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let voxels = v["voxels"].as_array().unwrap();
    assert_eq!(voxels.len(), map.index.len());
    for (vox, want) in voxels.iter().zip(&map.index) {
        let poses = vox["pose_manipulability"].as_array().unwrap();
        assert_eq!(poses.len(), 6);
        let reached = poses.iter().filter(|x| !x.is_null()).count();
        assert_eq!(reached as f64 / 6.0, *want);
    }
    assert!(!std::path::Path::new(&format!("{csv}.npz")).exists());

    // One line, non-zero exit, for each mistake.
    for (args, says) in [
        (
            vec!["reach", ur5.as_str(), "--shard", "2/2", "-o", "x.npz"],
            "--shard",
        ),
        (
            vec!["reach", ur5.as_str(), "--mode", "sideways", "-o", "x.npz"],
            "--mode",
        ),
        (
            vec!["reach", ur5.as_str(), "--bounds", "1,2,3", "-o", "x.npz"],
            "--bounds",
        ),
        (
            vec![
                "reach",
                ur5.as_str(),
                "--shard",
                "0/2",
                "--svg",
                "a.svg",
                "-o",
                "x.npz",
            ],
            "--svg",
        ),
        (
            vec!["reach", "merge", "-o", "x.npz", "/nonexistent/s0.npz"],
            "/nonexistent/s0.npz",
        ),
        (
            vec!["reach", "merge", "-o", &p("y.npz"), &shards[0]],
            "missing or twice",
        ),
    ] {
        let (ok, _, err) = run(&args);
        assert!(!ok, "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
}
