//! IK that keeps clear of contact ([`ChainClearance`] with `ik::solve_clear`): the bundled
//! Panda with a sphere on each link, a table and a box. Targets are reachable and clear by
//! construction (FK of random q* whose every pair is at least the margin apart). Every answer
//! is checked by an independent FK call and by the minimum over every pair's distance (the
//! `distances` query, not the `clear` test the solver uses); plain IK's answers are shown to
//! collide on the same targets, so the test can fail. Batches equal single calls whatever the
//! thread count. The Python suite checks the same with coal on meshes.

use screwkit_collision::{distances, ChainClearance, CollisionModel, CollisionWorkspace, Options};
use screwkit_lie::Se3;
use screwkit_model::geometry::Shape;
use screwkit_model::{load_chain, load_tree, KinematicTree, XacroOptions};
use screwkit_solve::batch::ik_batch_clear_from;
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{self, Clearance, IkOptions, IkStatus, StopReason};
use screwkit_solve::{Kinematics, TreeKinematics, Workspace};

/// The bundled Panda with a sphere at every link's frame (radius `r` for the big links),
/// written to a file of its own.
fn panda_with_spheres() -> std::path::PathBuf {
    static PATH: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    PATH.get_or_init(write_panda_with_spheres).clone()
}

fn write_panda_with_spheres() -> std::path::PathBuf {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/urdf/panda.urdf");
    let text = std::fs::read_to_string(src).unwrap();
    // Each link's segment to its child joint (the Panda's joint origins), and a radius.
    let segment = |link: &str| -> Option<([f64; 3], f64)> {
        Some(match link {
            "panda_link0" => ([0.0, 0.0, 0.333], 0.08),
            "panda_link1" => ([0.0, 0.0, 0.0], 0.06),
            "panda_link2" => ([0.0, -0.316, 0.0], 0.06),
            "panda_link3" => ([0.0825, 0.0, 0.0], 0.055),
            "panda_link4" => ([-0.0825, 0.384, 0.0], 0.055),
            "panda_link5" => ([0.0, 0.0, 0.0], 0.05),
            "panda_link6" => ([0.088, 0.0, 0.0], 0.04),
            "panda_link7" => ([0.0, 0.0, 0.107], 0.04),
            "panda_hand" => ([0.0, 0.0, 0.06], 0.05),
            _ => return None,
        })
    };
    let mut out = String::new();
    for line in text.lines() {
        if let Some(rest) = line.trim().strip_prefix("<link name=\"") {
            let name = &rest[..rest.find('"').unwrap()];
            if let (Some((p, r)), true) = (segment(name), line.trim().ends_with("/>")) {
                out.push_str(&format!("  <link name=\"{name}\">\n"));
                // Spheres along the segment, at most 0.12 m apart.
                let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                let count = (len / 0.12).ceil() as usize;
                for k in 0..=count {
                    let t = if count == 0 {
                        0.0
                    } else {
                        k as f64 / count as f64
                    };
                    out.push_str(&format!(
                        "    <collision><origin xyz=\"{} {} {}\"/><geometry><sphere radius=\"{r}\"/></geometry></collision>\n",
                        p[0] * t, p[1] * t, p[2] * t
                    ));
                }
                out.push_str("  </link>\n");
                continue;
            }
        }
        out.push_str(line);
        out.push('\n');
    }
    let dir = std::env::temp_dir().join(format!("screwkit-clearance-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("panda_spheres.urdf");
    std::fs::write(&path, out).unwrap();
    path
}

struct Setup {
    chain: Kinematics,
    tree: TreeKinematics,
    model: CollisionModel,
}

fn setup() -> Setup {
    let path = panda_with_spheres();
    let chain = Kinematics::new(&load_chain(&path, None, None).unwrap());
    let t = load_tree(&path, &XacroOptions::default()).unwrap();
    let tree = TreeKinematics::new(&KinematicTree::from_tree(&t).unwrap()).unwrap();
    let mut model = CollisionModel::new(&tree, Options::default()).unwrap();
    // Pairs touching at home are allowed (MoveIt's "Default" rule): the shoulder's spheres.
    let mut ws = CollisionWorkspace::new(&tree, &model);
    let mut found = Vec::new();
    let home = screwkit_solve::tree::configuration::neutral(&tree);
    distances(&model, &mut ws, &tree, &home, &mut found).unwrap();
    let touching: Vec<(String, String)> = found
        .iter()
        .filter(|d| d.distance < 0.02)
        .map(|d| {
            let (a, b) = model.pairs().nth(d.pair).unwrap();
            (model.owner(a).to_string(), model.owner(b).to_string())
        })
        .collect();
    for (a, b) in touching {
        model.disable(&a, &b).unwrap();
    }
    let table = Shape::Box {
        size: [0.6, 1.2, 0.05],
    };
    model
        .add_obstacle(
            "table",
            &table,
            Se3::from_xyz_rpy([0.6, 0.0, 0.1], [0.0; 3]).unwrap(),
        )
        .unwrap();
    let block = Shape::Box {
        size: [0.15, 0.15, 0.15],
    };
    model
        .add_obstacle(
            "box",
            &block,
            Se3::from_xyz_rpy([0.45, -0.3, 0.35], [0.0; 3]).unwrap(),
        )
        .unwrap();
    Setup { chain, tree, model }
}

/// The smallest distance over every checked pair at the chain's q (the tree's other joints at
/// home), by the `distances` query.
fn min_distance(s: &Setup, q: &[f64]) -> f64 {
    let mut tq = screwkit_solve::tree::configuration::neutral(&s.tree);
    for (name, x) in s.chain.names().iter().zip(q) {
        let k = s.tree.q_names().iter().position(|n| n == name).unwrap();
        tq[k] = *x;
    }
    let mut ws = CollisionWorkspace::new(&s.tree, &s.model);
    let mut found = Vec::new();
    distances(&s.model, &mut ws, &s.tree, &tq, &mut found).unwrap();
    found
        .iter()
        .map(|d| d.distance)
        .fold(f64::INFINITY, f64::min)
}

const MARGIN: f64 = 0.01;

/// `count` targets FK(q*) with q* clear by the margin.
fn targets(s: &Setup, count: usize) -> (Vec<Se3>, Vec<Vec<f64>>) {
    let mut rng = screwkit_solve::sample::SplitMix64(3);
    let mut ws = Workspace::new(&s.chain);
    let (mut out, mut qs) = (Vec::new(), Vec::new());
    let mut q = vec![0.0; s.chain.dof()];
    while out.len() < count {
        screwkit_solve::sample::configuration_into(&s.chain, &mut rng, &mut q);
        let t = fk(&s.chain, &mut ws, &q).unwrap();
        let p = t.translation();
        // The tool over the table, at most 0.2 m above its top (z = 0.125).
        let near = (0.3..0.9).contains(&p.x) && p.y.abs() < 0.6 && p.z < 0.325;
        if near && min_distance(s, &q) >= MARGIN + 0.005 {
            out.push(t);
            qs.push(q.clone());
        }
    }
    (out, qs)
}

#[test]
fn answers_are_clear_and_reach_the_target() {
    let s = setup();
    let base = screwkit_solve::tree::configuration::neutral(&s.tree);
    let body = ChainClearance::new(&s.model, &s.tree, s.chain.names(), base, MARGIN).unwrap();
    let (goals, _) = targets(&s, 300);
    let mut ws = Workspace::new(&s.chain);
    let mut scratch = body.scratch();
    let opts = IkOptions::default();
    let seed = s.chain.midpoint();
    let (mut solved, mut plain_colliding) = (0, 0);
    for t in &goals {
        let r = ik::solve_clear(&s.chain, &mut ws, t, &seed, &opts, &body, &mut scratch).unwrap();
        if r.status.converged {
            solved += 1;
            let reached = fk(&s.chain, &mut ws, &r.q).unwrap();
            assert!(reached.max_abs_diff(t) < 1e-8);
            assert!(s.chain.within_limits(&r.q, 0.0));
            let d = min_distance(&s, &r.q);
            assert!(
                d >= MARGIN - 1e-9,
                "answer {d} m from contact, margin {MARGIN}"
            );
        } else {
            assert_eq!(r.status.stop, StopReason::InCollision, "{:?}", r.status);
        }
        let plain = ik::solve(&s.chain, &mut ws, t, &seed, &opts).unwrap();
        if plain.status.converged && min_distance(&s, &plain.q) < MARGIN {
            plain_colliding += 1;
        }
    }
    eprintln!(
        "clear IK solved {solved} of {}; plain IK's answer collided on {plain_colliding}",
        goals.len()
    );
    // Plain IK's answers collide on some of these targets; keeping clear solves ≥ 99 %.
    assert!(
        plain_colliding >= 5,
        "plain IK collided on {plain_colliding}"
    );
    assert!(
        solved * 100 >= goals.len() * 99,
        "{solved} of {}",
        goals.len()
    );

    // Rejection alone (restarts until an answer is clear) is right too, if slower.
    let mut reject = body.clone();
    reject.steer = false;
    let mut rs = reject.scratch();
    let mut rejected_solved = 0;
    for t in &goals {
        let r = ik::solve_clear(&s.chain, &mut ws, t, &seed, &opts, &reject, &mut rs).unwrap();
        if r.status.converged {
            rejected_solved += 1;
            assert!(min_distance(&s, &r.q) >= MARGIN - 1e-9);
        }
    }
    eprintln!("rejection alone solved {rejected_solved}");
}

#[test]
fn batches_equal_single_calls_on_any_thread_count() {
    let s = setup();
    let base = screwkit_solve::tree::configuration::neutral(&s.tree);
    let body = ChainClearance::new(&s.model, &s.tree, s.chain.names(), base, MARGIN).unwrap();
    let (goals, _) = targets(&s, 40);
    let mut flat = vec![0.0; goals.len() * 16];
    for (t, row) in goals.iter().zip(flat.chunks_mut(16)) {
        t.write_row_major(row);
    }
    let n = s.chain.dof();
    let opts = IkOptions {
        seed: 9,
        ..IkOptions::default()
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut q = vec![0.0; goals.len() * n];
        let mut st = vec![IkStatus::unsolved(); goals.len()];
        pool.install(|| {
            ik_batch_clear_from(
                &s.chain, 5, &flat, None, &opts, &body, &mut q, &mut st, None,
            )
            .unwrap()
        });
        (q, st)
    };
    let (q1, st1) = run(1);
    let (q2, st2) = run(2);
    assert_eq!(q1, q2);
    assert_eq!(st1, st2);
    let mut ws = Workspace::new(&s.chain);
    let mut scratch = body.scratch();
    for (k, t) in goals.iter().enumerate() {
        let o = IkOptions {
            seed: screwkit_solve::batch::row_seed(9, 5 + k),
            ..IkOptions::default()
        };
        let r = ik::solve_clear(
            &s.chain,
            &mut ws,
            t,
            &s.chain.midpoint(),
            &o,
            &body,
            &mut scratch,
        )
        .unwrap();
        assert_eq!(r.q, q1[k * n..(k + 1) * n]);
        assert_eq!(r.status, st1[k]);
    }
}

#[test]
fn a_bad_margin_is_refused() {
    let s = setup();
    let base = screwkit_solve::tree::configuration::neutral(&s.tree);
    for m in [-0.1, f64::NAN, f64::INFINITY, 1e9] {
        let e =
            ChainClearance::new(&s.model, &s.tree, s.chain.names(), base.clone(), m).unwrap_err();
        assert!(e.to_string().contains("margin"), "{e}");
    }
}
