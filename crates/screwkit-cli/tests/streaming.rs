//! Batch mode streams: bounded memory on a large input, answers before the input ends (a
//! program can keep one `screwkit` open as a co-process), every kind of bad line reported
//! alone, chunked IK equal to one library batch, and the trajectory mode.

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use screwkit_model::load_chain;
use screwkit_solve::batch::{ik_batch, ik_path};
use screwkit_solve::ik::{IkOptions, IkStatus};
use screwkit_solve::{fk::fk, Kinematics, Workspace};
use screwkit_testkit::{bundled, Sampler};
use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn scratch(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("screwkit-stream-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The peak resident memory (VmHWM, kB) of a running process, if it is still there.
fn peak_kb(pid: u32) -> Option<u64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    s.lines()
        .find(|l| l.starts_with("VmHWM:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
}

/// 3 M lines through `fk --input`: the process never holds more than 64 MB (the input file
/// alone is 63 MB), and every line is answered.
#[test]
fn three_million_lines_in_bounded_memory() {
    let dir = scratch("big");
    let input = dir.join("q.jsonl");
    {
        let mut f = std::io::BufWriter::new(std::fs::File::create(&input).unwrap());
        for k in 0..3_000_000u32 {
            writeln!(f, "{{\"q\":[{},0.2,-0.3]}}", f64::from(k % 1000) * 1e-3).unwrap();
        }
    }
    let mut child = Command::new(BIN)
        .args([
            "fk",
            &bundled("planar_3r.urdf"),
            "--input",
            input.to_str().unwrap(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = child.id();
    let stdout = child.stdout.take().unwrap();
    let counter = std::thread::spawn(move || BufReader::new(stdout).lines().count());
    let mut peak = 0;
    while child.try_wait().unwrap().is_none() {
        if let Some(kb) = peak_kb(pid) {
            peak = peak.max(kb);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let lines = counter.join().unwrap();
    assert!(child.wait().unwrap().success());
    assert_eq!(lines, 3_000_000);
    assert!(peak > 0, "no memory reading");
    eprintln!("3 M lines: peak resident memory {peak} kB");
    assert!(peak < 64 * 1024, "peak resident memory {peak} kB");
    let _ = std::fs::remove_dir_all(dir);
}

/// One line in, its answer out, before the next line is written: the co-process use.
#[test]
fn answers_come_before_the_input_ends() {
    let mut child = Command::new(BIN)
        .args([
            "fk",
            &bundled("planar_3r.urdf"),
            "--input",
            "-",
            "--format",
            "json",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    for q in ["0.1,0.2,0.3", "0.3,0.2,0.1", "0,0,0"] {
        writeln!(stdin, "{{\"q\":[{q}]}}").unwrap();
        stdin.flush().unwrap();
        let t0 = Instant::now();
        let mut line = String::new();
        out.read_line(&mut line).unwrap();
        assert!(t0.elapsed() < Duration::from_secs(5));
        let v: Value = serde_json::from_str(&line).unwrap();
        let want: Vec<f64> = q.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(
            serde_json::from_value::<Vec<f64>>(v["q"].clone()).unwrap(),
            want
        );
    }
    drop(stdin);
    assert!(child.wait().unwrap().success());
}

/// IK over more lines than one chunk equals one library batch over all of them, bit for bit
/// (row k restarts from row_seed(seed, k) whatever chunk it lands in).
#[test]
fn chunked_ik_equals_one_library_batch() {
    let chain = load_chain(bundled("ur5.urdf"), None, None).unwrap();
    let kin = Kinematics::new(&chain);
    let mut ws = Workspace::new(&kin);
    let mut rng = Sampler::new(5);
    let rows = 5000;
    let mut targets = Vec::with_capacity(rows * 16);
    let mut text = String::new();
    for _ in 0..rows {
        let t = fk(&kin, &mut ws, &rng.config(&kin))
            .unwrap()
            .to_homogeneous();
        let m: Vec<Vec<f64>> = (0..4)
            .map(|r| (0..4).map(|c| t[(r, c)]).collect())
            .collect();
        targets.extend(m.iter().flatten());
        text.push_str(&format!(
            "{{\"target\":{}}}\n",
            serde_json::to_string(&m).unwrap()
        ));
    }
    let dir = scratch("ik");
    let input = dir.join("t.jsonl");
    std::fs::write(&input, &text).unwrap();
    let out = Command::new(BIN)
        .args([
            "ik",
            &bundled("ur5.urdf"),
            "--input",
            input.to_str().unwrap(),
            "--format",
            "json",
        ])
        .output()
        .unwrap();
    let mut q = vec![0.0; rows * 6];
    let mut status = vec![IkStatus::default(); rows];
    ik_batch(
        &kin,
        &targets,
        None,
        &IkOptions::default(),
        &mut q,
        &mut status,
        None,
    )
    .unwrap();
    let lines: Vec<Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), rows);
    for (k, v) in lines.iter().enumerate() {
        let got: Vec<f64> = serde_json::from_value(v["q"].clone()).unwrap();
        assert_eq!(got, q[k * 6..(k + 1) * 6], "row {k}");
        assert_eq!(v["converged"], status[k].converged);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// `--sequential`: a smooth straight-line path, each line seeded with the previous answer,
/// equals the library's ik_path and never jumps between branches.
#[test]
fn sequential_mode_follows_a_path() {
    let chain = load_chain(bundled("ur5.urdf"), None, None).unwrap();
    let kin = Kinematics::new(&chain);
    let mut ws = Workspace::new(&kin);
    let start = fk(&kin, &mut ws, &[0.2, -1.0, 1.2, -0.5, 1.0, 0.3]).unwrap();
    let path: Vec<screwkit_lie::Se3> = (0..200)
        .map(|k| {
            let d = nalgebra::Vector3::new(0.0, f64::from(k) * 1e-3, 0.0);
            screwkit_lie::Se3::from_parts_unchecked(*start.rotation(), start.translation() + d)
        })
        .collect();
    let seed = [0.2, -1.0, 1.2, -0.5, 1.0, 0.3];
    let mut text = String::new();
    for (k, t) in path.iter().enumerate() {
        let h = t.to_homogeneous();
        let m: Vec<Vec<f64>> = (0..4)
            .map(|r| (0..4).map(|c| h[(r, c)]).collect())
            .collect();
        let s = if k == 0 {
            format!(",\"seed\":{}", serde_json::to_string(&seed).unwrap())
        } else {
            String::new()
        };
        text.push_str(&format!(
            "{{\"target\":{}{s}}}\n",
            serde_json::to_string(&m).unwrap()
        ));
    }
    let mut child = Command::new(BIN)
        .args([
            "ik",
            &bundled("ur5.urdf"),
            "--input",
            "-",
            "--sequential",
            "--format",
            "json",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    let want = ik_path(&kin, &mut ws, &path, &seed, &IkOptions::default()).unwrap();
    let mut prev: Option<Vec<f64>> = None;
    for (k, line) in String::from_utf8(out.stdout).unwrap().lines().enumerate() {
        let v: Value = serde_json::from_str(line).unwrap();
        let q: Vec<f64> = serde_json::from_value(v["q"].clone()).unwrap();
        assert_eq!(q, want[k].q, "row {k}");
        if let Some(p) = &prev {
            let jump = q
                .iter()
                .zip(p)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(jump < 0.05, "row {k}: a jump of {jump} rad");
        }
        prev = Some(q);
    }
}
