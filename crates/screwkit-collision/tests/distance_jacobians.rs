//! Distance Jacobians against finite differences: for each checked pair apart (a unique closest
//! pair of features), the row J_d times a random velocity v equals the central difference
//! (d(q ⊕ h v) − d(q ⊖ h v)) / 2h, on the bundled humanoid URDF (a fixed base, primitives) and
//! the bundled MJCF humanoid (a free-floating root: q ⊕ v integrates the base on SE(3)).

use screwkit_collision::{
    distance_jacobians, distance_jacobians_batch, distances, CollisionModel, CollisionWorkspace,
    Options, PairDistance,
};
use screwkit_model::{load_tree, KinematicTree, XacroOptions};
use screwkit_solve::tree::configuration::{integrate, neutral};
use screwkit_solve::TreeKinematics;

fn robot(path: &str) -> TreeKinematics {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets")
        .join(path);
    let tree = load_tree(&path, &XacroOptions::default()).unwrap();
    let model = KinematicTree::from_tree(&tree).unwrap();
    TreeKinematics::new(&model.with_floating_base(tree.floating_root)).unwrap()
}

/// A small deterministic generator (no rand dependency in tests).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn check(path: &str, samples: usize) -> usize {
    let kin = robot(path);
    let model = CollisionModel::new(&kin, Options::default()).unwrap();
    assert!(
        model.pair_count() > 10,
        "{path}: {} pairs",
        model.pair_count()
    );
    let mut ws = CollisionWorkspace::new(&kin, &model);
    let (lower, upper) = (kin.lower(), kin.upper());
    let mut rng = Lcg(7);
    let (nq, nv) = (kin.nq(), kin.nv());
    // A floating base's seven entries first (lower/upper cover all of q).
    let base = if nq > nv { 7 } else { 0 };
    let mut checked = 0;
    let (mut d, mut rows, mut plus, mut minus) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..samples {
        let mut q = neutral(&kin);
        for (k, x) in q.iter_mut().enumerate().skip(base) {
            let (lo, hi) = (lower[k].max(-2.0), upper[k].min(2.0));
            *x = lo + (hi - lo) * rng.next();
        }
        if base == 7 {
            // Some base pose: a turn and a shift.
            let v: Vec<f64> = (0..6).map(|_| rng.next() - 0.5).collect();
            let mut dv = vec![0.0; nv];
            dv[..6].copy_from_slice(&v);
            q = integrate(&kin, &q, &dv, 1.0).unwrap();
        }
        distance_jacobians(&model, &mut ws, &kin, &q, &mut d, &mut rows).unwrap();
        let v: Vec<f64> = (0..nv).map(|_| rng.next() - 0.5).collect();
        let h = 1e-6;
        let qp = integrate(&kin, &q, &v, h)
            .map_err(|e| format!("{e} {q:?}"))
            .unwrap();
        let qm = integrate(&kin, &q, &v, -h).unwrap();
        distances(&model, &mut ws, &kin, &qp, &mut plus).unwrap();
        distances(&model, &mut ws, &kin, &qm, &mut minus).unwrap();
        for (k, pd) in d.iter().enumerate() {
            let PairDistance { distance, .. } = *pd;
            if distance < 1e-3 {
                continue;
            }
            let row = &rows[k * nv..(k + 1) * nv];
            let analytic: f64 = row.iter().zip(&v).map(|(a, b)| a * b).sum();
            let numeric = (plus[k].distance - minus[k].distance) / (2.0 * h);
            assert!(
                (analytic - numeric).abs() < 1e-6 * (1.0 + numeric.abs()),
                "{path}: pair {:?} ({} {}) at d = {distance}: J_d v = {analytic}, finite difference {numeric} ({} {})",
                model.pair_names(k), model.objects()[model.pairs().nth(k).unwrap().0].kind, model.objects()[model.pairs().nth(k).unwrap().1].kind, plus[k].distance, minus[k].distance
            );
            checked += 1;
        }
    }
    checked
}

#[test]
fn fixed_base_urdf_humanoid() {
    assert!(check("urdf/humanoid.urdf", 40) > 200);
}

#[test]
fn floating_mjcf_humanoid() {
    assert!(check("mjcf/humanoid.xml", 40) > 200);
}

/// The batch is each row's single call.
#[test]
fn batches_equal_single_calls() {
    let kin = robot("mjcf/humanoid.xml");
    let model = CollisionModel::new(&kin, Options::default()).unwrap();
    let mut ws = CollisionWorkspace::new(&kin, &model);
    let q0 = neutral(&kin);
    let mut qs = Vec::new();
    for k in 0..6 {
        let v: Vec<f64> = (0..kin.nv())
            .map(|i| ((i * 7 + k * 3) % 11) as f64 * 0.05)
            .collect();
        qs.extend(integrate(&kin, &q0, &v, 1.0).unwrap());
    }
    let mut out = vec![(Vec::new(), Vec::new()); 6];
    distance_jacobians_batch(&model, &kin, &qs, &mut out).unwrap();
    let (mut d, mut rows) = (Vec::new(), Vec::new());
    for (k, q) in qs.chunks(kin.nq()).enumerate() {
        distance_jacobians(&model, &mut ws, &kin, q, &mut d, &mut rows).unwrap();
        assert_eq!(out[k].0, d);
        assert_eq!(out[k].1, rows);
    }
}
