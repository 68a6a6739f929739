//! The interactive page as a notebook shows it: `Robot.show(...)` returns a `Page`, whose
//! `_repr_html_` is an `<iframe srcdoc="…">` holding the whole self-contained page (three.js
//! and the body inlined: nothing to install, nothing fetched), so Jupyter displays it inline.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An interactive page (`Robot.show`): displayed inline by Jupyter (`_repr_html_`), its HTML in
/// `html`, written to a file by `save`.
#[pyclass(frozen, module = "screwkit")]
pub struct Page {
    /// The page's HTML.
    #[pyo3(get)]
    html: String,
    /// The iframe's height in CSS pixels.
    #[pyo3(get)]
    height: u32,
}

impl Page {
    pub(crate) fn new(html: String, height: u32) -> PyResult<Page> {
        if !(100..=10_000).contains(&height) {
            return Err(PyValueError::new_err(format!(
                "height: expected 100 to 10000 pixels, got {height}"
            )));
        }
        Ok(Page { html, height })
    }
}

/// `s` as an HTML attribute value (between double quotes).
fn attribute(s: &str) -> String {
    s.replace('&', "&amp;").replace('"', "&quot;")
}

#[pymethods]
impl Page {
    /// The page in an iframe (`srcdoc`), as Jupyter displays it.
    fn _repr_html_(&self) -> String {
        format!(
            "<iframe srcdoc=\"{}\" style=\"width: 100%; height: {}px; border: 1px solid #ddd;\" \
             sandbox=\"allow-scripts\"></iframe>",
            attribute(&self.html),
            self.height
        )
    }

    /// Writes the page to `path` (an HTML file that opens offline).
    fn save(&self, path: std::path::PathBuf) -> PyResult<()> {
        screwkit_service::io::atomic::write(&path, self.html.as_bytes())
            .map_err(|e| crate::errors::io_error(&path.display().to_string(), &e))
    }

    fn __repr__(&self) -> String {
        format!("Page({} bytes, height={})", self.html.len(), self.height)
    }
}
