//! Prints the analytic-IK family of robot files:
//! `cargo run -p screwkit-solve --example families -- FILE[:BASE:TIP] …`
//! (xacro packages are looked up in ../shared/xacro).
fn main() {
    for spec in std::env::args().skip(1) {
        let mut it = spec.split(':');
        let file = it.next().unwrap_or_default();
        let base = it.next().filter(|s| !s.is_empty());
        let tip = it.next().filter(|s| !s.is_empty());
        let opts = screwkit_model::XacroOptions {
            package_paths: vec!["../shared/xacro".into()],
            args: Vec::new(),
        };
        match screwkit_model::load_chain_with(file, base, tip, &opts) {
            Ok(chain) => {
                let kin = screwkit_solve::Kinematics::new(&chain);
                let c = screwkit_solve::family::classify(&kin);
                println!(
                    "{file}: {:?}{}: {}",
                    c.family,
                    if c.reversed { " (reversed)" } else { "" },
                    c.family.describe()
                );
                if kin.dof() == 7 {
                    for j in 0..7 {
                        match screwkit_solve::analytic::AnalyticIk::locked(&kin, j) {
                            Ok(s) => println!(
                                "  lock joint {}: {:?}{}",
                                j + 1,
                                s.family(),
                                if s.reversed() { " (reversed)" } else { "" }
                            ),
                            Err(e) => println!("  lock joint {}: {e}", j + 1),
                        }
                    }
                }
            }
            Err(e) => println!("{file}: {e}"),
        }
    }
}
