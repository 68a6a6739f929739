//! Prints the screw-axis table (space and body) and home pose M of a URDF chain.
//!
//! Run: `cargo run --example screw_table -- assets/urdf/ur5.urdf [BASE TIP]`

use screwkit::model::{load_chain, table};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: screw_table URDF [BASE TIP]");
        std::process::exit(2);
    };
    match load_chain(
        path,
        args.get(1).map(String::as_str),
        args.get(2).map(String::as_str),
    ) {
        Ok(chain) => print!("{}", table::to_markdown(&chain, &screwkit::lie::Frame::ALL)),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
