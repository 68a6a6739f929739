//! The expression language of `${…}`: values, the lexer, the parser and evaluator, Python's
//! number rules. Independent of the expander but for the property lookup it is handed
//! ([`parser::Parser`] borrows the scope and the expander's budget).

use super::*;

mod lexer;
mod parser;
mod python;
mod value;

pub(crate) use lexer::*;
pub(crate) use parser::*;
pub(crate) use python::*;
pub(crate) use value::*;
