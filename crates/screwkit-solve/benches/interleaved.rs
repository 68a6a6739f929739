//! FK, all-link FK and FK + Jacobian of screwkit next to `k` 0.32, interleaved in one process:
//! every round times each kernel over the same 64 configurations (cycled), and the minimum over
//! the rounds is kept. On a shared host whose speed drifts by ±30 % from minute to minute, the
//! minimum of interleaved rounds is far steadier than one long run per kernel, and the ratio
//! to `k` (measured in the same rounds) cancels the host's current speed.
//!
//! Run: `cargo bench -p screwkit-solve --bench interleaved [-- ROUNDS [CALLS]]` (default 25
//! rounds of 100,000 calls per kernel). The last columns rescale screwkit's times to the speed
//! at which `k`'s FK takes 460 ns — the middle of the 400–520 ns measured for `k` on this
//! machine class when the performance targets of BENCHMARKS.md were set — so they can be set
//! against those targets.

use std::hint::black_box;
use std::time::Instant;

use screwkit_solve::fk::{fk, fk_all_links};
use screwkit_solve::jacobian::fk_jacobian;
use screwkit_solve::{Frame, Kinematics, Workspace};

const ROBOTS: &[(&str, &str)] = &[
    ("ur5", "tool0"),
    ("panda", "panda_hand_tcp"),
    ("iiwa14", "iiwa_link_ee"),
];

/// `k`'s FK time at which the rescaled columns are given (ns).
const K_REFERENCE_NS: f64 = 460.0;

/// Nanoseconds per call of `f(i)` over `calls` calls.
fn time(calls: usize, mut f: impl FnMut(usize) -> f64) -> f64 {
    let start = Instant::now();
    let mut sink = 0.0;
    for i in 0..calls {
        sink += f(i);
    }
    black_box(sink);
    start.elapsed().as_nanos() as f64 / calls as f64
}

fn main() {
    let mut args = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse::<usize>().ok());
    let rounds = args.next().unwrap_or(25);
    let calls = args.next().unwrap_or(100_000);
    println!("min over {rounds} interleaved rounds of {calls} calls each (ns per call)\n");
    println!("| robot | k FK | FK | all-link FK | FK + J_s | FK + J_b | k FK + J | k FK ÷ FK | k J ÷ FK + J_s | at k FK = {K_REFERENCE_NS} ns: FK / all / J_s / J_b |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for &(name, tip) in ROBOTS {
        let path = format!(
            "{}/../../assets/urdf/{name}.urdf",
            env!("CARGO_MANIFEST_DIR")
        );
        let kin = Kinematics::new(&screwkit_model::load_chain(&path, None, None).unwrap());
        let arm = k::SerialChain::from_end(
            k::Chain::<f64>::from_urdf_file(&path)
                .unwrap()
                .find_link(tip)
                .unwrap(),
        );
        let n = kin.dof();
        let qs = screwkit_solve::sample::configurations(&kin, 64, 7);
        let q = |i: usize| &qs[(i % 64) * n..(i % 64 + 1) * n];
        let mut ws = Workspace::new(&kin);
        let mut best = [f64::INFINITY; 6];
        for _ in 0..rounds {
            let t = [
                time(calls, |i| {
                    arm.set_joint_positions_unchecked(black_box(q(i)));
                    arm.end_transform().translation.x
                }),
                time(calls, |i| {
                    fk(&kin, &mut ws, black_box(q(i))).unwrap().translation().x
                }),
                time(calls, |i| {
                    fk_all_links(&kin, &mut ws, black_box(q(i))).unwrap()[0]
                        .translation()
                        .x
                }),
                time(calls, |i| {
                    fk_jacobian(&kin, &mut ws, black_box(q(i)), Frame::Space)
                        .unwrap()
                        .jacobian[(0, 0)]
                }),
                time(calls, |i| {
                    fk_jacobian(&kin, &mut ws, black_box(q(i)), Frame::Body)
                        .unwrap()
                        .jacobian[(0, 0)]
                }),
                time(calls, |i| {
                    arm.set_joint_positions_unchecked(black_box(q(i)));
                    k::jacobian(&arm)[(0, 0)]
                }),
            ];
            for (b, x) in best.iter_mut().zip(t) {
                *b = b.min(x);
            }
        }
        let [k_fk, fk, all, js, jb, k_j] = best;
        let s = K_REFERENCE_NS / k_fk;
        println!(
            "| {name} | {k_fk:.0} | {fk:.1} | {all:.1} | {js:.1} | {jb:.1} | {k_j:.0} | {:.1}× | {:.1}× | {:.0} / {:.0} / {:.0} / {:.0} |",
            k_fk / fk,
            k_j / js,
            fk * s,
            all * s,
            js * s,
            jb * s
        );
    }
}
