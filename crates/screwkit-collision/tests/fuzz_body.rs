//! The body of untrusted MJCF geoms: mutated models are read, their collision model built and
//! queried at rest and at a random configuration; nothing may panic (a degenerate or
//! enormous shape gives an error or a number, never an abort).

use screwkit_collision::{
    distances, in_collision, min_distance, CollisionModel, CollisionWorkspace, MeshMode, Options,
};
use screwkit_model::{mjcf, KinematicTree};
use screwkit_solve::TreeKinematics;
use screwkit_testkit::fuzz;

const SEED: &str = r#"<mujoco>
  <default><geom contype="1" conaffinity="1"/></default>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="a" pos="0 0 0.5">
      <joint name="ja" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.05"/>
      <geom type="ellipsoid" size="0.1 0.05 0.02" pos="0.3 0 0"/>
      <body name="b" pos="0.35 0 0">
        <joint name="jb" axis="0 0 1"/>
        <geom type="cylinder" size="0.04 0.1"/>
        <geom type="box" size="0.05 0.02 0.03" pos="0.1 0 0"/>
        <body name="c" pos="0.2 0 0">
          <joint name="jc" type="slide" axis="1 0 0"/>
          <geom type="sphere" size="0.03"/>
        </body>
      </body>
    </body>
  </worldbody>
  <contact><exclude body1="a" body2="c"/></contact>
</mujoco>"#;

const TOKENS: &[&[u8]] = &[
    b"<geom type=\"ellipsoid\" size=\"1e300 1e-300 1\"/>",
    b"<geom type=\"capsule\" fromto=\"0 0 0 1e300 0 0\" size=\"1e-300\"/>",
    b"<geom type=\"box\" size=\"1e308 1e308 1e308\"/>",
    b"<geom type=\"cylinder\" size=\"1e-320 5\"/>",
    b"<geom type=\"plane\" zaxis=\"1 1 0\"/>",
    b"<geom type=\"sphere\" size=\"0.01\" pos=\"1e300 0 0\"/>",
    b"contype=\"4294967295\"",
    b"conaffinity=\"0\"",
    b"<pair geom1=\"floor\" geom2=\"floor\"/>",
    b"<exclude body1=\"b\" body2=\"b\"/>",
    b"<freejoint/>",
    b"euler=\"1e308 0 0\"",
];

#[test]
fn fuzz_mjcf_bodies() {
    let dir = std::env::temp_dir();
    let n = fuzz::run(
        "mjcf-body",
        31,
        3.0,
        &[SEED.as_bytes().to_vec()],
        TOKENS,
        |input| {
            let text = String::from_utf8_lossy(input);
            let Ok(tree) = mjcf::load_str(&text, "fuzz.xml", &dir) else {
                return;
            };
            let Ok(model) = KinematicTree::from_tree(&tree) else {
                return;
            };
            let Ok(kin) = TreeKinematics::new(&model.with_floating_base(tree.floating_root)) else {
                return;
            };
            for mesh_mode in [MeshMode::Exact, MeshMode::ConvexHull] {
                let options = Options {
                    mesh_mode,
                    ..Options::default()
                };
                let Ok(body) = CollisionModel::new(&kin, options) else {
                    return;
                };
                let mut ws = CollisionWorkspace::new(&kin, &body);
                let mut q = screwkit_solve::tree::configuration::neutral(&kin);
                let mut out = Vec::new();
                for k in 0..2 {
                    if k == 1 {
                        for (i, x) in q
                            .iter_mut()
                            .enumerate()
                            .skip(usize::from(tree.floating_root) * 7)
                        {
                            *x += 0.3 * (i as f64 + 1.0);
                        }
                    }
                    let _ = in_collision(&body, &mut ws, &kin, &q);
                    let _ = distances(&body, &mut ws, &kin, &q, &mut out);
                    let _ = min_distance(&body, &mut ws, &kin, &q);
                }
            }
        },
    );
    assert!(n > 0);
}
