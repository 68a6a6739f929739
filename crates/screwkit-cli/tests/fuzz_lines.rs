//! Fuzz target of the JSON-lines batch parser (`fk`, `jacobian`, `ik --input -`, `ik --all
//! --input -`, `ik --tasks FILE --input -` with and without `--sequential`, `path --input -`): mutated lines from the seeded mutation fuzzer of `screwkit_testkit::fuzz`,
//! thousands per process. Every line gets exactly one answer (a result or an error object
//! naming its line), the exit code is 0 or 1, and nothing panics. A few seconds here;
//! `SCREWKIT_FUZZ_SECS=600` runs ten minutes.

use std::io::Write;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use screwkit_testkit::fuzz::{self, Mutator};

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn ur5() -> String {
    format!("{}/../../assets/urdf/ur5.urdf", env!("CARGO_MANIFEST_DIR"))
}

/// Runs `args` on `lines` (one mutated input per line) and checks the answers.
fn feed(args: &[&str], lines: &[Vec<u8>]) {
    let mut child = Command::new(BIN)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let input: Vec<u8> = lines
        .iter()
        .flat_map(|l| {
            let mut l: Vec<u8> = l
                .iter()
                .copied()
                .filter(|&b| b != b'\n' && b != b'\r')
                .collect();
            l.push(b'\n');
            l
        })
        .collect();
    let writer = std::thread::spawn(move || {
        let _ = stdin.write_all(&input);
    });
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        matches!(out.status.code(), Some(0 | 1)),
        "{args:?}: {:?}\n{err}",
        out.status
    );
    assert!(
        !err.contains("internal error") && !err.contains("panicked"),
        "{args:?}: {err}"
    );
    // One answer per non-blank line.
    let blank = |l: &Vec<u8>| {
        String::from_utf8(
            l.iter()
                .copied()
                .filter(|&b| b != b'\n' && b != b'\r')
                .collect(),
        )
        .is_ok_and(|s| s.strip_prefix('\u{feff}').unwrap_or(&s).trim().is_empty())
    };
    let expected = lines.iter().filter(|l| !blank(l)).count();
    let answers = out
        .stdout
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .count();
    assert_eq!(answers, expected, "{args:?}: {err}");
}

#[test]
fn fuzz_json_lines() {
    let seeds: Vec<Vec<u8>> = [
        r#"{"q":[0.1,-0.5,1.0,0.2,0.3,-0.4]}"#,
        r#"{"q":[0,0,0,0,0,0],"extra":null}"#,
        r#"{"target":[[-1,0,0,0.81725],[0,0,1,0.19145],[0,1,0,-0.005491],[0,0,0,1]],"seed":[0,0,0,0,0,0]}"#,
        r#"{"target":[[1,0,0,0.3],[0,1,0,0.1],[0,0,1,0.4],[0,0,0,1]]}"#,
        "\u{feff}{\"q\":[1e-300,2,3,4,5,6]}",
        r#"{"tasks":[{"target":[1,0,0,0.3,0,1,0,0.4,0,0,1,0.9,0,0,0,1]},null,{"weight":0.1}],"seed":[0,0,0,0,0,0,0]}"#,
        r#"{"tasks":[{"type":"axis","axis":[0,0,1],"direction":[1,0,0]},{"position_weight":[1,0,1]}]}"#,
        r#"{"from":[0.3,-1.2,1.4,-1.5,-1.4,0.4],"to":[0.5,0.3,0.3,3.1,0,0],"via":[[0.5,0.3,0.35,0,0,0,1]]}"#,
    ]
    .iter()
    .map(|s| s.as_bytes().to_vec())
    .collect();
    let tokens: &[&[u8]] = &[
        b"[",
        b"]",
        b"{",
        b"}",
        b",",
        b":",
        b"\"q\"",
        b"\"target\"",
        b"\"seed\"",
        b"\"tasks\"",
        b"\"weight\"",
        b"\"from\"",
        b"\"to\"",
        b"\"via\"",
        b"null",
        b"true",
        b"1e999",
        b"-0.0",
        b"[[",
        b"]]",
        b"\\u0000",
        b"\"",
        b"NaN",
        b"Infinity",
    ];
    let secs = fuzz::seconds(4.0);
    let start = Instant::now();
    let mut m = Mutator::new(6, &seeds, tokens);
    let (mut rounds, mut lines_fed) = (0u64, 0u64);
    let ur5 = ur5();
    let torso = format!(
        "{}/../../assets/urdf/torso_two_arms.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    let tasks = format!(
        "{}/../../assets/tasks/torso_two_arms.json",
        env!("CARGO_MANIFEST_DIR")
    );
    while start.elapsed() < Duration::from_secs_f64(secs) {
        let fk: Vec<Vec<u8>> = (0..5000).map(|_| m.input()).collect();
        feed(&["fk", &ur5, "--input", "-"], &fk);
        feed(&["jacobian", &ur5, "--input", "-"], &fk[..2000]);
        let ik: Vec<Vec<u8>> = (0..500).map(|_| m.input()).collect();
        feed(
            &[
                "ik",
                &ur5,
                "--input",
                "-",
                "--max-iter",
                "40",
                "--restarts",
                "2",
            ],
            &ik,
        );
        feed(&["ik", &ur5, "--all", "--input", "-"], &ik[..200]);
        // Whole-body IK's lines of task changes (`--tasks`), independent and in order.
        for sequential in [false, true] {
            let mut args = vec![
                "ik",
                &torso,
                "--tasks",
                &tasks,
                "--input",
                "-",
                "--max-iter",
                "10",
                "--restarts",
                "1",
            ];
            if sequential {
                args.push("--sequential");
            }
            feed(&args, &ik[..200]);
        }
        // Cartesian paths, coarse steps (a line's cost is its path's length).
        feed(
            &[
                "path",
                &ur5,
                "--input",
                "-",
                "--max-step",
                "0.05",
                "--max-joint-step",
                "0.5",
            ],
            &ik[..200],
        );
        rounds += 1;
        lines_fed += 8300;
    }
    eprintln!(
        "fuzz json lines: {lines_fed} lines in {rounds} rounds, {:.0} s, without a crash",
        start.elapsed().as_secs_f64()
    );
    assert!(rounds > 0);
}
