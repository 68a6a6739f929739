//! Each link's `<collision>` and `<visual>` shapes (`screwkit_model::geometry`): every kind read
//! with its origin, scale and colour; mesh paths resolved relative to the file, through
//! `package://` and `file://`; an element that cannot be read is a problem naming its link,
//! never a reason the robot does not load.

use screwkit_model::geometry::{Role, Shape};
use screwkit_model::{load_tree, XacroOptions};

fn asset(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets")
        .join(path)
}

/// The bundled humanoid: one collision and one visual shape per element of the file, on the
/// link that holds it, with the file's numbers.
#[test]
fn the_humanoid_has_its_primitives() {
    let path = asset("urdf/humanoid.urdf");
    let text = std::fs::read_to_string(&path).unwrap();
    let tree = load_tree(&path, &XacroOptions::default()).unwrap();
    assert!(
        tree.geometry_problems.is_empty(),
        "{:?}",
        tree.geometry_problems
    );
    let count = |role: Role| tree.geometries.iter().filter(|g| g.role == role).count();
    assert_eq!(count(Role::Collision), text.matches("<collision>").count());
    assert_eq!(count(Role::Visual), text.matches("<visual>").count());
    let pelvis = tree.link("pelvis").unwrap();
    let box_ = tree
        .geometries
        .iter()
        .find(|g| g.link == pelvis && g.role == Role::Collision)
        .unwrap();
    assert_eq!(
        box_.shape,
        Shape::Box {
            size: [0.14, 0.24, 0.08]
        }
    );
    let hip = tree
        .geometries
        .iter()
        .find(|g| matches!(g.shape, Shape::Cylinder { .. }))
        .unwrap();
    assert_eq!(
        hip.shape,
        Shape::Cylinder {
            radius: 0.04,
            length: 0.05
        }
    );
    assert_eq!(hip.origin.translation().z, -0.025);
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, text).unwrap();
    p
}

/// Every shape, origin rpy, a mesh with scale by a relative path, a package and file://, a
/// colour inline and by a named material; and the problems: a malformed number, an unknown
/// shape, two shapes in one geometry, a missing package — the robot still loads.
#[test]
fn every_shape_and_every_problem() {
    let dir = std::env::temp_dir().join(format!("screwkit-geometry-{}", std::process::id()));
    let pkg = dir.join("ws/src/my_robot");
    std::fs::create_dir_all(pkg.join("meshes")).unwrap();
    let urdf = format!(
        r#"<robot name="shapes">
  <material name="blue"><color rgba="0 0 1 1"/></material>
  <link name="a">
    <collision name="body"><origin xyz="1 2 3" rpy="0 0 1.5707963267948966"/>
      <geometry><box size="0.1 0.2 0.3"/></geometry></collision>
    <collision><geometry><sphere radius="0.5"/></geometry></collision>
    <collision><geometry><capsule radius="0.05" length="0.4"/></geometry></collision>
    <visual><geometry><mesh filename="meshes/a.stl" scale="0.001 0.001 0.001"/></geometry>
      <material name="blue"/></visual>
    <visual><geometry><cylinder radius="0.2" length="1"/></geometry>
      <material name="red"><color rgba="1 0 0 0.5"/></material></visual>
  </link>
  <link name="b">
    <collision><geometry><mesh filename="package://my_robot/meshes/b.dae"/></geometry></collision>
    <collision><geometry><mesh filename="file://{abs}"/></geometry></collision>
    <collision><geometry><box size="1 x 1"/></geometry></collision>
    <collision><geometry><cone radius="1"/></geometry></collision>
    <visual><geometry><sphere radius="1"/><box size="1 1 1"/></geometry></visual>
    <collision><geometry><mesh filename="package://nowhere/x.stl"/></geometry></collision>
    <collision><geometry><sphere radius="-1"/></geometry></collision>
    <collision><geometry><mesh filename="package:///my_robot/meshes/d.stl"/></geometry></collision>
  </link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#,
        abs = pkg.join("meshes/c.obj").display()
    );
    let path = write(&dir, "robots/shapes.urdf", &urdf);
    let options = XacroOptions {
        package_paths: vec![dir.join("ws")],
        ..XacroOptions::default()
    };
    let tree = load_tree(&path, &options).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        tree.joints.len(),
        1,
        "kinematics loads whatever the geometry"
    );
    let (a, b) = (tree.link("a").unwrap(), tree.link("b").unwrap());
    let of = |link: usize, role: Role| -> Vec<&screwkit_model::geometry::Geometry> {
        tree.geometries
            .iter()
            .filter(|g| g.link == link && g.role == role)
            .collect()
    };
    let ac = of(a, Role::Collision);
    assert_eq!(ac.len(), 3);
    assert_eq!(ac[0].name.as_deref(), Some("body"));
    assert_eq!(ac[0].origin.translation().as_slice(), &[1.0, 2.0, 3.0]);
    assert!((ac[0].origin.rpy()[2] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(ac[1].shape, Shape::Sphere { radius: 0.5 });
    assert_eq!(
        ac[2].shape,
        Shape::Capsule {
            radius: 0.05,
            length: 0.4
        }
    );
    let av = of(a, Role::Visual);
    let Shape::Mesh {
        uri,
        path: mesh,
        scale,
    } = &av[0].shape
    else {
        panic!("{:?}", av[0].shape)
    };
    assert_eq!(uri, "meshes/a.stl");
    assert_eq!(mesh, &dir.join("robots/meshes/a.stl"));
    assert_eq!(scale, &[0.001; 3]);
    assert_eq!(av[0].rgba, Some([0.0, 0.0, 1.0, 1.0]));
    assert_eq!(av[1].rgba, Some([1.0, 0.0, 0.0, 0.5]));
    let bc = of(b, Role::Collision);
    assert_eq!(bc.len(), 3, "{bc:?}");
    let paths: Vec<_> = bc
        .iter()
        .map(|g| match &g.shape {
            Shape::Mesh { path, .. } => path.clone(),
            s => panic!("{s:?}"),
        })
        .collect();
    assert_eq!(
        std::path::absolute(&paths[0]).unwrap(),
        std::path::absolute(pkg.join("meshes/b.dae")).unwrap()
    );
    assert_eq!(paths[1], pkg.join("meshes/c.obj"));
    // `package:///pkg/…` (an empty package name, as example-robot-data's TALOS writes it):
    // below the package folder's parent, as Pinocchio reads it.
    assert_eq!(
        std::path::absolute(&paths[2]).unwrap(),
        std::path::absolute(pkg.join("meshes/d.stl")).unwrap()
    );
    let problems = tree.geometry_problems.join("\n");
    for expected in [
        "link \"b\" <collision> 3: <box size>: \"x\" is not a number",
        "link \"b\" <collision> 4: unknown shape <cone>",
        "link \"b\" <visual> 1: <geometry> holds more than one shape",
        "link \"b\" <collision> 6: <sphere radius> is -1: it must be > 0",
        "link \"b\" <collision>: mesh \"package://nowhere/x.stl\": package \"nowhere\" not found",
    ] {
        assert!(problems.contains(expected), "{expected}\nin\n{problems}");
    }
    assert_eq!(tree.geometry_problems.len(), 5, "{problems}");
}

/// MJCF geoms: MuJoCo's sizes (half sizes, `fromto`), roles by `contype`/`conaffinity` and
/// group, mesh assets through `meshdir`, the contact rules; a geom that cannot be used is a
/// problem naming its line, and the kinematics still loads.
#[test]
fn mjcf_geoms_and_contact_rules() {
    let text = r#"<mujoco>
  <compiler meshdir="m"/>
  <option><flag filterparent="disable"/></option>
  <asset><mesh file="part.stl" scale="2 2 2"/></asset>
  <worldbody>
    <geom name="floor" type="plane" size="3 3 0.1"/>
    <body name="a">
      <joint name="ja"/>
      <geom name="cap" type="capsule" fromto="0 0 0 0 0 0.4" size="0.05"/>
      <geom name="box" type="box" size="0.1 0.2 0.3" contype="2" conaffinity="0"/>
      <geom name="look" type="sphere" size="0.1" contype="0" conaffinity="0" group="1"/>
      <geom name="hidden" type="ellipsoid" size="0.1 0.2 0.3" group="3"/>
      <geom name="part" type="mesh" mesh="part"/>
      <geom type="hfield"/>
      <geom type="box" mesh="part"/>
      <geom type="cylinder" size="0.1"/>
    </body>
  </worldbody>
  <contact><exclude body1="world" body2="a"/><pair geom1="look" geom2="floor"/></contact>
</mujoco>"#;
    let tree = screwkit_model::mjcf::load_str(text, "t.xml", std::path::Path::new("/r")).unwrap();
    let a = tree.link("a").unwrap();
    let find = |name: &str, role: Role| {
        tree.geometries
            .iter()
            .find(|g| g.name.as_deref() == Some(name) && g.role == role)
    };
    let cap = find("cap", Role::Collision).unwrap();
    assert_eq!(
        cap.shape,
        Shape::Capsule {
            radius: 0.05,
            length: 0.4
        }
    );
    assert!((cap.origin.translation().z - 0.2).abs() < 1e-15);
    let b = find("box", Role::Collision).unwrap();
    assert_eq!(
        b.shape,
        Shape::Box {
            size: [0.2, 0.4, 0.6]
        }
    );
    assert_eq!(b.bits.unwrap().contype, 2);
    assert_eq!(b.link, a);
    // Visual only, but a <pair> names it: a collision shape too.
    assert!(find("look", Role::Collision).is_some());
    assert!(find("look", Role::Visual).is_some());
    // Group 3: MuJoCo's viewer hides it; it still collides.
    assert!(find("hidden", Role::Visual).is_none());
    assert!(find("hidden", Role::Collision).is_some());
    let Shape::Mesh { path, scale, .. } = &find("part", Role::Collision).unwrap().shape else {
        panic!("not a mesh")
    };
    assert_eq!(path, std::path::Path::new("/r/m/part.stl"));
    assert_eq!(*scale, [2.0; 3]);
    let problems = tree.geometry_problems.join("\n");
    assert!(
        problems.contains("t.xml:14: <geom>: type=\"hfield\" is not read"),
        "{problems}"
    );
    assert!(
        problems.contains("t.xml:15: <geom>: a box fitted to a mesh"),
        "{problems}"
    );
    assert!(
        problems.contains("t.xml:16: <geom>: a cylinder needs 2 size number(s)"),
        "{problems}"
    );
    let rules = tree.contact_rules.as_ref().unwrap();
    assert!(!rules.filterparent);
    assert_eq!(rules.world_link, Some(tree.root));
    assert_eq!(rules.exclude, vec![(Some(tree.root), Some(a))]);
    assert_eq!(rules.pairs, vec![("look".to_string(), "floor".to_string())]);
    assert_eq!(rules.body_parent[&a], Some(tree.root));
    assert_eq!(
        tree.geometries
            .iter()
            .filter(|g| g.shape.word() == "plane")
            .count(),
        2
    );
}
