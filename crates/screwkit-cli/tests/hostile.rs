//! Hostile input and everyday mistakes through the `screwkit` binary: closed pipes and full
//! disks, absurd numbers and sizes, crafted .npy and map files, outputs that are inputs, maps
//! that would lie. Each case is one line on stderr and a non-zero exit (or, for a closed
//! pipe, a quiet end), never a panic or a lost file. Each failed before its fix.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn asset(name: &str) -> String {
    format!("{}/../../assets/urdf/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn run(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(BIN).args(args).output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Exit code 1 and one line on stderr containing `says`.
fn fails_with(args: &[&str], says: &str) {
    let (code, _, err) = run(args);
    assert_eq!(code, Some(1), "{args:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    assert!(err.contains(says), "{args:?}: {err}");
    assert!(
        !err.contains("internal error") && !err.contains("panicked"),
        "{err}"
    );
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("screwkit-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

/// A serial chain of `n` revolute joints.
fn long_chain(n: usize) -> PathBuf {
    let path = tmp(&format!("long{n}.urdf"));
    let mut t = String::from("<robot name=\"long\">");
    for i in 0..=n {
        t.push_str(&format!("<link name=\"l{i}\"/>"));
    }
    for i in 0..n {
        t.push_str(&format!(
            "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/><origin xyz=\"0 0 0.01\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\"/></joint>\n",
            i + 1
        ));
    }
    t.push_str("</robot>");
    std::fs::write(&path, t).unwrap();
    path
}

/// A float64 .npy of `shape` whose header may lie about its data.
fn npy(path: &Path, shape_text: &str, data: &[f64]) {
    let bytes = screwkit_testkit::npy_bytes("<f8", false, shape_text, data);
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn a_closed_pipe_ends_quietly_and_a_full_disk_is_an_error() {
    let file = long_chain(3000);
    for args in [
        vec!["info", file.to_str().unwrap()],
        vec!["table", file.to_str().unwrap()],
    ] {
        let mut child = Command::new(BIN)
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Read one line (as `head -1`), then close the pipe.
        let mut out = child.stdout.take().unwrap();
        let mut first = [0u8; 16];
        out.read_exact(&mut first).unwrap();
        drop(out);
        let status = child.wait().unwrap();
        let mut err = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        assert!(status.success(), "{args:?}: {status:?} {err}");
        assert!(err.is_empty(), "{args:?}: {err}");
    }
    #[cfg(target_os = "linux")]
    {
        let full = std::fs::File::create("/dev/full").unwrap();
        let out = Command::new(BIN)
            .args(["table", &asset("ur5.urdf")])
            .stdout(full)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(
            err.contains("cannot write the output") && err.contains("No space left"),
            "{err}"
        );
    }
}

#[test]
fn info_on_a_30000_link_chain() {
    let file = long_chain(30_000);
    let (code, out, err) = run(&["info", file.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    // Linear output: deep levels show their depth instead of 30,000 guide lines.
    assert!(out.len() < 20_000_000, "{} bytes", out.len());
    assert!(
        out.contains("⋮ (depth 30000) └── l30000 (j29999: revolute)"),
        "tail missing"
    );
}

#[test]
fn absurd_numbers_and_sizes() {
    let ur5 = asset("ur5.urdf");
    let panda = asset("panda.urdf");
    let target = ["--target-xyz-rpy", "0.4,0.1,0.5,3.14159,0,0.3"];
    for t in ["--timeout-ms=inf", "--timeout-ms=nan", "--timeout-ms=-1"] {
        let mut a = vec!["ik", panda.as_str(), t];
        a.extend(target);
        fails_with(&a, "--timeout-ms: expected a finite number of milliseconds");
    }
    let mut a = vec!["ik", panda.as_str(), "--timeout-ms", "1e300"];
    a.extend(target);
    let (code, out, err) = run(&a);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("converged          yes"), "{out}");

    let mut a = vec!["ik", panda.as_str(), "--all", "--sweep", "1000000000000"];
    a.extend(target);
    fails_with(&a, "more than 100000");
    fails_with(
        &[
            "reach",
            &ur5,
            "--resolution",
            "1e-3",
            "-o",
            &s(&tmp("r.npz")),
        ],
        "voxels is more than a map may have",
    );
    fails_with(
        &[
            "reach",
            &ur5,
            "--orientations",
            "1000000000000",
            "-o",
            &s(&tmp("r.npz")),
        ],
        "orientations per voxel is more than",
    );
    let (code, _, err) = run(&["bench", &ur5, "--n", "1000000000000"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--n"), "{err}");
    assert!(!tmp("r.npz").exists());
}

#[test]
fn crafted_npy_headers() {
    let ur5 = asset("ur5.urdf");
    let (input, output) = (tmp("crafted.npy"), tmp("crafted-out.npy"));
    npy(&input, "(1000000000000, 6)", &[0.0; 12]);
    fails_with(
        &["fk", &ur5, "--input", &s(&input), "--output", &s(&output)],
        "the header says shape",
    );
    assert!(!output.exists());
    npy(&input, "(4611686018427387904, 4611686018427387904)", &[]);
    fails_with(
        &["fk", &ur5, "--input", &s(&input), "--output", &s(&output)],
        "more elements than any file can hold",
    );
    // A header length of 4 GB (version 2.0's u32).
    let mut bytes = b"\x93NUMPY\x02\x00".to_vec();
    bytes.extend_from_slice(&u32::MAX.to_le_bytes());
    std::fs::write(&input, bytes).unwrap();
    fails_with(
        &["fk", &ur5, "--input", &s(&input), "--output", &s(&output)],
        "a header of 4294967295 bytes",
    );
    assert!(!output.exists());
}

#[test]
fn outputs_never_destroy_inputs_or_earlier_results() {
    let ur5 = asset("ur5.urdf");
    let big = tmp("big.npy");
    npy(&big, "(2, 6)", &[0.1; 12]);
    let before = std::fs::read(&big).unwrap();
    fails_with(
        &["fk", &ur5, "--input", &s(&big), "--output", &s(&big)],
        "is also an input",
    );
    assert_eq!(std::fs::read(&big).unwrap(), before);
    // Through the derived status path.
    let t = tmp("t.npy");
    let status = tmp("t.status.npy");
    npy(&status, "(1, 4, 4)", &[0.0; 16]);
    let before = std::fs::read(&status).unwrap();
    fails_with(
        &["ik", &ur5, "--input", &s(&status), "--output", &s(&t)],
        "is also an input",
    );
    assert_eq!(std::fs::read(&status).unwrap(), before);
    assert!(!t.exists());
    // A batch that fails (the data ends early) leaves the previous result as it was.
    let good = tmp("good.npy");
    let out = tmp("out.npy");
    npy(&good, "(2, 6)", &[0.1; 12]);
    let (code, _, err) = run(&["fk", &ur5, "--input", &s(&good), "--output", &s(&out)]);
    assert_eq!(code, Some(0), "{err}");
    let result = std::fs::read(&out).unwrap();
    let short = tmp("short.npy");
    npy(&short, "(3, 6)", &[0.1; 12]);
    fails_with(
        &["fk", &ur5, "--input", &s(&short), "--output", &s(&out)],
        "the header says shape",
    );
    assert_eq!(std::fs::read(&out).unwrap(), result);
    // No temporary files are left beside it.
    let left: Vec<_> = std::fs::read_dir(out.parent().unwrap())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    // /dev/null as the output takes the status too (no /dev/null.status.npy).
    #[cfg(unix)]
    {
        let targets = tmp("targets.npy");
        let mut m = vec![0.0; 16];
        for (i, v) in [
            -1.0, 0.0, 0.0, 0.81725, 0.0, 0.0, 1.0, 0.19145, 0.0, 1.0, 0.0, -0.005491, 0.0, 0.0,
            0.0, 1.0,
        ]
        .iter()
        .enumerate()
        {
            m[i] = *v;
        }
        npy(&targets, "(1, 4, 4)", &m);
        let (code, _, err) = run(&["ik", &ur5, "--input", &s(&targets), "--output", "/dev/null"]);
        assert_eq!(code, Some(0), "{err}");
        assert!(!Path::new("/dev/null.status.npy").exists());
    }
}

/// A small UR5 map (or shard) written by the CLI.
fn map(urdf: &str, name: &str, shard: Option<&str>) -> String {
    let out = s(&tmp(name));
    let mut a = vec![
        "reach",
        urdf,
        "--resolution",
        "0.3",
        "--orientations",
        "4",
        "-o",
        &out,
    ];
    if let Some(sh) = shard {
        a.extend(["--shard", sh]);
    }
    let (code, _, err) = run(&a);
    assert_eq!(code, Some(0), "{err}");
    out
}

#[test]
fn maps_that_would_lie_are_refused() {
    let ur5 = asset("ur5.urdf");
    let s0 = map(&ur5, "s0.npz", Some("0/2"));
    let s1 = map(&ur5, "s1.npz", Some("1/2"));
    let before = std::fs::read(&s0).unwrap();
    fails_with(&["reach", "merge", "-o", &s0, &s0, &s1], "is also an input");
    assert_eq!(std::fs::read(&s0).unwrap(), before);

    // A map build that fails leaves the existing map untouched.
    let whole = map(&ur5, "whole.npz", None);
    let kept = std::fs::read(&whole).unwrap();
    fails_with(
        &["reach", &ur5, "--resolution", "1e-3", "-o", &whole],
        "voxels",
    );
    assert_eq!(std::fs::read(&whole).unwrap(), kept);

    // One flipped byte in the stored data: the zip CRC catches it.
    let mut bad = std::fs::read(&s1).unwrap();
    let at = bad.windows(4).position(|w| w == b"NUMP").unwrap() + 200;
    bad[at] ^= 0x55;
    let bad_path = s(&tmp("bad.npz"));
    std::fs::write(&bad_path, &bad).unwrap();
    fails_with(
        &["reach", "merge", "-o", &s(&tmp("m.npz")), &s0, &bad_path],
        "damaged",
    );

    // The same robot name with other joint limits: a shard of another robot.
    let text = std::fs::read_to_string(&ur5).unwrap();
    let other = tmp("ur5_other.urdf");
    let changed = text.replacen("upper=\"6.283185307179586\"", "upper=\"1.0\"", 1);
    let changed = if changed == text {
        text.replacen("upper=\"", "upper=\"0.5", 1)
    } else {
        changed
    };
    assert_ne!(changed, text);
    std::fs::write(&other, changed).unwrap();
    let o1 = map(&s(&other), "o1.npz", Some("1/2"));
    fails_with(
        &["reach", "merge", "-o", &s(&tmp("m2.npz")), &s0, &o1],
        "another map",
    );
}

#[test]
fn a_map_whose_voxel_range_has_one_value() {
    let ur5 = asset("ur5.urdf");
    let good = map(&ur5, "vr.npz", None);
    // Copy every entry but voxel_range, which gets one value.
    let mut z = screwkit_service::io::npz::NpzReader::open(&good).unwrap();
    let meta = z.text("meta").unwrap();
    let path = s(&tmp("vr-bad.npz"));
    let mut w = screwkit_service::io::npz::NpzWriter::create(&path).unwrap();
    for name in ["index", "best_manipulability", "centres"] {
        let (shape, v) = z.f64_array(name).unwrap();
        w.f64_array(name, &shape, &v).unwrap();
    }
    w.i64_array("voxel_range", &[1], &[3]).unwrap();
    w.text("meta", &meta).unwrap();
    w.finish().unwrap();
    fails_with(
        &["reach", "merge", "-o", &s(&tmp("vr-m.npz")), &path],
        "voxel_range [3] is not a range",
    );
}

#[test]
fn endless_and_overlong_batch_lines() {
    let ur5 = asset("ur5.urdf");
    // /dev/zero: no line break in 64 MiB, the run stops with one line.
    #[cfg(unix)]
    fails_with(
        &["fk", &ur5, "--input", "/dev/zero"],
        "without a line break",
    );
    // One overlong line is that line's error; the others are answered; a BOM is skipped.
    let f = tmp("lines.jsonl");
    let long = format!("{{\"q\":[{}0]}}", "0,".repeat(600_000));
    std::fs::write(
        &f,
        format!("\u{feff}{{\"q\":[0,0,0,0,0,0]}}\n{long}\n{{\"q\":[0,0,0,0,0,0]}}\n"),
    )
    .unwrap();
    let (code, out, err) = run(&["fk", &ur5, "--input", &s(&f)]);
    assert_eq!(code, Some(1), "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].starts_with("{\"pose\""), "{}", lines[0]);
    assert!(
        lines[1].contains("longer than 1 MiB") && lines[1].contains("\"line\":2"),
        "{}",
        lines[1]
    );
    assert!(lines[2].starts_with("{\"pose\""));
}

#[test]
fn info_describes_the_chain_asked_for_and_suggests_names() {
    let torso = asset("torso_two_arms.urdf");
    let (code, out, err) = run(&["info", &torso, "--tip", "left_hand"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("Chain: pelvis → left_hand (4 DoF"), "{out}");
    assert!(out.contains("IK family: "), "{out}");
    // An unknown tip suggests the closest names instead of listing every link.
    let file = long_chain(40);
    fails_with(
        &["info", file.to_str().unwrap(), "--tip", "l4O"],
        "did you mean \"l4\", \"l40\"",
    );
    fails_with(
        &["info", file.to_str().unwrap(), "--tip", "l4O"],
        "41 links in all",
    );
}

#[test]
#[cfg(unix)]
fn ctrl_c_leaves_no_file_behind() {
    let ur5 = asset("ur5.urdf");
    interrupt_reach(
        "interrupted.npz",
        &[&ur5, "--resolution", "0.02", "--orientations", "50"],
    );
    // A map clear of contact (numerical IK steering away from the body's pairs) stops too.
    let humanoid = asset("humanoid.urdf");
    interrupt_reach(
        "interrupted-clear.npz",
        &[
            &humanoid,
            "--tip",
            "left_hand",
            "--resolution",
            "0.03",
            "--orientations",
            "50",
            "--avoid-collisions",
        ],
    );
}

/// Runs `screwkit reach ARGS -o NAME` over a previous file, sends SIGINT once the build has
/// started (its temporary file exists): exit 130, no temporary file left, the previous file
/// intact.
#[cfg(unix)]
fn interrupt_reach(name: &str, args: &[&str]) {
    let out = tmp(name);
    std::fs::write(&out, b"the previous map").unwrap();
    let mut child = Command::new(BIN)
        .arg("reach")
        .args(args)
        .args(["-o", &s(&out)])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the temporary file exists (the build has started), then Ctrl-C.
    let dir = out.parent().unwrap().to_path_buf();
    let prefix = format!(".{name}.");
    let tmp_exists = || {
        std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .any(|e| e.file_name().to_string_lossy().starts_with(&prefix))
    };
    let start = std::time::Instant::now();
    while !tmp_exists() && start.elapsed() < std::time::Duration::from_secs(30) {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(tmp_exists(), "{name}: the build never started");
    // Into the build (it runs for seconds), still running when interrupted.
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert!(
        child.try_wait().unwrap().is_none(),
        "{name}: ended too soon"
    );
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{name}: {status:?}");
    assert!(!tmp_exists(), "{name}: a temporary file stayed behind");
    assert_eq!(std::fs::read(&out).unwrap(), b"the previous map");
}

#[test]
#[cfg(unix)]
fn an_endless_robot_on_standard_input() {
    for cmd in ["info", "xacro"] {
        let out = Command::new(BIN)
            .args([cmd, "-"])
            .stdin(std::fs::File::open("/dev/zero").unwrap())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{cmd}: {err}");
        assert!(
            err.contains("<stdin>: too large: more than 64 MiB"),
            "{cmd}: {err}"
        );
    }
}

/// A file with a byte-order mark and one declared Latin-1 load as the plain file: the floor's
/// one decoding rule (Python's `test_floor.py` holds the package to the same answers).
#[test]
fn bom_and_latin1_files_load_as_the_plain_file() {
    let ur5 = asset("ur5.urdf");
    let text = std::fs::read_to_string(&ur5).unwrap();
    let body = match text.strip_prefix("<?xml") {
        Some(rest) => rest.split_once("?>").unwrap().1.to_string(),
        None => text.clone(),
    };
    let bom = tmp("bom.urdf");
    std::fs::write(&bom, [b"\xef\xbb\xbf".as_slice(), text.as_bytes()].concat()).unwrap();
    let latin = tmp("latin.urdf");
    let mut bytes = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>".to_vec();
    for c in body.replace("name=\"ur5\"", "name=\"ur5_\u{e9}\"").chars() {
        bytes.push(u8::try_from(u32::from(c)).unwrap());
    }
    std::fs::write(&latin, bytes).unwrap();
    let q = "0.1,-0.5,1,0.2,0.3,-0.4";
    let fk = |p: &str| run(&["fk", p, "--q", q, "--format", "json"]);
    let (code, plain, err) = fk(&ur5);
    assert_eq!(code, Some(0), "{err}");
    for p in [&bom, &latin] {
        let (code, out, err) = fk(&s(p));
        assert_eq!(code, Some(0), "{err}");
        assert_eq!(out, plain);
    }
    let (_, info, _) = run(&["info", &s(&latin), "--format", "json"]);
    assert!(info.contains("\"robot\":\"ur5_\u{e9}\""), "{info}");
}

/// Issue 44, item 1: no output may be written over a file the run read as input — the robot's
/// file, by any name (`./x`, a hard link, a symbolic link), or a file it includes — and a
/// command that writes two files refuses before writing the first.
#[test]
fn no_output_overwrites_a_robot_file_or_an_include() {
    let dir = tmp("own");
    std::fs::create_dir_all(&dir).unwrap();
    let robot = dir.join("ur5.urdf");
    std::fs::copy(asset("ur5.urdf"), &robot).unwrap();
    let original = std::fs::read(&robot).unwrap();
    let hard = dir.join("hard.urdf");
    let soft = dir.join("soft.urdf");
    let _ = std::fs::remove_file(&hard);
    let _ = std::fs::remove_file(&soft);
    std::fs::hard_link(&robot, &hard).unwrap();
    std::os::unix::fs::symlink(&robot, &soft).unwrap();
    let dotted = format!("{}/./ur5.urdf", s(&dir));
    let r = s(&robot);
    for out in [r.clone(), dotted, s(&hard), s(&soft)] {
        for args in [
            vec!["urdf", &r, "-o", &out],
            vec!["draw", &r, "-o", &out],
            vec!["view", &r, "-o", &out],
            vec!["table", &r, "-o", &out],
        ] {
            let (code, _, err) = run(&args);
            if args[0] == "table" && code == Some(2) {
                continue; // `table` writes to standard output only
            }
            assert_eq!(code, Some(1), "{args:?}: {err}");
            assert!(err.contains("is an input of this run"), "{args:?}: {err}");
            assert_eq!(err.trim().lines().count(), 1, "{err}");
            assert_eq!(std::fs::read(&robot).unwrap(), original, "{args:?}");
        }
    }
    // A file the robot includes (MJCF <include>).
    let part = dir.join("part.xml");
    std::fs::write(
        &part,
        r#"<mujoco><body name="b" pos="0 0 1"><joint name="j" axis="0 0 1"/></body></mujoco>"#,
    )
    .unwrap();
    let main = dir.join("main.xml");
    std::fs::write(
        &main,
        r#"<mujoco model="m"><worldbody><include file="part.xml"/></worldbody></mujoco>"#,
    )
    .unwrap();
    let part_before = std::fs::read(&part).unwrap();
    fails_with(
        &["urdf", &s(&main), "-o", &s(&part)],
        "is an input of this run",
    );
    assert_eq!(std::fs::read(&part).unwrap(), part_before);
    // reach: the picture over the robot's file is refused before the map is computed.
    let map_out = dir.join("refused.npz");
    fails_with(
        &[
            "reach",
            &r,
            "--resolution",
            "0.3",
            "--orientations",
            "4",
            "-o",
            &s(&map_out),
            "--svg",
            &r,
        ],
        "is an input of this run",
    );
    assert!(!map_out.exists());
    assert_eq!(std::fs::read(&robot).unwrap(), original);
    // reach merge: the picture over a shard.
    let s0 = map(&asset("ur5.urdf"), "own-s0.npz", Some("0/2"));
    let s1 = map(&asset("ur5.urdf"), "own-s1.npz", Some("1/2"));
    let shard_before = std::fs::read(&s0).unwrap();
    let merged = s(&dir.join("merged.npz"));
    fails_with(
        &["reach", "merge", "-o", &merged, "--svg", &s0, &s0, &s1],
        "is also an input",
    );
    assert_eq!(std::fs::read(&s0).unwrap(), shard_before);
    assert!(!Path::new(&merged).exists());
    // view: the page over the motion it plays, or over the scene it draws, by any name.
    let motion = dir.join("motion.json");
    std::fs::write(&motion, "[[0,0,0,0,0,0],[0.1,0,0,0,0,0]]").unwrap();
    let scene = dir.join("scene.json");
    std::fs::write(
        &scene,
        r#"{"obstacles": [{"name": "t", "shape": "box", "size": [1, 1, 0.1], "xyz": [0, 0, -0.2]}]}"#,
    )
    .unwrap();
    let (motion_before, scene_before) = (
        std::fs::read(&motion).unwrap(),
        std::fs::read(&scene).unwrap(),
    );
    for out in [s(&motion), format!("{}/./motion.json", s(&dir))] {
        fails_with(
            &["view", &r, "--motion", &s(&motion), "-o", &out],
            "is also an input",
        );
    }
    fails_with(
        &["view", &r, "--obstacles", &s(&scene), "-o", &s(&scene)],
        "is also an input",
    );
    assert_eq!(std::fs::read(&motion).unwrap(), motion_before);
    assert_eq!(std::fs::read(&scene).unwrap(), scene_before);
    // Writing elsewhere still works.
    let (code, _, err) = run(&["urdf", &r, "-o", &s(&dir.join("copy.urdf"))]);
    assert_eq!(code, Some(0), "{err}");
}

/// Issue 44, item 14: `exp --theta nan` printed a pose of nulls with exit 0.
#[test]
fn exp_of_a_non_finite_angle_is_an_error() {
    for theta in ["nan", "inf", "-inf"] {
        fails_with(
            &["exp", "--twist", "0,0,1,0,0,0", "--theta", theta],
            "expected a finite number",
        );
    }
    fails_with(
        &["exp", "--twist", "0,0,1e300,0,0,0", "--theta", "1e300"],
        "overflows",
    );
}

/// Issue 44, item 19: `view` of a 100,000-link tree (each joint's child link was searched over
/// every link: 30 s and 1.1 GB); every joint still names its own child link.
#[test]
fn view_of_a_hundred_thousand_links() {
    let n = 100_000;
    let path = tmp("star100k.urdf");
    let mut t = String::from("<robot name=\"star\"><link name=\"hub\"/>");
    for i in 0..n {
        t.push_str(&format!(
            "<link name=\"s{i}\"/><joint name=\"j{i}\" type=\"revolute\"><parent link=\"hub\"/><child link=\"s{i}\"/><origin xyz=\"0.1 0 0\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\"/></joint>"
        ));
    }
    t.push_str("</robot>");
    std::fs::write(&path, t).unwrap();
    let out = tmp("star100k.html");
    let (code, _, err) = run(&["view", &s(&path), "-o", &s(&out)]);
    assert_eq!(code, Some(0), "{err}");
    let page = std::fs::read_to_string(&out).unwrap();
    for k in [0, 1, 54_321, n - 1] {
        assert!(
            page.contains(&format!("\"link\":{},\"multiplier\"", k + 1))
                || page.contains(&format!("\"link\":{}}}", k + 1)),
            "joint {k}"
        );
    }
    let _ = std::fs::remove_file(&out);
}
