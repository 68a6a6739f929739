//! The `screwkit` command line (filled by the CLI issue).

fn main() {
    eprintln!("screwkit: the command line is not built yet; see the README for the examples that run today");
    std::process::exit(2);
}
