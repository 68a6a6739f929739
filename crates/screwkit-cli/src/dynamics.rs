//! `screwkit dynamics`: the floor's dynamics report ([`screwkit_service::dynamics`]) of one
//! configuration, as text or JSON.

use std::fmt::Write;

use screwkit_service::dynamics;
use screwkit_service::report;
use screwkit_solve::tree::dynamics::DynamicsWorkspace;

use crate::args::{DynamicsArgs, Format};
use crate::batch;
use crate::output::{emit, print_json, tuple, CliResult};

/// Runs `dynamics`.
pub fn run(a: &DynamicsArgs, format: Format) -> CliResult {
    let robot = crate::load(&a.chain)?;
    let kin = robot.whole()?;
    let d = dynamics::model(kin, &dynamics::options(a.inertias, a.armature, a.damping))?;
    if let Some(input) = &a.input {
        let done = batch::stream(input, |lines, _| {
            let rows = batch::parse_rows(lines, |text| {
                let obj = batch::parse_object(text)?;
                let q = batch::numbers(&obj, "q")?;
                let optional = |key: &str| {
                    obj.contains_key(key)
                        .then(|| batch::numbers(&obj, key))
                        .transpose()
                };
                Ok((q, optional("v")?, optional("a")?))
            });
            let errors: Vec<Option<String>> =
                rows.iter().map(|r| r.as_ref().err().cloned()).collect();
            Ok(batch::outputs(lines, &errors, |k| {
                let Ok((q, v, acc)) = &rows[k] else {
                    unreachable!("a row with an error is reported by `outputs`")
                };
                let mut ws = DynamicsWorkspace::new(&d);
                match dynamics::report(&d, &mut ws, kin.v_names(), q, v.as_deref(), acc.as_deref())
                {
                    Ok(r) => (report::to_value(&r), true),
                    Err(e) => (
                        serde_json::json!({"error": e.to_string(), "line": lines[k].number}),
                        false,
                    ),
                }
            }))
        });
        if let Some(w) = dynamics::massless_warning(&d) {
            eprintln!("screwkit: warning: {w}");
        }
        return done;
    }
    let mut ws = DynamicsWorkspace::new(&d);
    let r = dynamics::report(
        &d,
        &mut ws,
        kin.v_names(),
        &a.q.as_ref().expect("clap requires --q without --input").0,
        a.v.as_ref().map(|l| l.0.as_slice()),
        a.a.as_ref().map(|l| l.0.as_slice()),
    )?;
    // (Once the answer stands: a refused input is one line.)
    if let Some(w) = dynamics::massless_warning(&d) {
        eprintln!("screwkit: warning: {w}");
    }
    if format == Format::Json {
        return print_json(&report::to_value(&r));
    }
    let g = d.gravity();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Dynamics of `{}` (whole tree, {} velocity entries, gravity ({}, {}, {}) m/s²)",
        kin.model().robot,
        d.nv(),
        g.x,
        g.y,
        g.z
    );
    let _ = writeln!(out, "q = {}", tuple(&r.q));
    let _ = writeln!(out, "v = {}", tuple(&r.v));
    let _ = writeln!(out, "a = {}\n", tuple(&r.a));
    let _ = writeln!(
        out,
        "| variable | τ = ID(q, v, a) | g(q) | h(q, v) |\n|---|---|---|---|"
    );
    for (k, name) in r.variables.iter().enumerate() {
        let _ = writeln!(
            out,
            "| {name} | {:.6} | {:.6} | {:.6} |",
            r.tau[k], r.gravity[k], r.nonlinear_effects[k]
        );
    }
    let _ = writeln!(out, "\nM(q), row by row:");
    for row in &r.mass_matrix {
        let cells: Vec<String> = row.iter().map(|x| format!("{x:.6}")).collect();
        let _ = writeln!(out, "  [{}]", cells.join(", "));
    }
    let _ = writeln!(
        out,
        "\nkinetic energy {:.6} J, potential energy {:.6} J",
        r.kinetic_energy, r.potential_energy
    );
    emit(&out)
}
