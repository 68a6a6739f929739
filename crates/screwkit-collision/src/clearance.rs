//! IK that keeps clear of contact: the body of a chain inside its robot, as the solver asks for
//! it ([`screwkit_solve::ik::Clearance`]).
//!
//! The chain's joint values are placed in the whole tree's configuration (matched by name; the
//! tree's other joints held at a fixed configuration, the base included), so that every
//! checked pair counts: the chain's links against each other, against the rest of the robot
//! and against obstacles. A pair's gradient over the chain's variables is its row of
//! [`crate::query::distance_jacobians`] (n · (J_b(p_b) − J_a(p_a))) at the chain's columns.

use screwkit_solve::ik::Clearance;
use screwkit_solve::TreeKinematics;

use crate::model::{CollisionError, CollisionModel};
use crate::query::{self, CollisionWorkspace, PairDistance};

/// The largest margin accepted (m): a kilometre keeps every robot apart from everything.
pub const MAX_MARGIN: f64 = 1e3;

/// A chain's body for [`screwkit_solve::ik::solve_clear`] and
/// [`screwkit_solve::batch::ik_batch_clear_from`]: clear means every checked pair of `model`
/// at least `margin` apart.
#[derive(Debug, Clone)]
pub struct ChainClearance<'a> {
    model: &'a CollisionModel,
    kin: &'a TreeKinematics,
    /// The tree's configuration the chain's values are written into.
    base: Vec<f64>,
    /// Chain variable k's index in the tree's q and v (None: not a tree variable).
    at: Vec<Option<(usize, usize)>>,
    margin: f64,
    /// Steer away from contact with distance rows (true, the default), or only reject
    /// colliding answers (for measuring the two).
    pub steer: bool,
}

/// One thread's scratch of a [`ChainClearance`].
#[derive(Debug, Clone)]
pub struct ClearanceScratch {
    ws: CollisionWorkspace,
    q: Vec<f64>,
    found: Vec<PairDistance>,
    rows: Vec<f64>,
}

impl<'a> ChainClearance<'a> {
    /// The chain whose variables are `names` (in the chain's order), inside the tree `kin` at
    /// configuration `base` (length nq), checked by `model` with `margin` (m, ≥ 0).
    pub fn new(
        model: &'a CollisionModel,
        kin: &'a TreeKinematics,
        names: &[String],
        base: Vec<f64>,
        margin: f64,
    ) -> Result<Self, CollisionError> {
        if !(margin.is_finite() && (0.0..=MAX_MARGIN).contains(&margin)) {
            return Err(CollisionError::Geometry(format!(
                "margin: expected a distance in metres from 0 to {MAX_MARGIN}, got {margin}"
            )));
        }
        kin.check_q(&base)?;
        let offset = kin.nq() - kin.nv();
        let at = names
            .iter()
            .map(|name| {
                kin.q_names()
                    .iter()
                    .position(|n| n == name)
                    .map(|k| (k, k - offset))
            })
            .collect();
        Ok(ChainClearance {
            model,
            kin,
            base,
            at,
            margin,
            steer: true,
        })
    }

    /// The margin (m).
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// The closest checked pair at the chain's `q`: its two link (or obstacle) names and
    /// signed distance (m); None for a model without pairs. What a front end names when a
    /// configuration is not clear.
    pub fn closest(
        &self,
        scratch: &mut ClearanceScratch,
        q: &[f64],
    ) -> Result<Option<(String, String, f64)>, CollisionError> {
        self.place(scratch, q);
        let ClearanceScratch { ws, q: tq, .. } = scratch;
        Ok(query::min_distance(self.model, ws, self.kin, tq)?.map(|d| {
            let (a, b) = self.model.pair_names(d.pair);
            (a.to_string(), b.to_string(), d.distance)
        }))
    }

    /// The tree's configuration of the chain's `q`, into `scratch`.
    fn place<'s>(&self, s: &'s mut ClearanceScratch, q: &[f64]) -> &'s [f64] {
        s.q.clone_from(&self.base);
        for (x, at) in q.iter().zip(&self.at) {
            if let Some((k, _)) = at {
                s.q[*k] = *x;
            }
        }
        &s.q
    }
}

impl Clearance for ChainClearance<'_> {
    type Scratch = ClearanceScratch;

    fn scratch(&self) -> ClearanceScratch {
        ClearanceScratch {
            ws: CollisionWorkspace::new(self.kin, self.model),
            q: Vec::with_capacity(self.base.len()),
            found: Vec::new(),
            rows: Vec::new(),
        }
    }

    fn is_clear(&self, s: &mut ClearanceScratch, q: &[f64]) -> bool {
        self.place(s, q);
        let ClearanceScratch { ws, q: tq, .. } = s;
        query::clear(self.model, ws, self.kin, tq, self.margin).unwrap_or(false)
    }

    fn steers(&self) -> bool {
        self.steer
    }

    fn close_rows(
        &self,
        s: &mut ClearanceScratch,
        q: &[f64],
        within: f64,
        gaps: &mut Vec<f64>,
        rows: &mut Vec<f64>,
    ) {
        self.place(s, q);
        let ClearanceScratch {
            ws,
            q: tq,
            found,
            rows: tree_rows,
        } = s;
        if query::close_pairs(
            self.model,
            ws,
            self.kin,
            tq,
            self.margin + within,
            f64::INFINITY,
            None,
            found,
            Some(tree_rows),
        )
        .is_err()
        {
            return;
        }
        let nv = self.kin.nv();
        for (d, row) in found.iter().zip(tree_rows.chunks(nv.max(1))) {
            gaps.push(d.distance - self.margin);
            rows.extend(self.at.iter().map(|at| at.map_or(0.0, |(_, v)| row[v])));
        }
    }
}
