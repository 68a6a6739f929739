//! Binary batches: `--input FILE.npy --output FILE.npy` for fk, jacobian and ik give the
//! library's batch results bit for bit, NaN rows are reported, bad files are refused in one
//! line. The .npy files here are written and read by the test itself (numpy's format, by
//! hand), not by the code under test.

use std::process::Command;

use screwkit_model::load_chain;
use screwkit_solve::batch::{fk_batch, ik_batch, jacobian_batch};
use screwkit_solve::ik::{IkOptions, IkStatus};
use screwkit_solve::{Frame, Kinematics};
use screwkit_testkit::{bundled, Sampler};

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn write_npy(path: &std::path::Path, shape: &[usize], descr: &str, fortran: bool, data: &[f64]) {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let dims = if shape.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let bytes = screwkit_testkit::npy_bytes(descr, fortran, &dims, data);
    std::fs::write(path, bytes).unwrap();
}

/// (shape, values) of a float64 .npy.
fn read_npy(path: &std::path::Path) -> (Vec<usize>, Vec<f64>) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(&b[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([b[8], b[9]]) as usize;
    let h = std::str::from_utf8(&b[10..10 + len]).unwrap();
    assert!(
        h.contains("'descr': '<f8'") && h.contains("'fortran_order': False"),
        "{h}"
    );
    assert_eq!((10 + len) % 64, 0);
    let s = &h[h.find("'shape': (").unwrap() + 10..];
    let shape = s[..s.find(')').unwrap()]
        .split(',')
        .filter(|x| !x.trim().is_empty())
        .map(|x| x.trim().parse().unwrap())
        .collect();
    let data = b[10 + len..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    (shape, data)
}

fn run(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).output().unwrap()
}

#[test]
fn npy_batches_equal_the_library_batches() {
    let dir = std::env::temp_dir().join(format!("screwkit-npy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = bundled("panda.urdf");
    let kin = Kinematics::new(&load_chain(&urdf, None, None).unwrap());
    let mut rng = Sampler::new(8);
    let rows = 70_000; // more than one chunk
    let mut qs: Vec<f64> = (0..rows).flat_map(|_| rng.config(&kin)).collect();
    qs[7 * 5 + 2] = f64::NAN; // row 5 is bad
    let input = dir.join("q.npy");
    write_npy(&input, &[rows, 7], "<f8", false, &qs);
    let out = dir.join("poses.npy");
    let o = run(&[
        "fk",
        &urdf,
        "--input",
        input.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "one bad row");
    assert!(String::from_utf8_lossy(&o.stderr).contains("70000 rows, 1 failed"));
    let (shape, poses) = read_npy(&out);
    assert_eq!(shape, [rows, 4, 4]);
    let mut want = vec![0.0; rows * 16];
    let _ = fk_batch(&kin, &qs, &mut want);
    for (k, (a, b)) in poses.iter().zip(&want).enumerate() {
        assert!(a == b || (a.is_nan() && b.is_nan()), "value {k}");
    }
    assert!(poses[5 * 16..6 * 16].iter().all(|x| x.is_nan()));

    // Jacobians (a few rows), body frame.
    let few = &qs[7 * 10..7 * 40];
    write_npy(&input, &[30, 7], "<f8", false, few);
    let o = run(&[
        "jacobian",
        &urdf,
        "--frame",
        "body",
        "--input",
        input.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (shape, jac) = read_npy(&out);
    assert_eq!(shape, [30, 6, 7]);
    let mut want = vec![0.0; 30 * 42];
    jacobian_batch(&kin, few, Frame::Body, &mut want, None).unwrap();
    assert_eq!(jac, want);

    // IK: targets N × 4 × 4 → solutions and status.
    let mut targets = vec![0.0; 30 * 16];
    fk_batch(&kin, few, &mut targets).unwrap();
    let tfile = dir.join("t.npy");
    write_npy(&tfile, &[30, 4, 4], "<f8", false, &targets);
    let qout = dir.join("sol.npy");
    let o = run(&[
        "ik",
        &urdf,
        "--input",
        tfile.to_str().unwrap(),
        "--output",
        qout.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (shape, q) = read_npy(&qout);
    assert_eq!(shape, [30, 7]);
    let (sshape, status) = read_npy(&dir.join("sol.status.npy"));
    assert_eq!(sshape, [30, 4]);
    let mut want_q = vec![0.0; 30 * 7];
    let mut st = vec![IkStatus::default(); 30];
    ik_batch(
        &kin,
        &targets,
        None,
        &IkOptions::default(),
        &mut want_q,
        &mut st,
        None,
    )
    .unwrap();
    assert_eq!(q, want_q);
    for (k, s) in st.iter().enumerate() {
        assert_eq!(status[4 * k], f64::from(u8::from(s.converged)));
        assert_eq!(status[4 * k + 1], s.iterations as f64);
    }

    // Refused in one line: float32, Fortran order, wrong width, no --output, not a .npy.
    let bad = dir.join("bad.npy");
    for (shape, descr, fortran, want) in [
        (vec![3, 7], "<f4", false, "expected float64"),
        (vec![3, 7], "<f8", true, "Fortran-ordered"),
        (vec![3, 6], "<f8", false, "expected (N, dof)"),
    ] {
        write_npy(
            &bad,
            &shape,
            descr,
            fortran,
            &vec![0.0; shape.iter().product()],
        );
        let o = run(&[
            "fk",
            &urdf,
            "--input",
            bad.to_str().unwrap(),
            "--output",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1));
        assert!(err.contains(want) && err.lines().count() == 1, "{err}");
    }
    let o = run(&["fk", &urdf, "--input", input.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("needs --output FILE.npy"));
    std::fs::write(&bad, b"hello").unwrap();
    let o = run(&[
        "fk",
        &urdf,
        "--input",
        bad.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a .npy file"));
    let _ = std::fs::remove_dir_all(dir);
}

/// The whole tree's binary batches: `fk --frames A,B` gives (N, 2, 4, 4) and `jacobian --of A`
/// (N, 6, nv), equal to the library's tree batches, a bad row NaN and counted.
#[test]
fn tree_npy_batches_equal_the_library() {
    use screwkit_model::{urdf, KinematicTree};
    use screwkit_solve::tree::{batch, configuration};
    use screwkit_solve::{sample::SplitMix64, JacobianKind, TreeKinematics};
    let dir = std::env::temp_dir().join(format!("screwkit-tree-npy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = bundled("torso_two_arms.urdf");
    let model = KinematicTree::from_tree(&urdf::load_file(&urdf).unwrap())
        .unwrap()
        .with_floating_base(true);
    let kin = TreeKinematics::new(&model).unwrap();
    let mut rng = SplitMix64(4);
    let rows = 300;
    let nq = kin.nq();
    let mut qs: Vec<f64> = (0..rows)
        .flat_map(|_| configuration::random(&kin, &mut rng))
        .collect();
    qs[nq * 7 + 9] = f64::INFINITY; // row 7 is bad
    let input = dir.join("q.npy");
    write_npy(&input, &[rows, nq], "<f8", false, &qs);
    let (poses, jacs) = (dir.join("poses.npy"), dir.join("jac.npy"));
    let (i, p, j) = (
        input.to_str().unwrap(),
        poses.to_str().unwrap(),
        jacs.to_str().unwrap(),
    );
    let fk = run(&[
        "fk",
        &urdf,
        "--floating-base",
        "--frames",
        "left_hand,right_hand",
        "--input",
        i,
        "--output",
        p,
    ]);
    assert_eq!(fk.status.code(), Some(1), "one bad row");
    assert!(String::from_utf8_lossy(&fk.stderr).contains("300 rows, 1 failed"));
    let (shape, got) = read_npy(&poses);
    assert_eq!(shape, [rows, 2, 4, 4]);
    // The all-frame sweep's poses (the one-frame batch runs the chain kernel instead: equal to
    // an ulp, not bit for bit).
    let frames = kin.frame_count();
    let mut want = vec![0.0; rows * frames * 16];
    let _ = batch::fk_frames_batch(&kin, &qs, &mut want);
    for (f, name) in ["left_hand", "right_hand"].iter().enumerate() {
        let i = kin.frame(name).unwrap();
        for r in 0..rows {
            let g = &got[(2 * r + f) * 16..(2 * r + f + 1) * 16];
            let w = &want[(r * frames + i) * 16..(r * frames + i + 1) * 16];
            if r == 7 {
                assert!(g.iter().all(|x| x.is_nan()));
            } else {
                assert_eq!(g, w, "row {r} frame {name}");
            }
        }
    }
    let jac = run(&[
        "jacobian",
        &urdf,
        "--floating-base",
        "--of",
        "left_hand",
        "--frame",
        "world-aligned",
        "--input",
        i,
        "--output",
        j,
    ]);
    assert_eq!(jac.status.code(), Some(1));
    let (shape, got) = read_npy(&jacs);
    assert_eq!(shape, [rows, 6, kin.nv()]);
    let mut want = vec![0.0; rows * 6 * kin.nv()];
    let _ = batch::frame_jacobian_batch(
        &kin,
        kin.frame("left_hand").unwrap(),
        JacobianKind::WorldAligned,
        &qs,
        &mut want,
        None,
    );
    let w = 6 * kin.nv();
    for r in (0..rows).filter(|&r| r != 7) {
        assert_eq!(got[r * w..(r + 1) * w], want[r * w..(r + 1) * w], "row {r}");
    }
    assert!(got[7 * w..8 * w].iter().all(|x| x.is_nan()));
    let _ = std::fs::remove_dir_all(dir);
}
