//! Project tasks, run as `cargo xtask <task>` (the cargo-xtask pattern: plain Rust, no tools to
//! install first).
//!
//! - `cargo xtask test`: the whole suite. Rust: `cargo test --workspace`. Python: a venv in
//!   `target/xtask-venv` (made with `python3 -m venv` when missing) with the pinned test
//!   requirements of `crates/screwkit-py/tests/requirements.txt`, the package installed exactly
//!   as a user does (`pip install ./crates/screwkit-py`), then `ruff format --check`, `ruff
//!   check`, `mypy --strict` (package stubs and tests), `mypy.stubtest` (the stubs against the
//!   built module) and `pytest`.
//! - `cargo xtask test --rust` or `--python`: one half.
//! - `cargo xtask features`: checks that the CLI and the Python package ask for the same
//!   features of every dependency they share (`cargo tree`, no build), so that
//!   `pip install ./crates/screwkit-py` after `cargo build --release -p screwkit-cli` reuses
//!   its compiled dependencies instead of building them a second time, and that the CLI alone
//!   asks for what the workspace's test build does (so the CLI the Python tests call is the
//!   one `cargo test --workspace` built); see `crates/workspace-hack/Cargo.toml`. A difference
//!   names the crates and what to add there.
//!
//! The Python interpreter is `$PYTHON`, else `python3`.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

const USAGE: &str = "usage: cargo xtask test [--rust | --python] | cargo xtask features";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match args.as_slice() {
        ["test"] => test(true, true),
        ["test", "--rust"] => test(true, false),
        ["test", "--python"] => test(false, true),
        ["features"] => features(),
        _ => Err(USAGE.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The workspace root (the parent of this crate's directory).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// Runs a command in the workspace root; an error names it and its exit status.
fn run(cmd: &mut Command) -> Result<(), String> {
    let shown = format!("{cmd:?}");
    eprintln!("xtask: {shown}");
    let status = cmd
        .current_dir(root())
        .status()
        .map_err(|e| format!("cannot start {shown}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{shown} failed ({status})"))
    }
}

fn test(rust: bool, python: bool) -> Result<(), String> {
    if rust {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        run(Command::new(cargo).args(["test", "--workspace"]))?;
    }
    if python {
        test_python()?;
    }
    Ok(())
}

fn test_python() -> Result<(), String> {
    let root = root();
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let venv = target.join("xtask-venv");
    let bin = venv.join(if cfg!(windows) { "Scripts" } else { "bin" });
    let py = bin.join("python");
    if !py.exists() {
        let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
        run(Command::new(python).arg("-m").arg("venv").arg(&venv))?;
        run(Command::new(&py).args(["-m", "pip", "install", "--quiet", "--upgrade", "pip"]))?;
    }
    let pkg = "crates/screwkit-py";
    run(Command::new(&py).args([
        "-m",
        "pip",
        "install",
        "--quiet",
        "-r",
        "crates/screwkit-py/tests/requirements.txt",
    ]))?;
    // Exactly the README's install command.
    run(Command::new(&py).args(["-m", "pip", "install", "--quiet", "./crates/screwkit-py"]))?;
    let sources = [
        "crates/screwkit-py/python",
        "crates/screwkit-py/tests",
        "crates/screwkit-py/benchmarks",
    ];
    run(Command::new(&py)
        .args(["-m", "ruff", "format", "--check"])
        .args(sources))?;
    run(Command::new(&py)
        .args(["-m", "ruff", "check"])
        .args(sources))?;
    run(Command::new(&py)
        .args([
            "-m",
            "mypy",
            "--config-file",
            "crates/screwkit-py/pyproject.toml",
        ])
        .args(sources))?;
    run(Command::new(&py)
        .args(["-m", "mypy.stubtest", "screwkit", "--mypy-config-file"])
        .arg(format!("{pkg}/pyproject.toml")))?;
    // The CLI, for the tests that hold Python and the command line to the same answers.
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    run(Command::new(cargo).args(["build", "-p", "screwkit-cli"]))?;
    let mut pytest = Command::new(&py);
    pytest.args(["-m", "pytest", "-q", "crates/screwkit-py/tests"]);
    pytest.env(
        "SCREWKIT_CLI",
        target.join("debug").join(if cfg!(windows) {
            "screwkit.exe"
        } else {
            "screwkit"
        }),
    );
    if std::env::var_os("SCREWKIT_SHARED_URDF").is_none() {
        let shared = root.join("../shared/urdf");
        if shared.is_dir() {
            pytest.env("SCREWKIT_SHARED_URDF", shared);
        }
    }
    run(&mut pytest)
}

/// The front ends whose dependency builds must coincide.
const FRONT_ENDS: [&str; 2] = ["screwkit-cli", "screwkit-py"];

/// Feature sets per dependency: "name vX.Y.Z [(source)]" → {"f1,f2", …}.
type Features = std::collections::BTreeMap<String, std::collections::BTreeSet<String>>;

/// Each dependency of a build (`selection`: `-p PACKAGE` or `--workspace`; `edges`:
/// `normal,build` as `cargo build` resolves them, with `dev` as `cargo test` does) with the
/// feature sets it is built with.
fn dependency_features(selection: &[&str], edges: &str) -> Result<Features, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(root())
        .arg("tree")
        .args(selection)
        .args([
            "-e",
            edges,
            "--prefix",
            "none",
            "--no-dedupe",
            "-f",
            "{p}|{f}",
        ])
        .output()
        .map_err(|e| format!("cannot run cargo tree: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "cargo tree {} failed: {}",
            selection.join(" "),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let mut map = Features::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        if let Some((crate_, features)) = line.split_once('|') {
            if features.trim() == "(*)" {
                continue;
            }
            map.entry(crate_.trim().to_string())
                .or_default()
                .insert(features.trim().to_string());
        }
    }
    Ok(map)
}

/// The shared dependencies whose feature sets differ between two builds, one line each.
fn differing(a: (&str, &Features), b: (&str, &Features)) -> Vec<String> {
    a.1.iter()
        .filter_map(|(k, va)| {
            let vb = b.1.get(k)?;
            (va != vb).then(|| format!("  {k}: {} {va:?}, {} {vb:?}", a.0, b.0))
        })
        .collect()
}

fn features() -> Result<(), String> {
    let [a, b] = FRONT_ENDS;
    let fa = dependency_features(&["-p", a], "normal,build")?;
    let fb = dependency_features(&["-p", b], "normal,build")?;
    let tests = dependency_features(&["--workspace"], "normal,build,dev")?;
    let mut problems = differing((a, &fa), (b, &fb));
    problems.extend(differing((a, &fa), ("the test build", &tests)));
    if problems.is_empty() {
        eprintln!(
            "xtask: {a} and {b} share {} dependencies, each with the same features, also in \
             the workspace's test build",
            fa.keys().filter(|k| fb.contains_key(*k)).count()
        );
        Ok(())
    } else {
        Err(format!(
            "these shared dependencies are built with different features, so one build \
             compiles them (and everything above them) again after the other; add the union \
             to crates/workspace-hack/Cargo.toml:\n{}",
            problems.join("\n")
        ))
    }
}
