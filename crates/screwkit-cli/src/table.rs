//! `screwkit table`: the screw-axis table and M.

use screwkit_model::{load_chain, table};

use crate::args::{Format, TableArgs};
use crate::output::{print_json, CliResult};

/// Runs `table`.
pub fn run(args: &TableArgs, format: Format) -> CliResult {
    let c = &args.chain;
    let chain = load_chain(&c.urdf, c.base.as_deref(), c.tip.as_deref())?;
    let frames = &args.frame.0;
    match format {
        Format::Json => print_json(&table::to_json(&chain)),
        Format::Csv => print!("{}", table::to_csv(&chain, frames)),
        Format::Text | Format::Md => print!("{}", table::to_markdown(&chain, frames)),
    }
    Ok(())
}
