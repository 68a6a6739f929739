//! Fuzz target of Cartesian paths' inputs (`screwkit path --waypoints FILE.npy`): mutated `.npy`
//! files of poses read by `path::read_waypoints`, and each file read followed as a path by the
//! bundled UR5 (closed-form IK) from a fixed seed. Every input gives poses or an error naming
//! the file, never a panic; a path made of poses that were read ends with a stop word and at
//! most `MAX_SAMPLES` samples, all within the joint limits. A few seconds here;
//! `SCREWKIT_FUZZ_SECS=600` runs ten minutes.

use screwkit_service::path;
use screwkit_solve::path::{PathOptions, MAX_SAMPLES};
use screwkit_solve::{Kinematics, Workspace};
use screwkit_testkit::{fuzz, npy_bytes};

const TOKENS: &[&[u8]] = &[
    b"'shape': (2, 4, 4)",
    b"'shape': (3, 7)",
    b"'shape': (1, 6)",
    b"'shape': (100000000, 16)",
    b"'shape': (0, 16)",
    b"'shape': (2, 5)",
    b"'descr': '<f4'",
    b"'fortran_order': True",
    b"\x00\x00\x00\x00\x00\x00\xf8\x7f", // NaN
    b"\x00\x00\x00\x00\x00\x00\xf0\x7f", // +inf
    b"\x00\x00\x00\x00\x00\x00\xf0\x3f", // 1.0
    b"\x00\x00\x00\x00\x00\x00\x00\x00", // 0.0
    b"\x93NUMPY\x01\x00",
];

/// Found by this target: a header whose dimensions' product overflows (shape (0, 2⁶³, 4)) made
/// the `.npy` reader shared by every command panic (debug) or wrap (release); it is refused.
#[test]
fn a_header_larger_than_any_file_is_refused() {
    let file = std::env::temp_dir().join(format!("screwkit-huge-{}.npy", std::process::id()));
    for shape in [
        "(0, 9223372036854775808, 4)",
        "(2, 4611686018427387904)",
        "(3, 1, 1, 1)",
    ] {
        std::fs::write(&file, npy_bytes("<f8", false, shape, &[1.0, 2.0, 3.0])).unwrap();
        let e = screwkit_service::io::npy::NpyReader::open(file.to_str().unwrap())
            .err()
            .map(|e| e.to_string());
        match shape {
            "(3, 1, 1, 1)" => assert!(e.is_none(), "{e:?}"),
            _ => assert!(
                e.as_deref()
                    .is_some_and(|m| m.contains("more elements than any file can hold")),
                "{e:?}"
            ),
        }
    }
    let _ = std::fs::remove_file(&file);
}

#[test]
fn fuzz_waypoint_files() {
    let urdf = format!("{}/../../assets/urdf/ur5.urdf", env!("CARGO_MANIFEST_DIR"));
    let chain = screwkit_model::load_chain(&urdf, None, None).unwrap();
    let kin = Kinematics::new(&chain);
    let mut ws = Workspace::new(&kin);
    let seed = [0.3, -1.2, 1.4, -1.5, -1.4, 0.4];
    let start = screwkit_solve::fk::fk(&kin, &mut ws, &seed).unwrap();
    let mut m = [0.0; 16];
    start.write_row_major(&mut m);
    let mut moved = m;
    moved[3] += 0.05;
    let mut matrices = m.to_vec();
    matrices.extend_from_slice(&moved);
    let seeds = vec![
        npy_bytes("<f8", false, "(2, 4, 4)", &matrices),
        npy_bytes(
            "<f8",
            false,
            "(2, 7)",
            &[
                0.5, 0.3, 0.3, 0.0, 0.0, 0.0, 1.0, 0.45, 0.3, 0.35, 0.0, 1.0, 0.0, 0.0,
            ],
        ),
        npy_bytes("<f8", false, "(1, 6)", &[0.4, 0.2, 0.4, 3.0, 0.1, 0.2]),
    ];
    let solvers = screwkit_service::solutions::Solvers::default();
    let analytic = path::path_solver(&kin, &solvers, None).unwrap();
    // Coarse steps: a fuzz input is about the file, not about a long path.
    let options = PathOptions {
        max_step: 0.05,
        max_joint_step: 0.5,
        ..Default::default()
    };
    let file = std::env::temp_dir().join(format!(
        "screwkit-fuzz-waypoints-{}.npy",
        std::process::id()
    ));
    let name = file.to_str().unwrap().to_string();
    let n = fuzz::run("waypoints", 51, 3.0, &seeds, TOKENS, |input| {
        std::fs::write(&file, input).unwrap();
        let Ok(poses) = path::read_waypoints(&name) else {
            return;
        };
        assert!(!poses.is_empty() && poses.len() <= path::MAX_WAYPOINTS);
        assert!(poses.iter().all(|p| p.is_finite()));
        if poses.len() > 4 {
            return; // (the reading is what is fuzzed; long paths only cost time)
        }
        let Ok(p) = path::cartesian_path(
            &kin,
            &mut ws,
            analytic.as_deref(),
            &poses,
            &seed,
            &options,
            None,
        ) else {
            return;
        };
        assert!(p.place.len() <= MAX_SAMPLES + 1);
        assert_eq!(p.q.len(), p.place.len() * 6);
        assert!((0.0..=1.0).contains(&p.fraction), "{}", p.fraction);
        for q in p.q.chunks(6) {
            assert!(kin.check_q(q).is_ok(), "{q:?}");
        }
    });
    let _ = std::fs::remove_file(&file);
    assert!(n > 0);
}
