//! Whole-body IK steps with collision avoidance, split by cost: the scenario of
//! `crates/screwkit-py/benchmarks/collision_avoidance_bench.py` (example-robot-data's TALOS,
//! its collision meshes as convex hulls, a table; the right gripper driven under the table top
//! by a position task of gain 0.05 beside a posture task (weight 0.01) and damping (0.3); dt =
//! 5 ms, 1,000 steps; the right arm's (`PAIRS=hand`: the wrist and gripper's) pairs with the
//! table, the torso and the base; margin 5 mm, detection 5 cm, gain 0.85), run in Rust without
//! Python's call. Per step, along the same trajectory: the whole step with the limit, the step
//! without it (at the same q), and the limit's rows alone; the rest is the QP with rows and
//! the re-tightening; the rows' own parts (`close_pairs`: placing the shapes, measuring the
//! pairs within the detection distance, their rows, the contact patches within 2 mm of the
//! margin) and each close pair's share; and the chatter (‖v_k − v_{k−1}‖ after the first 20
//! steps). Interleaved rounds, minimum kept.
//!
//! Run: `cargo bench -p screwkit-collision --bench avoidance` (example-robot-data from
//! `SCREWKIT_ERD_SHARE` or the venv of `cargo xtask test`).

use std::sync::Arc;
use std::time::Instant;

use screwkit_collision::{CollisionAvoidance, CollisionModel, Options};
use screwkit_lie::Se3;
use screwkit_model::{KinematicTree, XacroOptions};
use screwkit_solve::tree::configuration::integrate;
use screwkit_solve::tree::differential_ik::{ik_step, DiffIkWorkspace, Limits};
use screwkit_solve::tree::fk::fk_frame;
use screwkit_solve::tree::limits::Limit;
use screwkit_solve::tree::tasks::Task;
use screwkit_solve::tree::TreeWorkspace;
use screwkit_solve::TreeKinematics;

fn main() {
    let Some(share) = screwkit_testkit::example_robot_data() else {
        eprintln!(
            "skipped: no example-robot-data (set SCREWKIT_ERD_SHARE, or run cargo xtask test)"
        );
        return;
    };
    println!("host: {}", screwkit_testkit::protocol::host());
    let urdf = share.join("example-robot-data/robots/talos_data/robots/talos_reduced.urdf");
    let opts = XacroOptions {
        package_paths: vec![share.clone()],
        ..Default::default()
    };
    let tree = screwkit_model::load_tree(&urdf, &opts).unwrap();
    let kin = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
    let mut model = CollisionModel::new(
        &kin,
        Options {
            mesh_mode: screwkit_collision::MeshMode::ConvexHull,
            ..Options::default()
        },
    )
    .unwrap();
    let table = Se3::from_parts_unchecked(
        nalgebra::Matrix3::identity(),
        nalgebra::Vector3::new(0.45, 0.0, -0.25),
    );
    model
        .add_obstacle(
            "table",
            &screwkit_model::geometry::Shape::Box {
                size: [0.4, 1.0, 0.05],
            },
            table,
        )
        .unwrap();
    let hand_only = std::env::var("PAIRS").is_ok_and(|p| p == "hand");
    let others: &[&str] = if hand_only {
        &["table"]
    } else {
        &["table", "torso_1_link", "torso_2_link", "base_link"]
    };
    let mut pairs = Vec::new();
    for (a, b) in (0..model.pair_count()).map(|k| model.pair_names(k)) {
        for (x, y) in [(a, b), (b, a)] {
            let arm =
                x.contains("right") && !x.contains("leg") && !(hand_only && x.contains("arm_"));
            if arm && others.contains(&y) {
                pairs.push((x.to_string(), y.to_string()));
            }
        }
    }
    pairs.sort();
    pairs.dedup();
    let model_copy = model.clone();
    let avoid: Arc<dyn Limit> = Arc::new(
        CollisionAvoidance::new(Arc::new(model), &kin, Some(&pairs), 0.005, 0.05, 0.85).unwrap(),
    );
    println!("{} link pairs constrained", pairs.len());

    let names = kin.q_names().to_vec();
    let (lower, upper) = (kin.lower(), kin.upper());
    let mut q0: Vec<f64> = (0..kin.nq())
        .map(|i| 0.0_f64.clamp(lower[i], upper[i]))
        .collect();
    for (name, value) in [
        ("arm_left_2_joint", 0.4),
        ("arm_right_2_joint", -0.4),
        ("arm_left_4_joint", -1.2),
        ("arm_right_4_joint", -1.2),
    ] {
        q0[names.iter().position(|n| n == name).unwrap()] = value;
    }
    let hand = kin.frame("gripper_right_base_link").unwrap();
    let mut tws = TreeWorkspace::new(&kin);
    let start = fk_frame(&kin, &mut tws, &q0, hand).unwrap();
    let target =
        Se3::from_parts_unchecked(*start.rotation(), nalgebra::Vector3::new(0.45, -0.2, -0.45));
    let mut frame = Task::frame(hand, target).with_gain(0.05);
    frame.orientation_weight = [0.0; 3];
    let tasks = vec![
        frame,
        Task::posture(q0.clone()).with_weight(1e-2),
        Task::damping(0.3),
    ];
    let dt = 0.005;
    let with = Limits {
        extra: vec![avoid.clone()],
        ..Limits::default()
    };
    let without = Limits::default();
    let mut ws = DiffIkWorkspace::new(&kin);

    // The trajectory with the limit.
    let mut qs = vec![q0.clone()];
    let mut rows = Vec::new();
    let mut vs: Vec<Vec<f64>> = Vec::new();
    for _ in 0..1000 {
        let q = qs.last().unwrap().clone();
        let v = ik_step(&kin, &mut ws, &q, &tasks, dt, &with)
            .unwrap()
            .to_vec();
        vs.push(v.clone());
        rows.push(ws.rows().1.len());
        if std::env::var("BINDABLE").is_ok() {
            let (g, h) = ws.rows();
            let (_, _, lo, hi) = ws.qp();
            let nv = lo.len();
            let bindable = g
                .chunks(nv)
                .zip(h)
                .filter(|(row, &hk)| {
                    let min: f64 = row
                        .iter()
                        .zip(lo.iter().zip(hi.iter()))
                        .map(|(gi, (l, u))| (gi * l).min(gi * u))
                        .sum();
                    min < hk
                })
                .count();
            eprint!("{}/{} ", bindable, h.len());
        }
        qs.push(integrate(&kin, &q, &v, dt).unwrap());
    }
    qs.pop();
    // Chatter: the step-to-step change of v after the first 20 steps, against |v|.
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut dv: Vec<f64> = vs[20..]
        .windows(2)
        .map(|w| {
            norm(
                &w[1]
                    .iter()
                    .zip(&w[0])
                    .map(|(a, b)| a - b)
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    dv.sort_by(f64::total_cmp);
    let vmax = vs[20..].iter().map(|v| norm(v)).fold(0.0, f64::max);
    println!(
        "chatter: ‖Δv‖ p99 {:.3}, max {:.3} (‖v‖ max {vmax:.3}; p99/max ‖v‖ {:.3})",
        dv[dv.len() * 99 / 100],
        dv[dv.len() - 1],
        dv[dv.len() * 99 / 100] / vmax
    );
    let (mut full, mut plain, mut only_rows) = (f64::MAX, f64::MAX, f64::MAX);
    let (mut g, mut h, mut tags) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..5 {
        let t0 = Instant::now();
        for q in &qs {
            std::hint::black_box(ik_step(&kin, &mut ws, q, &tasks, dt, &with).unwrap());
        }
        full = full.min(t0.elapsed().as_secs_f64());
        let t0 = Instant::now();
        for q in &qs {
            std::hint::black_box(ik_step(&kin, &mut ws, q, &tasks, dt, &without).unwrap());
        }
        plain = plain.min(t0.elapsed().as_secs_f64());
        let t0 = Instant::now();
        for q in &qs {
            g.clear();
            h.clear();
            tags.clear();
            avoid.rows(&kin, q, &mut g, &mut h, &mut tags).unwrap();
        }
        only_rows = only_rows.min(t0.elapsed().as_secs_f64());
    }
    let us = |s: f64| s / qs.len() as f64 * 1e6;
    {
        // The rows' parts: placing alone, distances alone, with rows (no patch, patch).
        let model = screwkit_collision::CollisionModel::clone(&model_copy);
        let sel: Vec<bool> = (0..model.pair_count())
            .map(|k| {
                let (a, b) = model.pair_names(k);
                pairs
                    .iter()
                    .any(|(x, y)| (x == a && y == b) || (x == b && y == a))
            })
            .collect();
        let mut cws = screwkit_collision::CollisionWorkspace::new(&kin, &model);
        let (mut found, mut r) = (Vec::new(), Vec::new());
        let mut best = [f64::MAX; 4];
        for _ in 0..5 {
            for (i, (within, patch, rows)) in [
                (-1.0, -1.0, false),
                (0.055, -1.0, false),
                (0.055, -1.0, true),
                (0.055, 0.007, true),
            ]
            .into_iter()
            .enumerate()
            {
                let t0 = Instant::now();
                for q in &qs {
                    screwkit_collision::query::close_pairs(
                        &model,
                        &mut cws,
                        &kin,
                        q,
                        within,
                        patch,
                        Some(&sel),
                        &mut found,
                        if rows { Some(&mut r) } else { None },
                    )
                    .unwrap();
                }
                best[i] = best[i].min(t0.elapsed().as_secs_f64());
            }
        }
        for k in 0..model.pair_count() {
            if !sel[k] {
                continue;
            }
            let mut one = vec![false; model.pair_count()];
            one[k] = true;
            let mut bestk = f64::MAX;
            let mut hits = 0;
            for _ in 0..3 {
                let t0 = Instant::now();
                hits = 0;
                for q in &qs {
                    screwkit_collision::query::close_pairs(
                        &model,
                        &mut cws,
                        &kin,
                        q,
                        0.055,
                        -1.0,
                        Some(&one),
                        &mut found,
                        None,
                    )
                    .unwrap();
                    hits += found.len();
                }
                bestk = bestk.min(t0.elapsed().as_secs_f64());
            }
            println!(
                "  pair {:?}: {:.2} µs per step incl. placing, within detection on {hits} steps",
                model.pair_names(k),
                us(bestk) - us(best[0])
            );
        }
        println!(
            "close_pairs: placing {:.1} µs, distances {:.1}, + rows {:.1}, + patches {:.1}",
            us(best[0]),
            us(best[1]),
            us(best[2]),
            us(best[3])
        );
    }
    let with_rows = rows.iter().filter(|&&r| r > 0).count();
    println!(
        "per step: {:.1} µs with the limit = {:.1} the step without it + {:.1} the rows + {:.1} \
         the QP with rows and re-tightening; {with_rows} of {} steps have rows (mean {:.1}, max {})",
        us(full),
        us(plain),
        us(only_rows),
        us(full - plain - only_rows),
        qs.len(),
        rows.iter().sum::<usize>() as f64 / with_rows.max(1) as f64,
        rows.iter().max().unwrap_or(&0),
    );
}
