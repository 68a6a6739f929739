//! Mutated URDF text never panics the loader (proptest as a light fuzzer).

use proptest::prelude::*;
use screwkit_model::{urdf, Chain};

fn seed_text() -> String {
    std::fs::read_to_string(format!(
        "{}/../../assets/urdf/tricky.urdf",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize, usize),
    Insert(usize, String),
    Duplicate(usize, usize),
    Replace(usize, char),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let token = prop_oneof![
        Just("<".to_string()),
        Just(">".to_string()),
        Just("\"".to_string()),
        Just("/>".to_string()),
        Just("NaN".to_string()),
        Just("-1e309".to_string()),
        Just("<joint name=\"j1\" type=\"revolute\">".to_string()),
        Just("<link name=\"l1\"/>".to_string()),
        Just("</joint>".to_string()),
        Just("<mimic joint=\"j1\"/>".to_string()),
        Just("<limit/>".to_string()),
        Just("type=\"planar\"".to_string()),
        "[ -~]{0,12}",
    ];
    prop_oneof![
        (0usize..1_000_000, 1usize..200).prop_map(|(a, n)| Mutation::Delete(a, n)),
        (0usize..1_000_000, token).prop_map(|(a, t)| Mutation::Insert(a, t)),
        (0usize..1_000_000, 1usize..300).prop_map(|(a, n)| Mutation::Duplicate(a, n)),
        (0usize..1_000_000, any::<char>()).prop_map(|(a, c)| Mutation::Replace(a, c)),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let chars: Vec<char> = text.chars().collect();
    let at = |a: usize| a % (chars.len() + 1);
    let mut out: Vec<char> = chars.clone();
    match m {
        Mutation::Delete(a, n) => {
            let s = at(*a);
            let e = (s + n).min(chars.len());
            out.drain(s..e);
        }
        Mutation::Insert(a, t) => {
            let s = at(*a);
            out.splice(s..s, t.chars());
        }
        Mutation::Duplicate(a, n) => {
            let s = at(*a);
            let e = (s + n).min(chars.len());
            let piece: Vec<char> = chars[s..e].to_vec();
            out.splice(e..e, piece);
        }
        Mutation::Replace(a, c) => {
            if !chars.is_empty() {
                let s = *a % chars.len();
                out[s] = *c;
            }
        }
    }
    out.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn mutated_urdf_never_panics(muts in prop::collection::vec(mutation(), 1..4)) {
        let mut text = seed_text();
        for m in &muts {
            text = apply(&text, m);
        }
        if let Ok(tree) = urdf::load_str(&text, "mutated.urdf") {
            // Any chain request either works or is an error.
            let _ = Chain::from_tree(&tree, None, None);
            let _ = Chain::from_tree(&tree, Some("base_link"), Some("tool"));
        }
    }
}
