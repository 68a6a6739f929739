//! The voxel grid of a map and the poses tested in each voxel.
//!
//! Voxel centres sit at integer multiples of the resolution in the base frame, so the planes
//! x = 0, y = 0 and z = 0 through the base are layers of the grid (the slices of the pictures).
//! Voxel v = (i·n_y + j)·n_z + k (C order over the shape (n_x, n_y, n_z)) has its centre at
//! origin + (i, j, k)·resolution.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::ReachError;

/// A regular grid of voxel centres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    /// The centre of voxel (0, 0, 0), a multiple of `resolution` per axis (m).
    pub origin: [f64; 3],
    /// Edge length of a voxel (m).
    pub resolution: f64,
    /// Voxels along x, y, z.
    pub shape: [usize; 3],
}

impl Grid {
    /// The grid of voxels of edge `resolution` whose centres are the multiples of the
    /// resolution from `lo` to `hi` (each rounded to the nearest multiple).
    pub fn covering(lo: [f64; 3], hi: [f64; 3], resolution: f64) -> Result<Grid, ReachError> {
        if !(resolution.is_finite() && resolution > 0.0) {
            return Err(ReachError::Input(format!(
                "the resolution must be a positive length in metres, got {resolution}"
            )));
        }
        let mut origin = [0.0; 3];
        let mut shape = [0; 3];
        for a in 0..3 {
            if !(lo[a].is_finite() && hi[a].is_finite() && lo[a] <= hi[a]) {
                return Err(ReachError::Input(format!(
                    "bounds along {} must be finite with min ≤ max, got {} .. {}",
                    ["x", "y", "z"][a],
                    lo[a],
                    hi[a]
                )));
            }
            let (m0, m1) = ((lo[a] / resolution).round(), (hi[a] / resolution).round());
            origin[a] = m0 * resolution;
            shape[a] = (m1 - m0) as usize + 1;
        }
        let grid = Grid {
            origin,
            resolution,
            shape,
        };
        if grid.len() > 1 << 40 {
            return Err(ReachError::Input(format!(
                "{} voxels is more than any map can hold: use a coarser resolution",
                grid.len()
            )));
        }
        Ok(grid)
    }

    /// Number of voxels.
    pub fn len(&self) -> usize {
        // Saturating: a grid read from a damaged file never overflows.
        self.shape.iter().fold(1usize, |n, &d| n.saturating_mul(d))
    }

    /// True when the grid has no voxel.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The centre of voxel `v` (C order over the shape).
    pub fn centre(&self, v: usize) -> [f64; 3] {
        let [_, ny, nz] = self.shape;
        let (i, j, k) = (v / (ny * nz), (v / nz) % ny, v % nz);
        [
            self.origin[0] + i as f64 * self.resolution,
            self.origin[1] + j as f64 * self.resolution,
            self.origin[2] + k as f64 * self.resolution,
        ]
    }

    /// The index along `axis` of the layer through coordinate 0 (the base), if the grid has one.
    pub fn zero_layer(&self, axis: usize) -> Option<usize> {
        let m = (-self.origin[axis] / self.resolution).round();
        (m >= 0.0 && (m as usize) < self.shape[axis]).then_some(m as usize)
    }
}

pub use screwkit_service::words::OrientationMode;

/// The K rotations (tool orientation in the base frame) tested in every voxel.
pub fn orientations(mode: OrientationMode, k: usize) -> Vec<Matrix3<f64>> {
    match mode {
        OrientationMode::Free => super_fibonacci(k),
        OrientationMode::Directions => fibonacci_sphere(k)
            .into_iter()
            .map(|d| pointing(-d))
            .collect(),
    }
}

/// Super-Fibonacci spiral on SO(3) (Alexa, "Super-Fibonacci Spirals: Fast, Low-Discrepancy
/// Sampling of SO(3)", CVPR 2022): for s = i + ½, r = √(s/n), R = √(1 − s/n), α = 2πs/φ,
/// β = 2πs/ψ with φ = √2 and ψ the root of ψ⁴ = ψ + 4, the unit quaternion
/// (r sin α, r cos α, R sin β, R cos β).
fn super_fibonacci(n: usize) -> Vec<Matrix3<f64>> {
    let phi = std::f64::consts::SQRT_2;
    let psi = 1.533_751_168_755_204_3;
    (0..n)
        .map(|i| {
            let s = i as f64 + 0.5;
            let (r, big_r) = ((s / n as f64).sqrt(), (1.0 - s / n as f64).sqrt());
            let (alpha, beta) = (
                std::f64::consts::TAU * s / phi,
                std::f64::consts::TAU * s / psi,
            );
            let q = nalgebra::Quaternion::new(
                big_r * beta.cos(),
                r * alpha.sin(),
                r * alpha.cos(),
                big_r * beta.sin(),
            );
            *UnitQuaternion::from_quaternion(q)
                .to_rotation_matrix()
                .matrix()
        })
        .collect()
}

/// n points evenly on the unit sphere (the Fibonacci lattice: z = 1 − (2i + 1)/n, longitude
/// steps of the golden angle).
fn fibonacci_sphere(n: usize) -> Vec<Vector3<f64>> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2 * i + 1) as f64 / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let (s, c) = (golden * i as f64).sin_cos();
            Vector3::new(r * c, r * s, z)
        })
        .collect()
}

/// A rotation whose z axis is `z` (unit), x axis in the plane of z and the base's z axis.
fn pointing(z: Vector3<f64>) -> Matrix3<f64> {
    let up = if z.z.abs() > 1.0 - 1e-9 {
        Vector3::x()
    } else {
        Vector3::z()
    };
    let x = up.cross(&z).cross(&z).normalize() * -1.0;
    let y = z.cross(&x);
    Matrix3::from_columns(&[x, y, z])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_layers_through_the_base() {
        let g = Grid::covering([-1.02, -0.5, 0.1], [1.0, 0.5, 1.2], 0.1).unwrap();
        assert_eq!(g.shape, [21, 11, 12]);
        assert!((g.origin[0] + 1.0).abs() < 1e-12);
        assert_eq!(g.zero_layer(0), Some(10));
        assert_eq!(g.zero_layer(2), None);
        let v = (3 * 11 + 4) * 12 + 5;
        let c = g.centre(v);
        assert!((c[0] - (-0.7)).abs() < 1e-12 && (c[1] + 0.1).abs() < 1e-12);
        assert!((c[2] - 0.6).abs() < 1e-12);
        assert!(Grid::covering([0.0; 3], [1.0; 3], 0.0).is_err());
        assert!(Grid::covering([0.0; 3], [f64::NAN; 3], 0.1).is_err());
    }

    /// The orientation sets are rotations, distinct and spread: every one of 2000 random
    /// rotations is within 50° of one of 200 super-Fibonacci ones (the covering radius of 200
    /// well-spread rotations is ≈ 36–45°), and the directions' z axes point inwards.
    #[test]
    fn orientation_sets_are_spread_rotations() {
        for mode in [OrientationMode::Free, OrientationMode::Directions] {
            let set = orientations(mode, 200);
            assert_eq!(set.len(), 200);
            for r in &set {
                assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-12);
                assert!((r.determinant() - 1.0).abs() < 1e-12);
            }
        }
        let set = orientations(OrientationMode::Free, 200);
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut worst: f64 = 0.0;
        for _ in 0..2000 {
            let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                next() - 0.5,
                next() - 0.5,
                next() - 0.5,
                next() - 0.5,
            ));
            let r = q.to_rotation_matrix();
            let best = set
                .iter()
                .map(|s| {
                    let c = ((s.transpose() * r.matrix()).trace() - 1.0) / 2.0;
                    c.clamp(-1.0, 1.0).acos()
                })
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(best);
        }
        assert!(worst < 50f64.to_radians(), "{}", worst.to_degrees());
        let dirs = fibonacci_sphere(100);
        let mean: Vector3<f64> = dirs.iter().sum::<Vector3<f64>>() / 100.0;
        assert!(mean.norm() < 0.02);
        for (d, r) in dirs
            .iter()
            .zip(orientations(OrientationMode::Directions, 100))
        {
            assert!((r.column(2) + d).norm() < 1e-12);
        }
    }
}
