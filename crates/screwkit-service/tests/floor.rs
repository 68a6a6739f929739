//! The floor's loading, defaults and errors.

use std::io::ErrorKind;

use screwkit_service::{Error, IkSettings, LoadOptions, ReachSpec, Robot, Source};
use screwkit_solve::ik::IkOptions;

fn asset(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/urdf")
        .join(name)
}

#[test]
fn one_set_of_defaults_the_librarys() {
    let d = IkSettings::default();
    let o = d.options().unwrap();
    let l = IkOptions::default();
    assert_eq!(o.method, l.method);
    assert_eq!(
        (
            o.tol_rot,
            o.tol_pos,
            o.max_iterations,
            o.max_restarts,
            o.timeout,
            o.seed
        ),
        (
            l.tol_rot,
            l.tol_pos,
            l.max_iterations,
            l.max_restarts,
            l.timeout,
            l.seed
        )
    );
    assert_eq!((o.weights, o.position_only), (l.weights, l.position_only));
    assert_eq!(ReachSpec::default().resolution, 0.05);
    let bad = IkSettings {
        weights: vec![1.0; 3],
        ..d.clone()
    }
    .options()
    .unwrap_err();
    assert_eq!(
        bad.to_string(),
        "weights: needs 6 numbers (ω1, ω2, ω3, v1, v2, v3; 0 masks one out), got 3"
    );
    let bad = IkSettings {
        timeout_ms: -1.0,
        ..d
    }
    .options()
    .unwrap_err();
    assert!(
        matches!(
            bad,
            Error::Option {
                name: "timeout_ms",
                ..
            }
        ),
        "{bad}"
    );
}

#[test]
fn unreadable_files_keep_the_operating_systems_error() {
    for (path, kind) in [
        (
            std::path::PathBuf::from("/definitely/not/here.urdf"),
            ErrorKind::NotFound,
        ),
        (asset(""), ErrorKind::IsADirectory),
    ] {
        match Robot::load(&Source::Path(path.clone()), &LoadOptions::default()) {
            Err(Error::Io { path: p, source }) => {
                assert_eq!(p, path);
                assert_eq!(source.kind(), kind);
            }
            other => panic!("{path:?}: {other:?}"),
        }
    }
}

#[test]
fn a_path_text_and_its_urdf_give_the_same_robot() {
    let path = asset("ur5.urdf");
    let a = Robot::load(&Source::Path(path.clone()), &LoadOptions::default()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let b = Robot::load(&Source::text(text, "ur5"), &LoadOptions::default()).unwrap();
    assert_eq!(a.chain().unwrap().home, b.chain().unwrap().home);
    assert_eq!(a.urdf(), b.urdf());
    // The URDF kept is what loads the same robot again (pickling).
    let c = Robot::load(&Source::text(a.urdf(), "again"), &LoadOptions::default()).unwrap();
    assert_eq!(c.chain().unwrap().home, a.chain().unwrap().home);
    let tool = LoadOptions {
        tool: Some(vec![0.0, 0.0, 0.1, 0.0, 0.0, 0.0]),
        ..LoadOptions::default()
    };
    let t = Robot::load(&Source::Path(path.clone()), &tool).unwrap();
    assert_eq!(
        t.chain().unwrap().tip,
        format!("{}+tool", a.chain().unwrap().tip)
    );
    let bad = LoadOptions {
        tool: Some(vec![0.0]),
        ..LoadOptions::default()
    };
    let e = Robot::load(&Source::Path(path), &bad).unwrap_err();
    assert_eq!(
        e.to_string(),
        "tool: needs 6 numbers x,y,z,roll,pitch,yaw, got 1"
    );
}
