//! The IK benchmark protocol of BENCHMARKS.md ([`screwkit_testkit::protocol`]) on the bundled
//! UR5-, Panda- and iiwa-class arms, per method, and the UR5 scaled by 1e-5 … 1e4 (scale-free
//! IK: about the same time at every size). Run:
//! `cargo bench -p screwkit-solve --bench ik_protocol [-- N]`.

use screwkit_solve::ik::{IkMethod, IkOptions};
use screwkit_solve::Kinematics;
use screwkit_testkit::protocol;

fn main() {
    let n: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(2000);
    for name in ["ur5", "panda", "iiwa14"] {
        let chain = screwkit_model::load_chain(
            screwkit_testkit::bundled(&format!("{name}.urdf")),
            None,
            None,
        )
        .unwrap();
        let kin = Kinematics::new(&chain);
        for (label, method) in [
            ("lm", IkMethod::LM),
            ("nr", IkMethod::NewtonRaphson),
            ("dls", IkMethod::DLS),
        ] {
            let opts = IkOptions {
                method,
                timeout: Some(screwkit_testkit::protocol::TIME_CAP),
                ..IkOptions::default()
            };
            let r = protocol::run(&kin, n, 42, &opts);
            println!(
                "{name:<7} {label:<4} solved {:6.2}%  mean {:7.1} µs  median {:7.1} µs  p99 {:7.1} µs  iterations/solve {:5.1}  FK {:5.0} ns  FK+J {:5.0} ns",
                100.0 * r.solve_rate(),
                r.mean_us,
                r.median_us,
                r.p99_us,
                r.mean_iterations,
                r.fk_ns,
                r.jacobian_ns
            );
        }
    }
    // Scale-free IK: the UR5 s times its size, LM, the same protocol (targets scale with it;
    // the success check is the protocol's absolute 1e-5, so compare the times).
    for s in [1e-5, 1e-3, 1.0, 1e3, 1e4] {
        let kin = Kinematics::new(&screwkit_testkit::scaled_chain("ur5.urdf", s));
        let opts = IkOptions {
            timeout: Some(screwkit_testkit::protocol::TIME_CAP),
            ..IkOptions::default()
        };
        let r = protocol::run(&kin, n, 42, &opts);
        println!(
            "ur5 x{s:<7e} lm   converged-rate {:6.2}%  mean {:7.1} µs  median {:7.1} µs  p99 {:7.1} µs  iterations/solve {:5.1}",
            100.0 * r.solve_rate(),
            r.mean_us,
            r.median_us,
            r.p99_us,
            r.mean_iterations,
        );
    }
}
