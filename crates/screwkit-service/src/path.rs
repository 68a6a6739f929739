//! Cartesian paths for the front ends (`Robot.cartesian_path`): the chain's closed-form IK when
//! it has one (branches followed exactly), numerical IK seeded by the previous sample
//! otherwise ([`screwkit_solve::path`]).

use screwkit_lie::Se3;
use screwkit_solve::path::{self, CartesianPath, PathOptions};
use screwkit_solve::{Kinematics, Workspace};

use crate::error::Result;
use crate::solutions::Solvers;

/// The path from `seed` through `targets`: with the chain's closed-form IK from `solvers`
/// (a 6R arm's; a 7R arm has none without a locked joint, and is followed numerically).
pub fn cartesian_path(
    kin: &Kinematics,
    ws: &mut Workspace,
    solvers: &Solvers,
    targets: &[Se3],
    seed: &[f64],
    options: &PathOptions,
) -> Result<CartesianPath> {
    let analytic = solvers.get(kin, None).ok();
    Ok(path::cartesian_path(
        kin,
        ws,
        analytic.as_deref(),
        targets,
        seed,
        options,
    )?)
}
