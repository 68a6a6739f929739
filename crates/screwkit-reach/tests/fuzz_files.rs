//! Fuzz targets of the file readers of the maps: the `.npy` header reader (also the CLI's
//! binary batches) and whole `.npz` maps (read, export, merge), by the seeded mutation fuzzer
//! of `screwkit_testkit::fuzz`, from real files. A few seconds each here;
//! `SCREWKIT_FUZZ_SECS=600` runs ten minutes.

use screwkit_model::load_chain;
use screwkit_reach::{Plan, ReachSpec, Shard};
use screwkit_service::io::npz;
use screwkit_solve::Kinematics;
use screwkit_testkit::{bundled, fuzz};

#[test]
fn fuzz_npy_headers() {
    let seeds: Vec<Vec<u8>> = [
        npz::npy_header("<f8", &[3, 6]),
        npz::npy_header("<f8", &[100, 4, 4]),
        npz::npy_header("|b1", &[7]),
        npz::npy_header("<U12", &[]),
        npz::npy_header("<i8", &[2]),
    ]
    .into_iter()
    .map(|mut h| {
        h.extend_from_slice(&[0u8; 64]);
        h
    })
    .collect();
    let tokens: &[&[u8]] = &[
        b"'shape': (",
        b"), ",
        b"'descr': '",
        b"'fortran_order': True",
        b"1000000000000",
        b"18446744073709551615",
        b",",
        b"(,)",
        b"\x93NUMPY\x02\x00\xff\xff\xff\xff",
        b"\x93NUMPY\x03\x00",
        b"}",
        b"{",
    ];
    let n = fuzz::run("npy", 4, 3.0, &seeds, tokens, |input| {
        let mut r = input;
        if let Ok(h) = npz::read_npy_header(&mut r) {
            // A header that reads has a shape whose element count fits.
            let _ = h
                .shape
                .iter()
                .try_fold(1usize, |n, &d| n.checked_mul(d))
                .unwrap();
        }
    });
    assert!(n > 0);
}

#[test]
fn fuzz_maps() {
    let chain = load_chain(bundled("ur5.urdf"), None, None).unwrap();
    let kin = Kinematics::new(&chain);
    let spec = ReachSpec {
        resolution: 0.4,
        orientations: 3,
        ..ReachSpec::default()
    };
    let plan = Plan::new(&chain, &kin, &spec).unwrap();
    let dir = std::env::temp_dir().join(format!("screwkit-fuzz-maps-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = |n: &str| dir.join(n).to_string_lossy().into_owned();
    let mut seeds = Vec::new();
    for (name, shard) in [
        ("whole.npz", Shard { index: 0, count: 1 }),
        ("s1.npz", Shard { index: 1, count: 2 }),
    ] {
        screwkit_reach::build(&plan, &kin, shard, &p(name), |_, _| {}).unwrap();
        seeds.push(std::fs::read(p(name)).unwrap());
    }
    let s0 = p("s0.npz");
    screwkit_reach::build(&plan, &kin, Shard { index: 0, count: 2 }, &s0, |_, _| {}).unwrap();
    let tokens: &[&[u8]] = &[
        b"voxel_range",
        b"{\"format\":",
        b"\"grid\":",
        b"NUMPY",
        b"PK\x03\x04",
        b"PK\x01\x02",
    ];
    let (input, csv, merged) = (p("in.npz"), p("out.csv"), p("merged.npz"));
    let n = fuzz::run("maps", 5, 3.0, &seeds, tokens, |bytes| {
        std::fs::write(&input, bytes).unwrap();
        if let Ok(m) = screwkit_reach::read(&input) {
            assert_eq!(m.index.len(), m.voxels.len());
            let _ = screwkit_reach::export(&input, &csv);
            let _ = screwkit_reach::merge(&[s0.clone(), input.clone()], &merged);
        }
    });
    let _ = std::fs::remove_dir_all(&dir);
    assert!(n > 0);
}
