//! `screwkit table`: the screw-axis table and M.

use screwkit_model::table;

use crate::args::{Format, TableArgs};
use crate::output::{print_json, CliResult};

/// Runs `table`.
pub fn run(args: &TableArgs, format: Format) -> CliResult {
    let robot = crate::load(&args.chain)?;
    let chain = robot.chain()?;
    let frames = &args.frame.frames();
    match format {
        Format::Json => print_json(&table::to_json(chain))?,
        Format::Csv => crate::output::emit(&table::to_csv(chain, frames))?,
        Format::Text | Format::Md => crate::output::emit(&table::to_markdown(chain, frames))?,
    }
    Ok(())
}
