//! MuJoCo's `qpos` and screwkit's configuration, both ways, for the front ends: the model's
//! conversion ([`screwkit_model::mujoco_qpos`], where the layout is documented) on a prepared
//! tree, its errors as the floor's ([`Error::Option`] naming `qpos` or `q`).

use screwkit_model::mujoco_qpos::{self, QposError};
use screwkit_solve::TreeKinematics;

use crate::error::{Error, Result};

fn option(e: QposError) -> Error {
    Error::option(e.argument, e.message)
}

/// The length of the robot's own `qpos`: 7 for a floating base, one per movable joint.
pub fn qpos_len(kin: &TreeKinematics) -> usize {
    mujoco_qpos::qpos_len(kin.model())
}

/// The length of the whole MuJoCo model's `qpos`, props the tree reads past included.
pub fn model_qpos_len(kin: &TreeKinematics) -> usize {
    mujoco_qpos::model_qpos_len(kin.model())
}

/// screwkit's q of MuJoCo's `qpos`, the robot's own or the whole model's
/// ([`mujoco_qpos::from_qpos`]).
pub fn from_qpos(kin: &TreeKinematics, qpos: &[f64]) -> Result<Vec<f64>> {
    mujoco_qpos::from_qpos(kin.model(), qpos).map_err(option)
}

/// MuJoCo's `qpos` of screwkit's q, the robot's own, or written into the whole model's
/// ([`mujoco_qpos::to_qpos`]).
pub fn to_qpos(kin: &TreeKinematics, q: &[f64], model: Option<&[f64]>) -> Result<Vec<f64>> {
    mujoco_qpos::to_qpos(kin.model(), q, model).map_err(option)
}
