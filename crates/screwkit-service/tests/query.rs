//! The query floor's frame selector (`query::Selection`, `query::Poses`) against the library's
//! own calls on the bundled models: what each selection resolves to, chain or tree, and every
//! pose, single and batched, equal to the FK it routes to.

use screwkit_service::query::{Poses, Selection};
use screwkit_service::{LoadOptions, Robot, Source};
use screwkit_solve::sample::SplitMix64;
use screwkit_solve::{fk, tree, TreeWorkspace, Workspace};

fn load(name: &str, options: &LoadOptions) -> Robot {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets")
        .join(name);
    Robot::load(&Source::Path(path), options).unwrap()
}

/// q rows within ±1 (and a unit quaternion for a floating base: entries 3..7 of the tree's).
fn rows(n: usize, len: usize, floating: bool, rng: &mut SplitMix64) -> Vec<f64> {
    let mut qs: Vec<f64> = (0..n * len).map(|_| 2.0 * rng.uniform() - 1.0).collect();
    if floating {
        for r in qs.chunks_mut(len) {
            let norm = r[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
            r[3..7].iter_mut().for_each(|x| *x /= norm);
        }
    }
    qs
}

/// On a chain: the tip is the tip FK, `Links` the all-links FK, and the tip equals the last
/// link bit for bit (the chain report's "pose" of `--all-links` is read from it), with a tool
/// frame too; batches equal the single calls row by row.
#[test]
fn chain_selections_are_the_chain_fk() {
    let mut rng = SplitMix64(0x5E1E_C700_0000_0001);
    for (file, tool) in [
        ("urdf/ur5.urdf", None),
        ("urdf/panda.urdf", Some(vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6])),
        ("urdf/iiwa14.urdf", None),
        ("urdf/scara.urdf", None),
    ] {
        let options = LoadOptions {
            tool,
            ..LoadOptions::default()
        };
        let robot = load(file, &options);
        let kin = robot.kin().unwrap();
        let tip = Poses::resolve(&robot, None, Selection::Tip).unwrap();
        let links = Poses::resolve(&robot, None, Selection::Links).unwrap();
        assert!(matches!(tip, Poses::Tip(_)) && matches!(links, Poses::ChainLinks(_)));
        assert_eq!((tip.count(), links.count()), (1, kin.links().len()));
        assert_eq!(tip.shape(), vec![4, 4]);
        let n = 17;
        let qs = rows(n, kin.dof(), false, &mut rng);
        let (mut one, mut all) = (vec![0.0; 16], vec![0.0; 16 * links.count()]);
        let mut batch = vec![0.0; n * 16 * links.count()];
        links.poses_batch(&qs, &mut batch).unwrap();
        let mut ws = Workspace::new(kin);
        for (r, q) in qs.chunks(kin.dof()).enumerate() {
            tip.poses(q, &mut one).unwrap();
            links.poses(q, &mut all).unwrap();
            let mut expected = [0.0; 16];
            fk::fk(kin, &mut ws, q)
                .unwrap()
                .write_row_major(&mut expected);
            assert_eq!(one, expected, "{file}");
            assert_eq!(
                &all[all.len() - 16..],
                &expected[..],
                "{file}: the tip is the last link"
            );
            for (p, t) in all
                .chunks(16)
                .zip(fk::fk_all_links(kin, &mut ws, q).unwrap())
            {
                let mut e = [0.0; 16];
                t.write_row_major(&mut e);
                assert_eq!(p, &e[..]);
            }
            assert_eq!(&batch[r * all.len()..(r + 1) * all.len()], &all[..]);
        }
        let report =
            serde_json::to_value(links.report(&qs[..kin.dof()], &batch[..all.len()])).unwrap();
        assert_eq!(report["links"].as_array().unwrap().len(), links.count());
        assert_eq!(report["pose"], report["links"][links.count() - 1]["pose"]);
    }
}

/// On the whole tree (the humanoid, no chain; the floating MJCF humanoid): `Tip` and
/// `Leaves` give the leaf links, `Links` every link, `All` every frame, `Named` the frames in
/// the order asked (an unknown name is an error naming it); each pose equals the tree's
/// all-frame FK, single and batched.
#[test]
fn tree_selections_are_the_tree_fk() {
    let mut rng = SplitMix64(0x5E1E_C700_0000_0002);
    for file in ["urdf/humanoid.urdf", "mjcf/humanoid.xml"] {
        let robot = load(file, &LoadOptions::default());
        let kin = robot.whole().unwrap();
        let leaves = screwkit_service::whole::leaf_frames(kin);
        let names: Vec<String> = ["right_foot", "head"]
            .iter()
            .filter(|n| kin.frame(n).is_ok())
            .map(|n| n.to_string())
            .collect();
        assert_eq!(names.len(), 2, "{file}: the frames the test names");
        let named: Vec<usize> = names.iter().map(|n| kin.frame(n).unwrap()).collect();
        for (selection, frames) in [
            (Selection::Tip, leaves.clone()),
            (Selection::Leaves, leaves.clone()),
            (Selection::Links, (0..kin.model().links.len()).collect()),
            (Selection::All, (0..kin.frame_count()).collect()),
            (Selection::Named(&names), named.clone()),
        ] {
            let poses = Poses::resolve(&robot, None, selection).unwrap();
            let Poses::Frames(_, got) = &poses else {
                panic!("{file}: {selection:?} is about the tree")
            };
            assert_eq!(got, &frames, "{file}: {selection:?}");
            let n = 5;
            let qs = rows(n, kin.nq(), kin.floating_base(), &mut rng);
            let k = poses.count();
            let mut batch = vec![0.0; n * k * 16];
            poses.poses_batch(&qs, &mut batch).unwrap();
            let mut ws = TreeWorkspace::new(kin);
            let mut one = vec![0.0; k * 16];
            for (r, q) in qs.chunks(kin.nq()).enumerate() {
                poses.poses(q, &mut one).unwrap();
                let all = tree::fk::fk_frames(kin, &mut ws, q).unwrap();
                for (p, &f) in one.chunks(16).zip(&frames) {
                    let mut e = [0.0; 16];
                    all[f].write_row_major(&mut e);
                    assert_eq!(p, &e[..]);
                }
                assert_eq!(&batch[r * k * 16..(r + 1) * k * 16], &one[..]);
            }
        }
        let bad = ["no_such_frame".to_string()];
        let e = Poses::resolve(&robot, None, Selection::Named(&bad)).unwrap_err();
        assert!(e.to_string().contains("no_such_frame"), "{e}");
    }
}
