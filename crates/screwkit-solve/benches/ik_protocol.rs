//! The IK protocol of the performance issue, on the bundled UR5-, Panda- and iiwa-class arms:
//! q* uniform within limits (fixed seed), target = FK(q*), initial guess = limit midpoints,
//! success = rotation error ≤ 1e-5 rad and position error ≤ 1e-5 m by an independent FK call,
//! with the solution within limits; 5 ms wall-time cap per query; failures count in the times.
//! Prints solve rate, mean, median and p99 per method. Run:
//! `cargo bench -p screwkit-solve --bench ik_protocol [-- N]`.

use std::time::Instant;

use screwkit_solve::fk::fk_unchecked;
use screwkit_solve::ik::{solve, IkMethod, IkOptions};
use screwkit_solve::{Kinematics, Workspace};

fn main() {
    let n: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(2000);
    for name in ["ur5", "panda", "iiwa14"] {
        let chain = screwkit_model::load_chain(
            format!(
                "{}/../../assets/urdf/{name}.urdf",
                env!("CARGO_MANIFEST_DIR")
            ),
            None,
            None,
        )
        .unwrap();
        let kin = Kinematics::new(&chain);
        let mut ws = Workspace::new(&kin);
        for (label, method) in [
            ("lm", IkMethod::LM),
            ("nr", IkMethod::NewtonRaphson),
            ("dls", IkMethod::DLS),
        ] {
            let opts = IkOptions {
                method,
                ..IkOptions::default()
            };
            let mut s = 0x00C0_FFEE_1234_5678u64;
            let mut times = Vec::with_capacity(n);
            let (mut ok, mut iters) = (0usize, 0usize);
            let seed = kin.midpoint();
            for _ in 0..n {
                let q_star: Vec<f64> = (0..kin.dof())
                    .map(|k| {
                        s ^= s << 13;
                        s ^= s >> 7;
                        s ^= s << 17;
                        let u = (s >> 11) as f64 / (1u64 << 53) as f64;
                        kin.lower()[k] + (kin.upper()[k] - kin.lower()[k]) * u
                    })
                    .collect();
                let target = fk_unchecked(&kin, &q_star);
                let t0 = Instant::now();
                let r = solve(&kin, &mut ws, &target, &seed, &opts).unwrap();
                times.push(t0.elapsed().as_secs_f64() * 1e6);
                iters += r.iterations;
                let t = fk_unchecked(&kin, &r.q);
                let d = t.inverse_compose(&target);
                let rot = screwkit_lie::so3::log(d.rotation()).norm();
                let pos = (t.translation() - target.translation()).norm();
                if rot <= 1e-5 && pos <= 1e-5 && kin.within_limits(&r.q, 0.0) {
                    ok += 1;
                }
            }
            times.sort_by(f64::total_cmp);
            let mean = times.iter().sum::<f64>() / n as f64;
            println!(
                "{name:<7} {label:<4} solved {:6.2}%  mean {:7.1} µs  median {:7.1} µs  p99 {:7.1} µs  iterations/solve {:5.1}",
                100.0 * ok as f64 / n as f64,
                mean,
                times[n / 2],
                times[(n * 99) / 100],
                iters as f64 / n as f64
            );
        }
    }
}
