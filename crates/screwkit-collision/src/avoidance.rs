//! Collision avoidance as a limit of whole-body differential IK (mink's
//! `CollisionAvoidanceLimit`): each checked pair closer than the detection distance beyond the
//! margin gives one inequality row on the step's displacement Δ = v·dt,
//!
//! ```text
//! nᵀ (J_b(p_b) − J_a(p_a)) Δ ≥ −gain · (d − margin),
//! ```
//!
//! that is ḋ ≥ −gain (d − margin) / dt: a velocity damper that lets a pair close at most
//! `gain` of its gap to the margin in one step, and makes a pair already closer than the margin
//! move apart (the row's bound is then positive). The rows are linear in the step and the
//! distance is not: after the QP, the pairs the step brought near the margin are measured at
//! q ⊕ Δ, and a row whose pair ended under the margin is tightened by the shortfall and the QP
//! solved again ([`Limit::tighten`]; the rows aim 10 µm beyond the margin for rounding), so
//! that no step ends closer than the margin. d, n, p_a, p_b are the pair's signed distance,
//! normal and witness points ([`crate::query::close_pairs`]); the row is its
//! [`crate::query::distance_jacobians`] row. The solver knows the limit only through
//! [`screwkit_solve::tree::limits::Limit::rows`].

use std::sync::{Arc, Mutex};

use screwkit_solve::tree::limits::Limit;
use screwkit_solve::{SolveError, TreeKinematics};

use crate::model::{CollisionError, CollisionModel};
use crate::query::{self, CollisionWorkspace, PairDistance};

/// mink's defaults: the least distance kept (m).
pub const DEFAULT_MARGIN: f64 = 0.005;
/// Pairs closer than this beyond the margin get a row (m).
pub const DEFAULT_DETECTION_DISTANCE: f64 = 0.05;
/// The fraction of its gap a pair may close in one step.
pub const DEFAULT_GAIN: f64 = 0.85;
/// How far under the margin a pair may be and still keep the limit (m): the rounding of a step
/// whose rows were tightened to land on the margin.
pub const SATISFIED_TOLERANCE: f64 = 1e-6;
/// The rows keep pairs this much (m) beyond the margin, and a step that leaves one less than
/// half of it beyond is solved again: so that the rows' linearisation and the step's rounding
/// never take a pair under the margin itself.
const BUFFER: f64 = 1e-5;
/// Pairs closer than this beyond the margin (m) give their contact patch's rows
/// ([`crate::query::close_pairs`]), the others their witness's row alone. A patch matters
/// where rows bind, at the margin (a hull riding on a table sits 10 µm beyond it): measured on
/// TALOS's gripper against a table, patches within 1 mm of the margin already remove the
/// chatter (p99 of ‖Δv‖ 0.079 with patches on every close pair, 0.079 within 1 mm, 0.61
/// at the margin alone), and cut the rows from 47 to 26 a step; twice that is kept.
const PATCH_WITHIN: f64 = 2e-3;
/// After a step, a row whose predicted gap to the margin is within this (m) of the step's own
/// change is measured again (rounding and the step's second-order terms).
const RECHECK_WITHIN: f64 = 1e-4;

/// The limit (module documentation) on a collision model: its pairs, or those between given
/// links (and obstacles).
#[derive(Debug)]
pub struct CollisionAvoidance {
    model: Arc<CollisionModel>,
    /// A flag per model pair: constrained or not.
    selected: Vec<bool>,
    margin: f64,
    detection: f64,
    gain: f64,
    /// Workspaces for the calls (one per concurrent caller, kept).
    pool: Mutex<Vec<Scratch>>,
}

#[derive(Debug)]
struct Scratch {
    ws: CollisionWorkspace,
    found: Vec<PairDistance>,
    rows: Vec<f64>,
    /// The rows measured again after a step, and their pairs (sorted, each once).
    picked: Vec<usize>,
    picked_tags: Vec<usize>,
}

impl CollisionAvoidance {
    /// The limit on `model`'s pairs (built for `kin`): all of them (`pairs` None), or those
    /// between the named links or obstacles (either order; a name pair no checked pair joins
    /// is an error naming it). `margin` ≥ 0 and `detection_distance` > 0 in metres, `gain` in
    /// (0, 1].
    pub fn new(
        model: Arc<CollisionModel>,
        kin: &TreeKinematics,
        pairs: Option<&[(String, String)]>,
        margin: f64,
        detection_distance: f64,
        gain: f64,
    ) -> Result<CollisionAvoidance, CollisionError> {
        check_settings(margin, detection_distance, gain)?;
        check_model(&model, kin)?;
        let selected = match pairs {
            None => vec![true; model.pair_count()],
            Some(named) => {
                let mut selected = vec![false; model.pair_count()];
                for (a, b) in named {
                    let mut any = false;
                    for (k, (x, y)) in model.pairs().enumerate() {
                        let (x, y) = (model.owner(x), model.owner(y));
                        if (x == a && y == b) || (x == b && y == a) {
                            selected[k] = true;
                            any = true;
                        }
                    }
                    if !any {
                        return Err(CollisionError::Unknown(format!(
                            "collision avoidance: no checked pair joins {a:?} and {b:?} (a \
                             link or obstacle without shapes, adjacent bodies, or a pair the \
                             SRDF disables)"
                        )));
                    }
                }
                selected
            }
        };
        Ok(CollisionAvoidance {
            model,
            selected,
            margin,
            detection: detection_distance,
            gain,
            pool: Mutex::new(Vec::new()),
        })
    }

    /// The number of pairs it constrains (when close).
    pub fn pair_count(&self) -> usize {
        self.selected.iter().filter(|s| **s).count()
    }

    /// The margin (m).
    pub fn margin(&self) -> f64 {
        self.margin
    }
}

/// The limit's settings: `margin` ≥ 0 (at most [`crate::clearance::MAX_MARGIN`]) and
/// `detection_distance` > 0 in metres, `gain` in (0, 1]; an error naming the bad one.
pub fn check_settings(
    margin: f64,
    detection_distance: f64,
    gain: f64,
) -> Result<(), CollisionError> {
    let bad = |what: &str, x: f64| {
        Err(CollisionError::Geometry(format!(
            "collision avoidance: {what}, got {x}"
        )))
    };
    if !(margin.is_finite() && (0.0..=crate::clearance::MAX_MARGIN).contains(&margin)) {
        return bad("margin must be a distance ≥ 0 (m)", margin);
    }
    if !(detection_distance.is_finite() && detection_distance > 0.0) {
        return bad(
            "detection_distance must be a distance > 0 (m)",
            detection_distance,
        );
    }
    if !(gain > 0.0 && gain <= 1.0) {
        return bad("gain must be in (0, 1]", gain);
    }
    Ok(())
}

/// The model must be the tree's: the same links, in order.
fn check_model(model: &CollisionModel, kin: &TreeKinematics) -> Result<(), CollisionError> {
    let links = &kin.model().links;
    let same = model.links().len() == links.len()
        && model.links().iter().zip(links).all(|(a, l)| *a == l.name);
    if same {
        Ok(())
    } else {
        Err(CollisionError::Geometry(
            "collision avoidance: the collision model was built for another robot".into(),
        ))
    }
}

impl Limit for CollisionAvoidance {
    fn check(&self, kin: &TreeKinematics) -> Result<(), SolveError> {
        check_model(&self.model, kin).map_err(|e| SolveError::InvalidInput(e.to_string()))
    }

    fn narrow(
        &self,
        _: &TreeKinematics,
        _: &[f64],
        _: Option<f64>,
        _: &mut [f64],
        _: &mut [f64],
    ) -> Result<(), SolveError> {
        Ok(())
    }

    fn rows(
        &self,
        kin: &TreeKinematics,
        q: &[f64],
        g: &mut Vec<f64>,
        h: &mut Vec<f64>,
        tags: &mut Vec<usize>,
    ) -> Result<(), SolveError> {
        let mut s = self.scratch(kin);
        let result = query::close_pairs(
            &self.model,
            &mut s.ws,
            kin,
            q,
            self.margin + self.detection,
            self.margin + PATCH_WITHIN,
            Some(&self.selected),
            &mut s.found,
            Some(&mut s.rows),
        );
        if result.is_ok() {
            let nv = kin.nv();
            for (d, row) in s.found.iter().zip(s.rows.chunks(nv.max(1))) {
                g.extend_from_slice(row);
                h.push(-self.gain * (d.distance - self.margin - BUFFER));
                tags.push(d.pair);
            }
        }
        self.give_back(s);
        result.map_err(solve_error)
    }

    /// Every constrained pair at least the margin apart (to [`SATISFIED_TOLERANCE`]).
    fn satisfied(&self, kin: &TreeKinematics, q: &[f64]) -> Result<bool, SolveError> {
        let mut s = self.scratch(kin);
        let Scratch { ws, found, .. } = &mut s;
        let result = query::close_pairs(
            &self.model,
            ws,
            kin,
            q,
            self.margin,
            self.margin,
            Some(&self.selected),
            found,
            None,
        );
        let kept = found
            .iter()
            .all(|d| d.distance >= self.margin - SATISFIED_TOLERANCE);
        self.give_back(s);
        result.map_err(solve_error)?;
        Ok(kept)
    }

    /// A pair the step left closer than the margin (d' < margin at q_next) needs its row's
    /// ḋ Δ larger by the shortfall: h += (margin − d') (and a hair more, so the next step lands
    /// at or beyond the margin rather than on it). Only the rows whose predicted gap after the
    /// step, (d − margin) + G Δ with d − margin ≥ −h / gain (h only rises), is no larger than
    /// the step's own change |G Δ| (and 0.1 mm) are measured again: the others keep more room
    /// than the step moved them by.
    fn tighten(
        &self,
        kin: &TreeKinematics,
        q_next: &[f64],
        tags: &[usize],
        moved: &[f64],
        h: &mut [f64],
    ) -> Result<bool, SolveError> {
        let mut s = self.scratch(kin);
        s.picked.clear();
        s.picked_tags.clear();
        for (k, (&m, &bound)) in moved.iter().zip(h.iter()).enumerate() {
            // The predicted gap to margin + BUFFER after the step.
            let after = -bound / self.gain + m;
            if after <= m.abs() + RECHECK_WITHIN {
                s.picked.push(k);
                s.picked_tags.push(tags[k]);
            }
        }
        // Each pair measured once (a contact patch gives a pair several rows).
        s.picked_tags.sort_unstable();
        s.picked_tags.dedup();
        let result = if s.picked.is_empty() {
            Ok(())
        } else {
            let Scratch {
                ws,
                found,
                picked_tags,
                ..
            } = &mut s;
            query::pair_distances(&self.model, ws, kin, q_next, picked_tags, found)
        };
        let mut raised = false;
        if result.is_ok() && !s.picked.is_empty() {
            for &k in &s.picked {
                let Ok(at) = s.picked_tags.binary_search(&tags[k]) else {
                    continue;
                };
                let d = &s.found[at];
                if d.distance < self.margin + 0.5 * BUFFER {
                    h[k] += (self.margin + BUFFER - d.distance) * 1.01;
                    raised = true;
                }
            }
        }
        self.give_back(s);
        result.map_err(solve_error)?;
        Ok(raised)
    }
}

impl CollisionAvoidance {
    /// A workspace from the pool (or a new one).
    fn scratch(&self, kin: &TreeKinematics) -> Scratch {
        let taken = self.pool.lock().map(|mut p| p.pop()).unwrap_or(None);
        taken.unwrap_or_else(|| Scratch {
            ws: CollisionWorkspace::new(kin, &self.model),
            found: Vec::new(),
            rows: Vec::new(),
            picked: Vec::new(),
            picked_tags: Vec::new(),
        })
    }

    fn give_back(&self, s: Scratch) {
        if let Ok(mut p) = self.pool.lock() {
            p.push(s);
        }
    }
}

fn solve_error(e: CollisionError) -> SolveError {
    match e {
        CollisionError::Solve(e) => e,
        e => SolveError::InvalidInput(e.to_string()),
    }
}
