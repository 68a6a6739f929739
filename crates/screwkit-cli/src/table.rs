//! `screwkit table`: the screw-axis table and M.

use screwkit_model::{load_chain_with, table};

use crate::args::{Format, TableArgs};
use crate::output::{print_json, CliResult};

/// Runs `table`.
pub fn run(args: &TableArgs, format: Format) -> CliResult {
    let c = &args.chain;
    let chain = load_chain_with(
        &c.urdf,
        c.base.as_deref(),
        c.tip.as_deref(),
        &c.xacro.options(),
    )?;
    let frames = &args.frame.0;
    match format {
        Format::Json => print_json(&table::to_json(&chain)),
        Format::Csv => print!("{}", table::to_csv(&chain, frames)),
        Format::Text | Format::Md => print!("{}", table::to_markdown(&chain, frames)),
    }
    Ok(())
}
