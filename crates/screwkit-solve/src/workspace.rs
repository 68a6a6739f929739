//! [`Workspace`]: the reusable scratch of one thread (Pinocchio's `Data`).

use nalgebra::Matrix6xX;
use screwkit_lie::Se3;

use crate::columns::Columns;
use crate::kinematics::Kinematics;

/// Reusable scratch for one thread, sized for one [`Kinematics`]: the algorithms write their
/// intermediate and bulky results here (Jacobians, link poses, the IK loop's vectors) and
/// allocate nothing in their hot loops. Create one per thread with [`Workspace::new`]; it is
/// cheap to keep and reuse across calls.
#[derive(Debug, Clone)]
pub struct Workspace {
    pub(crate) jacobian: Matrix6xX<f64>,
    pub(crate) links: Vec<Se3>,
    /// The link poses as the all-link kernel writes them (columns), converted into `links`.
    pub(crate) link_columns: Vec<Columns>,
    pub(crate) ik: IkScratch,
    /// A locked analytic solver's prepared problem at its last lock value (boxed: ~500 bytes
    /// that `Workspace::local` would otherwise move in and out at every call).
    pub(crate) analytic: Option<Box<crate::analytic::PreparedAt>>,
}

/// The per-solve buffers of the IK loop, kept in the workspace so a solve allocates only the
/// q it returns.
#[derive(Debug, Clone, Default)]
pub(crate) struct IkScratch {
    /// The current iterate.
    pub(crate) q: Vec<f64>,
    /// The step.
    pub(crate) dq: Vec<f64>,
    /// The best iterate so far.
    pub(crate) best_q: Vec<f64>,
    /// Active-set flags: joints held at a limit this iteration.
    pub(crate) locked: Vec<bool>,
    /// The clearance step's buffers ([`crate::ik::solve_clear`]).
    pub(crate) clear: ClearScratch,
}

/// The buffers of IK's clearance step: the close pairs' gaps and rows, the QP.
#[derive(Debug, Clone, Default)]
pub(crate) struct ClearScratch {
    pub(crate) gaps: Vec<f64>,
    pub(crate) rows: Vec<f64>,
    pub(crate) h: Vec<f64>,
    pub(crate) c: Vec<f64>,
    pub(crate) lower: Vec<f64>,
    pub(crate) upper: Vec<f64>,
    pub(crate) step: Vec<f64>,
    pub(crate) qp: crate::linalg::qp::QpWorkspace,
}

impl Workspace {
    /// Scratch sized for `kin`.
    pub fn new(kin: &Kinematics) -> Self {
        let n = kin.dof();
        Self {
            jacobian: Matrix6xX::zeros(n),
            links: vec![Se3::identity(); kin.links.len()],
            link_columns: vec![Columns::identity(); kin.links.len()],
            ik: IkScratch {
                q: vec![0.0; n],
                dq: vec![0.0; n],
                best_q: vec![0.0; n],
                locked: vec![false; n],
                clear: ClearScratch::default(),
            },
            analytic: None,
        }
    }
}

impl Default for Workspace {
    /// An empty workspace: every algorithm fits it to its chain on first use (one allocation).
    fn default() -> Self {
        Self {
            jacobian: Matrix6xX::zeros(0),
            links: Vec::new(),
            link_columns: Vec::new(),
            ik: IkScratch::default(),
            analytic: None,
        }
    }
}

impl Workspace {
    /// Runs `f` in this thread's kept workspace, fitted to `kin`: a batch small enough for the
    /// calling thread then makes none (measured: 0.23 µs for the Panda's, a quarter of a
    /// one-row batch from Python). Taken out while `f` runs, so a batch inside `f` makes its
    /// own; algorithms never read what a workspace held before. Kept boxed: taking it out
    /// and back moves a pointer, not the workspace.
    pub fn local<R>(kin: &Kinematics, f: impl FnOnce(&mut Workspace) -> R) -> R {
        thread_local! {
            static KEPT: std::cell::RefCell<Option<Box<Workspace>>> = const { std::cell::RefCell::new(None) };
        }
        let mut ws = KEPT.with(|k| k.borrow_mut().take()).unwrap_or_default();
        ws.fit(kin);
        let out = f(&mut ws);
        KEPT.with(|k| *k.borrow_mut() = Some(ws));
        out
    }

    /// Makes the workspace fit `kin` (a workspace made for another chain is rebuilt, so a
    /// mix-up costs an allocation, never a panic or a wrong size).
    #[inline(always)]
    pub(crate) fn fit(&mut self, kin: &Kinematics) {
        if self.jacobian.ncols() != kin.dof() || self.links.len() != kin.links.len() {
            self.refit(kin);
        }
    }

    /// The cold path of [`Workspace::fit`].
    #[cold]
    #[inline(never)]
    fn refit(&mut self, kin: &Kinematics) {
        *self = Workspace::new(kin);
    }
}
