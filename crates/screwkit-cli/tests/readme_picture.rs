//! The picture at the top of the README is the output of the command the README shows; this
//! test fails when it is stale. Regenerate with `SCREWKIT_UPDATE_PICTURES=1 cargo test -p
//! screwkit-cli --test readme_picture` and look at it before committing.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

/// Runs `screwkit ARGS` from the repository root and holds `docs/FILE` to its output
/// (`SCREWKIT_UPDATE_PICTURES=1` rewrites it).
fn assert_current(args: &[&str], file: &str) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = Command::new(BIN)
        .current_dir(root)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let path = format!("{root}/docs/{file}");
    if std::env::var_os("SCREWKIT_UPDATE_PICTURES").is_some() {
        std::fs::write(&path, &out.stdout).unwrap();
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == out.stdout,
        "docs/{file} is stale: regenerate it with SCREWKIT_UPDATE_PICTURES=1 cargo test -p screwkit-cli --test readme_picture"
    );
}

#[test]
fn readme_picture_is_current() {
    assert_current(
        &[
            "draw",
            "assets/urdf/ur5.urdf",
            "--q",
            "0.3,-1.0,1.4,-0.8,-1.2,0.4",
            "--view",
            "all",
            "-o",
            "-",
        ],
        "ur5.svg",
    );
}

/// The README's MJCF picture (gymnasium's humanoid from ../shared/mjcf, present beside the
/// clone in CI) is the output of the command under it.
#[test]
fn readme_humanoid_picture_is_current() {
    let model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/mjcf/humanoid.xml"
    );
    assert!(
        std::path::Path::new(model).is_file(),
        "{model} not found: ../shared/mjcf belongs beside the clone"
    );
    assert_current(
        &[
            "draw",
            "../shared/mjcf/humanoid.xml",
            "--q",
            "0,0,1.4,0,0,0,1,0.1,-0.2,0,-0.1,0,-0.6,-0.9,0,0,0.2,-0.2,0.5,-0.6,-0.8,-0.4,0.7,-0.5",
            "--view",
            "all",
            "-o",
            "-",
        ],
        "humanoid.svg",
    );
}
