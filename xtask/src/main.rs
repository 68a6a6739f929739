//! Project tasks, run as `cargo xtask <task>` (the cargo-xtask pattern: plain Rust, no tools to
//! install first).
//!
//! - `cargo xtask test` (the README's test command): the whole suite as a newcomer runs it on a
//!   fresh clone with nothing beside it. Rust: `cargo test --workspace`. Python: a venv in
//!   `target/xtask-venv` (made with `python3 -m venv` when missing) with the pinned test
//!   requirements of `crates/screwkit-py/tests/requirements.txt`, the package installed exactly
//!   as a user does (`pip install ./crates/screwkit-py`), then `ruff format --check`, `ruff
//!   check`, `mypy --strict` (package stubs and tests), `mypy.stubtest` (the stubs against the
//!   built module) and `pytest`. Tests that need the project's CI data are skipped there, each
//!   with a one-line reason.
//! - `cargo xtask test --rust` or `--python`: one half.
//! - `cargo xtask conformance`: the tests on the CI data (real URDF, MJCF and xacro files), which
//!   it reads only through `SCREWKIT_SHARED_URDF`, `SCREWKIT_SHARED_MJCF` and
//!   `SCREWKIT_SHARED_XACRO` (all three must be set: `.ci/run` sets them): `cargo test
//!   --workspace -- --ignored` (with the browser tests: Chromium must be installed) and `pytest
//!   -m shared` with `SCREWKIT_CONFORMANCE=1`, where a missing variable fails instead of
//!   skipping.
//! - `cargo xtask newcomer`: runs the README's "Start here" block line by line, word for word,
//!   with the `SCREWKIT_SHARED_*` variables removed, and prints each command's wall time.
//! - `cargo xtask wheel`: builds the abi3 wheel with `maturin build --release` into
//!   `target/wheels`, installs it into a new venv (`target/wheel-venv`) with `cargo` and `rustc`
//!   off the PATH and `--only-binary :all:` (so nothing can be compiled), and runs the
//!   package's smoke tests (`crates/screwkit-py/tests/test_smoke.py`) there.
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
use std::time::Instant;

const USAGE: &str = "usage: cargo xtask test [--rust | --python] | cargo xtask conformance | \
                     cargo xtask newcomer | cargo xtask wheel | cargo xtask features";

/// The variables that name the CI data's folders.
const SHARED_VARIABLES: [&str; 3] = [
    "SCREWKIT_SHARED_URDF",
    "SCREWKIT_SHARED_MJCF",
    "SCREWKIT_SHARED_XACRO",
];

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match args.as_slice() {
        ["test"] => test(true, true),
        ["test", "--rust"] => test(true, false),
        ["test", "--python"] => test(false, true),
        ["conformance"] => conformance(),
        ["newcomer"] => newcomer(),
        ["wheel"] => wheel(),
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

/// The cargo target directory.
fn target() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target"))
}

fn cargo() -> Command {
    Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
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
        run(cargo().args(["test", "--workspace"]))?;
    }
    if python {
        let py = python_env()?;
        check_python(&py)?;
        run(&mut pytest(&py)?)?;
    }
    Ok(())
}

/// The venv's bin directory.
fn venv_bin(venv: &Path) -> PathBuf {
    venv.join(if cfg!(windows) { "Scripts" } else { "bin" })
}

/// A new venv at `venv` (from `$PYTHON`, else `python3`), with an up-to-date pip.
fn make_venv(venv: &Path) -> Result<PathBuf, String> {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    run(Command::new(python).arg("-m").arg("venv").arg(venv))?;
    let py = venv_bin(venv).join("python");
    run(Command::new(&py).args(["-m", "pip", "install", "--quiet", "--upgrade", "pip"]))?;
    Ok(py)
}

/// The test venv (`target/xtask-venv`) with the pinned requirements and the package installed
/// exactly as the README says; its Python.
fn python_env() -> Result<PathBuf, String> {
    let venv = target().join("xtask-venv");
    let mut py = venv_bin(&venv).join("python");
    if !py.exists() {
        py = make_venv(&venv)?;
    }
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
    Ok(py)
}

/// Formatting, lints, types and the stubs of the Python package.
fn check_python(py: &Path) -> Result<(), String> {
    let sources = [
        "crates/screwkit-py/python",
        "crates/screwkit-py/tests",
        "crates/screwkit-py/benchmarks",
    ];
    run(Command::new(py)
        .args(["-m", "ruff", "format", "--check"])
        .args(sources))?;
    run(Command::new(py).args(["-m", "ruff", "check"]).args(sources))?;
    run(Command::new(py)
        .args([
            "-m",
            "mypy",
            "--config-file",
            "crates/screwkit-py/pyproject.toml",
        ])
        .args(sources))?;
    run(Command::new(py)
        .args(["-m", "mypy.stubtest", "screwkit", "--mypy-config-file"])
        .arg("crates/screwkit-py/pyproject.toml"))
}

/// pytest on the package's tests, with the debug CLI (built here) for the tests that hold
/// Python and the command line to the same answers.
fn pytest(py: &Path) -> Result<Command, String> {
    run(cargo().args(["build", "-p", "screwkit-cli"]))?;
    let mut pytest = Command::new(py);
    pytest.args(["-m", "pytest", "-q", "-rs", "crates/screwkit-py/tests"]);
    pytest.env(
        "SCREWKIT_CLI",
        target().join("debug").join(if cfg!(windows) {
            "screwkit.exe"
        } else {
            "screwkit"
        }),
    );
    Ok(pytest)
}

/// The tests on the CI data, read through the `SCREWKIT_SHARED_*` variables only.
fn conformance() -> Result<(), String> {
    let missing: Vec<&str> = SHARED_VARIABLES
        .into_iter()
        .filter(|v| std::env::var_os(v).is_none_or(|d| !Path::new(&d).is_dir()))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "the conformance tests read the CI data through {}: set {} to its folders \
             (.ci/run does)",
            SHARED_VARIABLES.join(", "),
            missing.join(", ")
        ));
    }
    run(cargo().args(["test", "--workspace", "--", "--ignored"]))?;
    let py = python_env()?;
    let mut shared = pytest(&py)?;
    shared
        .args(["-m", "shared"])
        .env("SCREWKIT_CONFORMANCE", "1");
    run(&mut shared)
}

/// The shell lines of the README's "Start here" block: its first ```sh block.
fn start_here() -> Result<Vec<String>, String> {
    let readme =
        std::fs::read_to_string(root().join("README.md")).map_err(|e| format!("README.md: {e}"))?;
    let block = readme
        .split("\n```sh\n")
        .nth(1)
        .and_then(|b| b.split("\n```").next())
        .ok_or("README.md has no ```sh block")?;
    Ok(block
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(String::from)
        .collect())
}

/// The README's "Start here" commands, word for word, in one shell (a `venv` activated on one
/// line holds for the next), without the CI data's variables; each command's wall time.
fn newcomer() -> Result<(), String> {
    let lines = start_here()?;
    let mut script = String::from("set -euo pipefail\nTIMEFORMAT='xtask: newcomer: %R s'\n");
    for l in &lines {
        let shown = l.replace('\'', "'\\''");
        script.push_str(&format!(
            "echo 'xtask: newcomer: {shown}' >&2\ntime {{ {l}\n}}\n"
        ));
    }
    let mut sh = Command::new("bash");
    sh.arg("-c").arg(script);
    for v in SHARED_VARIABLES {
        sh.env_remove(v);
    }
    let start = Instant::now();
    run(&mut sh)?;
    eprintln!(
        "xtask: newcomer: the README's {} commands passed in {:.0} s",
        lines.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The wheel a user without Rust installs: built once, installed and smoke-tested in a new
/// venv with no Rust toolchain on the PATH.
fn wheel() -> Result<(), String> {
    let py = python_env()?;
    let wheels = target().join("wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    run(Command::new(&py)
        .args(["-m", "maturin", "build", "--release", "--manifest-path"])
        .arg("crates/screwkit-py/Cargo.toml")
        .arg("--out")
        .arg(&wheels))?;
    let wheel = std::fs::read_dir(&wheels)
        .map_err(|e| format!("{}: {e}", wheels.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "whl"))
        .ok_or("maturin built no wheel")?;
    let name = wheel.file_name().unwrap_or_default().to_string_lossy();
    if !(name.contains("abi3") && name.contains("manylinux")) {
        return Err(format!("{name}: not an abi3 manylinux wheel"));
    }
    // The PATH without any folder that holds cargo or rustc.
    let path = std::env::var_os("PATH").unwrap_or_default();
    let kept: Vec<PathBuf> = std::env::split_paths(&path)
        .filter(|d| !d.join("cargo").exists() && !d.join("rustc").exists())
        .collect();
    let path = std::env::join_paths(kept).map_err(|e| e.to_string())?;
    let venv = target().join("wheel-venv");
    let _ = std::fs::remove_dir_all(&venv);
    let vpy = make_venv(&venv)?;
    let no_rust = |cmd: &mut Command| {
        cmd.env("PATH", &path)
            .env_remove("CARGO")
            .env_remove("RUSTC")
            .env_remove("RUSTUP_HOME")
            .env_remove("CARGO_HOME");
    };
    let mut which = Command::new("sh");
    which.args(["-c", "! command -v cargo && ! command -v rustc"]);
    no_rust(&mut which);
    run(&mut which).map_err(|_| "cargo or rustc is still on the stripped PATH".to_string())?;
    let mut install = Command::new(&vpy);
    install
        .args(["-m", "pip", "install", "--quiet", "--only-binary", ":all:"])
        .arg(&wheel)
        .arg("pytest");
    no_rust(&mut install);
    run(&mut install)?;
    let mut smoke = Command::new(&vpy);
    smoke
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg("crates/screwkit-py/tests/test_smoke.py");
    no_rust(&mut smoke);
    run(&mut smoke)?;
    let size = std::fs::metadata(&wheel).map(|m| m.len()).unwrap_or(0);
    eprintln!(
        "xtask: wheel: {name} ({:.1} MB) installs and passes its smoke tests without Rust",
        size as f64 / 1e6
    );
    Ok(())
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
