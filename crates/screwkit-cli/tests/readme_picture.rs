//! The picture at the top of the README is the output of the command the README shows; this
//! test fails when it is stale. Regenerate with `SCREWKIT_UPDATE_PICTURES=1 cargo test -p
//! screwkit-cli --test readme_picture` and look at it before committing.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

#[test]
fn readme_picture_is_current() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = Command::new(BIN)
        .current_dir(root)
        .args([
            "draw",
            "assets/urdf/ur5.urdf",
            "--q",
            "0.3,-1.0,1.4,-0.8,-1.2,0.4",
            "--view",
            "all",
            "-o",
            "-",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let file = format!("{root}/docs/ur5.svg");
    if std::env::var_os("SCREWKIT_UPDATE_PICTURES").is_some() {
        std::fs::write(&file, &out.stdout).unwrap();
    }
    let committed = std::fs::read(&file).unwrap_or_default();
    assert!(
        committed == out.stdout,
        "docs/ur5.svg is stale: regenerate it with SCREWKIT_UPDATE_PICTURES=1 cargo test -p screwkit-cli --test readme_picture"
    );
}

/// The README's MJCF picture (gymnasium's humanoid from ../shared/mjcf, present beside the
/// clone in CI) is the output of the command under it.
#[test]
fn readme_humanoid_picture_is_current() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let model = format!("{root}/../shared/mjcf/humanoid.xml");
    assert!(
        std::path::Path::new(&model).is_file(),
        "{model} not found: ../shared/mjcf belongs beside the clone"
    );
    let out = Command::new(BIN)
        .current_dir(root)
        .args([
            "draw",
            "../shared/mjcf/humanoid.xml",
            "--q",
            "0,0,1.4,0,0,0,1,0.1,-0.2,0,-0.1,0,-0.6,-0.9,0,0,0.2,-0.2,0.5,-0.6,-0.8,-0.4,0.7,-0.5",
            "--view",
            "all",
            "-o",
            "-",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let file = format!("{root}/docs/humanoid.svg");
    if std::env::var_os("SCREWKIT_UPDATE_PICTURES").is_some() {
        std::fs::write(&file, &out.stdout).unwrap();
    }
    let committed = std::fs::read(&file).unwrap_or_default();
    assert!(
        committed == out.stdout,
        "docs/humanoid.svg is stale: regenerate it with SCREWKIT_UPDATE_PICTURES=1 cargo test -p screwkit-cli --test readme_picture"
    );
}
