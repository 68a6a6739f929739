//! The README's library snippet is `examples/readme_library.rs` (compiled with the examples)
//! and names no crate but `screwkit` and `std`.

#[test]
fn readme_snippet_is_the_compiled_example() {
    let root = env!("CARGO_MANIFEST_DIR");
    let readme = std::fs::read_to_string(format!("{root}/README.md")).unwrap();
    let section = &readme[readme.find("**From Rust**").unwrap()..];
    let start = section.find("```rust\n").unwrap() + "```rust\n".len();
    let block = &section[start..start + section[start..].find("```").unwrap()];
    let example = std::fs::read_to_string(format!("{root}/examples/readme_library.rs")).unwrap();
    assert!(
        example.ends_with(block),
        "README block and examples/readme_library.rs differ"
    );
    for line in block.lines() {
        if let Some(path) = line.trim().strip_prefix("use ") {
            assert!(
                path.starts_with("screwkit::") || path.starts_with("std::"),
                "{line}"
            );
        }
        assert!(!line.contains("nalgebra::"), "{line}: use the re-export");
    }
}
