//! Robots from screw axes: how rows are read, what is refused, and that descriptions and tables
//! read back into the same robot.

use screwkit_lie::{Frame, Se3, Twist};
use screwkit_model::{table, ErrorKind, JointKind, ScrewRobot};

const M: [f64; 16] = [
    -1., 0., 0., 0., 0., 1., 0., 6., 0., 0., -1., 2., 0., 0., 0., 1.,
];

fn robot(screws: Vec<[f64; 6]>, limits: Option<Vec<(f64, f64)>>) -> ScrewRobot {
    ScrewRobot::new("test", M, screws, Frame::Space, limits, None).unwrap()
}

#[test]
fn rows_are_revolute_helical_or_prismatic() {
    // Modern Robotics' FKinSpace example: revolute, prismatic, helical of pitch 0.1.
    let r = robot(
        vec![
            [0., 0., 1., 4., 0., 0.],
            [0., 0., 0., 0., 1., 0.],
            [0., 0., -1., -6., 0., -0.1],
        ],
        None,
    );
    let c = r.chain().unwrap();
    let kinds: Vec<JointKind> = c.joints.iter().map(|j| j.kind).collect();
    assert_eq!(
        kinds,
        [
            JointKind::Continuous,
            JointKind::Prismatic,
            JointKind::Helical
        ]
    );
    assert_eq!(c.joints[2].s_space.pitch(), Some(0.1));
    assert_eq!(c.variables[0].lower, f64::NEG_INFINITY);
    // With limits a revolute joint is revolute.
    let limited = robot(vec![[0., 0., 1., 4., 0., 0.]], Some(vec![(-1.0, 1.0)]));
    assert_eq!(limited.chain().unwrap().joints[0].kind, JointKind::Revolute);
    // B_i = [Ad_M^-1] S_i, and the body-frame description gives back S.
    let m = Se3::from_row_major(&M, 1e-12).unwrap();
    for j in &c.joints {
        let b = m.adjoint_inverse_apply(j.s_space.twist());
        assert!((b.to_vector() - j.b_body.twist().to_vector()).amax() == 0.0);
    }
    let body = ScrewRobot {
        frame: Frame::Body,
        joints: r
            .joints
            .iter()
            .zip(&c.joints)
            .map(|(sj, cj)| {
                let mut sj = sj.clone();
                sj.screw
                    .copy_from_slice(cj.b_body.twist().to_vector().as_slice());
                sj
            })
            .collect(),
        ..r.clone()
    };
    let cb = body.chain().unwrap();
    assert_eq!(cb.joints[2].kind, JointKind::Helical);
    for (a, b) in c.joints.iter().zip(&cb.joints) {
        assert!((a.s_space.twist().to_vector() - b.s_space.twist().to_vector()).amax() < 1e-14);
    }
    // The tree holds the same screws to rounding, the helical joint with its pitch.
    let tree = r.tree().unwrap();
    let kt = screwkit_model::KinematicTree::from_tree(&tree).unwrap();
    for (a, b) in c.joints.iter().zip(&kt.joints) {
        let d = a.s_space.twist().to_vector() - b.s_space.twist().to_vector();
        assert!(d.amax() < 1e-15, "{}: {d}", a.name);
    }
}

#[test]
fn unit_rows_are_normalised_to_1e6() {
    // (0.6, 0.8, 0) typed 5e-7 long: accepted and normalised.
    let typed = robot(vec![[0.6000003, 0.8000004, 0., 0., 0., 0.]], None);
    let w = typed.chain().unwrap().joints[0].s_space.twist().w;
    assert!((w.norm() - 1.0).abs() < 1e-15);
    assert!((w.x - 0.6).abs() < 1e-15 && (w.y - 0.8).abs() < 1e-15);
    // 2e-6 long: refused.
    assert!(
        robot(vec![[0.600_001_2, 0.800_001_6, 0., 0., 0., 0.]], None)
            .chain()
            .is_err()
    );
}

#[test]
fn bad_rows_are_named() {
    let err = |screws: Vec<[f64; 6]>| robot(screws, None).chain().unwrap_err();
    let e = err(vec![[0., 0., 1., 0., 0., 0.], [0., 0., 1.1, 0., 0., 0.]]);
    assert!(
        matches!(&e.kind, ErrorKind::Screw { row: 1, joint, .. } if joint == "joint2"),
        "{e}"
    );
    assert!(e.to_string().contains("‖ω‖ = 1.1"), "{e}");
    let e = err(vec![[0., 0., 0., 0., 0., 2.]]);
    assert!(e.to_string().contains("ω = 0 and ‖v‖ = 2"), "{e}");
    let e = err(vec![[0., 0., 1., f64::NAN, 0., 0.]]);
    assert!(e.to_string().contains("NaN"), "{e}");
    let e = ScrewRobot::new(
        "t",
        M,
        vec![[0., 0., 1., 0., 0., 0.]; 2],
        Frame::Space,
        Some(vec![(0., 1.)]),
        None,
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("limits has 1 rows for 2 screw axes"),
        "{e}"
    );
    let e = ScrewRobot::new(
        "t",
        M,
        vec![[0., 0., 1., 0., 0., 0.]],
        Frame::Space,
        None,
        Some(vec![String::new()]),
    )
    .unwrap()
    .chain()
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("screw row 0 (joint \"\"): the joint has an empty name"),
        "{e}"
    );
    let mut bad_m = M;
    bad_m[0] = 2.0;
    let e = ScrewRobot::new(
        "t",
        bad_m,
        vec![[0., 0., 1., 0., 0., 0.]],
        Frame::Space,
        None,
        None,
    )
    .unwrap()
    .chain()
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("home pose M is not a rigid transform"),
        "{e}"
    );
}

#[test]
fn descriptions_and_tables_read_back_into_the_same_robot() {
    let axis = Twist::new(
        nalgebra::Vector3::new(0.36, 0.48, 0.8),
        nalgebra::Vector3::new(0.1, -0.3, 0.2),
    );
    let r = robot(
        vec![
            [0., 0., 1., 4., 0., 0.],
            axis.to_vector().as_slice().try_into().unwrap(),
            [0., 0., 0., 0.6, 0.8, 0.],
        ],
        Some(vec![(-1.0, 2.0), (f64::NEG_INFINITY, 3.0), (0.0, 0.5)]),
    );
    let c = r.chain().unwrap();
    let again = table::read_screw_table(&r.to_json().to_string(), "x").unwrap();
    assert_eq!(
        again.chain().unwrap(),
        ScrewRobot {
            source: "x".into(),
            ..r.clone()
        }
        .chain()
        .unwrap()
    );
    // The table screwkit prints (`table --format json`) gives the same chain, bit for bit.
    let from_table = table::read_screw_table(&table::to_json(&c).to_string(), "test").unwrap();
    let ct = from_table.chain().unwrap();
    assert_eq!(ct.home, c.home);
    for (a, b) in c.joints.iter().zip(&ct.joints) {
        assert_eq!(a.s_space, b.s_space);
        assert_eq!(a.b_body, b.b_body);
        assert_eq!(a.kind, b.kind);
    }
    assert_eq!(ct.variables, c.variables);
    // Not a table at all.
    assert!(!table::is_screw_table("<robot name=\"x\"/>"));
    let e = table::read_screw_table("{\"joints\": 3}", "t.json").unwrap_err();
    assert!(
        e.to_string().starts_with("t.json: not a screw table"),
        "{e}"
    );
}
