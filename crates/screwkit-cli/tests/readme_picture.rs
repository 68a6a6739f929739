//! The pictures of the README and the guide are the outputs of the commands they show; this
//! test fails when one is stale. Regenerate with `SCREWKIT_UPDATE_PICTURES=1 cargo test -p
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
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    assert!(
        readme.contains(
            "`screwkit draw assets/urdf/ur5.urdf --q 0.3,-1.0,1.4,-0.8,-1.2,0.4 --view all -o docs/ur5.svg`"
        ),
        "the README shows the command that draws docs/ur5.svg"
    );
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

/// The guide's MJCF picture (the bundled humanoid, `assets/mjcf/humanoid.xml`) is the output of
/// the command under it in `docs/guide/mjcf.md`.
#[test]
fn humanoid_picture_is_current() {
    let command = [
        "draw",
        "assets/mjcf/humanoid.xml",
        "--q",
        HUMANOID_Q,
        "--view",
        "all",
        "-o",
        "docs/humanoid.svg",
    ];
    let page = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/guide/mjcf.md"
    ))
    .unwrap();
    assert!(
        page.contains(&format!("`screwkit {}`", command.join(" "))),
        "docs/guide/mjcf.md shows the command that draws docs/humanoid.svg"
    );
    let mut args = command.to_vec();
    *args.last_mut().unwrap() = "-";
    assert_current(&args, "humanoid.svg");
}

/// The humanoid's pose in that picture: the floating base (x, y, z, qx, qy, qz, qw), then the 23
/// joints in file order (left leg, right leg, waist, left arm, neck, right arm).
const HUMANOID_Q: &str = "0,0,0.71,0,0,0,1,0,0.1,-0.6,0.9,-0.3,-0.1,0,-0.05,0.2,0.3,-0.5,0.05,0.2,-0.8,0.3,0,-1.0,0.3,0.2,0.4,-0.2,0.1,-0.6";
