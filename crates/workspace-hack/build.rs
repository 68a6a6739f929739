//! Empty: a build script makes cargo resolve this crate's build dependencies (the host-side
//! feature unification, see Cargo.toml).

fn main() {}
