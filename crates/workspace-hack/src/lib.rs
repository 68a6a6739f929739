//! No code: this crate exists for its dependency features (see its Cargo.toml). Every front
//! end of the workspace depends on it so that separate builds share one compile of the
//! dependencies.
