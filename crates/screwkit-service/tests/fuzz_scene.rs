//! Fuzz target of scene files (`screwkit collide --obstacles`, `Robot.add_obstacles`): mutated
//! scenes read by `body::read_scene`'s parser, and each one read added to a robot's collision
//! model and queried. Every input gives obstacles or an error naming the file, never a panic; an
//! obstacle that was read has finite, checked numbers. A few seconds here;
//! `SCREWKIT_FUZZ_SECS=600` runs ten minutes.

use screwkit_collision::{distances, in_collision, CollisionModel, CollisionWorkspace, Options};
use screwkit_model::{urdf, KinematicTree};
use screwkit_service::body;
use screwkit_solve::TreeKinematics;
use screwkit_testkit::fuzz;

const SEED: &str = r#"{"obstacles": [
  {"name": "table", "shape": "box", "size": [1.0, 0.8, 0.05], "xyz": [0.6, 0, 0.4]},
  {"name": "ball", "shape": "sphere", "radius": 0.1, "xyz": [0.4, 0.3, 0.9], "rpy": [0, 0, 1]},
  {"name": "post", "shape": "cylinder", "radius": 0.05, "length": 1.0},
  {"name": "bar", "shape": "capsule", "radius": 0.02, "length": 0.5,
   "pose": [[1, 0, 0, 0.5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}
]}"#;

const TOKENS: &[&[u8]] = &[
    b"\"mesh\"",
    b"\"path\": \"part.stl\"",
    b"\"path\": \"package://nowhere/x.stl\"",
    b"\"path\": \"file:///dev/zero\"",
    b"\"scale\": [1e308, 1, 1]",
    b"\"size\": [0, 1, 1]",
    b"\"radius\": -1",
    b"1e999",
    b"-0.0",
    b"null",
    b"\"name\": \"table\"",
    b"\"pose\": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
    b"\"xyz\": [1e300, 0, 0]",
    b"{",
    b"}",
    b"[",
    b"]",
    b",",
];

#[test]
fn fuzz_scenes() {
    let path = format!(
        "{}/../../assets/urdf/humanoid.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    let tree = urdf::load_file(path).unwrap();
    let kin = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
    let base = CollisionModel::new(&kin, Options::default()).unwrap();
    let q = vec![0.1; kin.nq()];
    let dir = std::env::temp_dir();
    let n = fuzz::run(
        "scene",
        41,
        3.0,
        &[SEED.as_bytes().to_vec()],
        TOKENS,
        |input| {
            let text = String::from_utf8_lossy(input);
            let Ok(obstacles) = body::scene_from_str(&text, "fuzz.json", &dir, &[]) else {
                return;
            };
            for o in &obstacles {
                assert!(o.shape.check().is_ok(), "{o:?}");
            }
            let mut model = base.clone();
            if body::add_obstacles(&mut model, &obstacles).is_ok() {
                let mut ws = CollisionWorkspace::new(&kin, &model);
                let mut out = Vec::new();
                let _ = in_collision(&model, &mut ws, &kin, &q);
                let _ = distances(&model, &mut ws, &kin, &q, &mut out);
            }
        },
    );
    assert!(n > 0);
}
