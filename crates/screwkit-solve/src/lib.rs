//! FK, Jacobians, singularity analysis and IK on screw models (filled by the solver issue).
