//! URDF → kinematic tree → serial chain with screw axes (filled by the model issue).
