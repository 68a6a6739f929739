//! `screwkit table`: the screw-axis table and M.

use screwkit_model::{load_chain, table};

use crate::args::{Format, TableArgs, TableFrame};
use crate::output::{print_json, CliResult};

/// Runs `table`.
pub fn run(args: &TableArgs, format: Format) -> CliResult {
    let c = &args.chain;
    let chain = load_chain(&c.urdf, c.base.as_deref(), c.tip.as_deref())?;
    let frame = match args.frame {
        TableFrame::Space => table::Frame::Space,
        TableFrame::Body => table::Frame::Body,
        TableFrame::Both => table::Frame::Both,
    };
    match format {
        Format::Json => print_json(&table::to_json(&chain)),
        Format::Csv => print!("{}", table::to_csv(&chain, frame)),
        Format::Text | Format::Md => print!("{}", table::to_markdown(&chain, frame)),
    }
    Ok(())
}
