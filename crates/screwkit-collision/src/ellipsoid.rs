//! MuJoCo's ellipsoid geom as a convex shape of the engine (parry has none): given by its
//! support function, so that every convex query (intersection, distance, penetration, witness
//! points) runs through the engine's GJK and EPA, exactly as for its own round shapes.
//!
//! For semi-axes r = (a, b, c) and a direction d, the support point (the surface point of
//! greatest d · p) is p = R² d / ‖R d‖ with R = diag(a, b, c): the ellipsoid is the unit
//! sphere stretched by R, whose support along d is R (R d / ‖R d‖).

use parry3d_f64::bounding_volume::{Aabb, BoundingSphere};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::math::{Real, Vector};
use parry3d_f64::query::details::{
    local_point_projection_on_support_map, local_ray_intersection_with_support_map_with_params,
};
use parry3d_f64::query::gjk::VoronoiSimplex;
use parry3d_f64::query::{PointProjection, PointQuery, Ray, RayCast, RayIntersection};
use parry3d_f64::shape::{FeatureId, Shape, ShapeType, SupportMap, TypedShape};

/// An ellipsoid centred on its frame's origin, semi-axes along x, y, z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipsoid {
    /// Semi-axes (m), each > 0.
    pub radii: Vector,
}

impl Ellipsoid {
    /// The ellipsoid of semi-axes `radii`.
    pub fn new(radii: [f64; 3]) -> Ellipsoid {
        Ellipsoid {
            radii: Vector::new(radii[0], radii[1], radii[2]),
        }
    }
}

impl SupportMap for Ellipsoid {
    fn local_support_point(&self, dir: Vector) -> Vector {
        let stretched = self.radii * dir;
        let len = stretched.length();
        if len > 0.0 && len.is_finite() {
            self.radii * stretched / len
        } else {
            Vector::new(self.radii.x, 0.0, 0.0)
        }
    }
}

impl PointQuery for Ellipsoid {
    fn project_local_point(&self, pt: Vector, solid: bool) -> PointProjection {
        local_point_projection_on_support_map(self, &mut VoronoiSimplex::new(), pt, solid)
    }

    fn project_local_point_and_get_feature(&self, pt: Vector) -> (PointProjection, FeatureId) {
        (self.project_local_point(pt, false), FeatureId::Unknown)
    }
}

impl RayCast for Ellipsoid {
    fn cast_local_ray_and_get_normal(
        &self,
        ray: &Ray,
        max_time_of_impact: Real,
        solid: bool,
    ) -> Option<RayIntersection> {
        local_ray_intersection_with_support_map_with_params(
            self,
            &mut VoronoiSimplex::new(),
            ray,
            max_time_of_impact,
            solid,
        )
    }
}

impl Shape for Ellipsoid {
    fn compute_local_aabb(&self) -> Aabb {
        Aabb::new(-self.radii, self.radii)
    }

    fn compute_local_bounding_sphere(&self) -> BoundingSphere {
        BoundingSphere::new(Vector::ZERO, self.radii.max_element())
    }

    fn clone_dyn(&self) -> Box<dyn Shape> {
        Box::new(*self)
    }

    fn scale_dyn(&self, scale: Vector, _num_subdivisions: u32) -> Option<Box<dyn Shape>> {
        Some(Box::new(Ellipsoid {
            radii: self.radii * scale.abs(),
        }))
    }

    /// Mass m = ρ (4/3) π a b c; principal moments m (b² + c²) / 5, m (a² + c²) / 5,
    /// m (a² + b²) / 5.
    fn mass_properties(&self, density: Real) -> MassProperties {
        let r = self.radii;
        let mass = density * 4.0 / 3.0 * std::f64::consts::PI * r.x * r.y * r.z;
        let sq = r * r;
        MassProperties::new(
            Vector::ZERO,
            mass,
            Vector::new(sq.y + sq.z, sq.x + sq.z, sq.x + sq.y) * (mass / 5.0),
        )
    }

    fn shape_type(&self) -> ShapeType {
        ShapeType::Custom
    }

    fn as_typed_shape(&self) -> TypedShape<'_> {
        TypedShape::Custom(self)
    }

    fn ccd_thickness(&self) -> Real {
        self.radii.min_element()
    }

    fn ccd_angular_thickness(&self) -> Real {
        std::f64::consts::FRAC_PI_2
    }

    fn as_support_map(&self) -> Option<&dyn SupportMap> {
        Some(self as &dyn SupportMap)
    }
}

impl Ellipsoid {
    /// The closest point of the ellipsoid's surface to `y` (local frame), for `y` outside:
    /// x_i = a_i² y_i / (a_i² + t), with t ≥ 0 the root of Σ (a_i y_i / (a_i² + t))² = 1, found
    /// by Newton's method from t = 0 (the function is decreasing and convex there, so the
    /// iterates rise monotonically to the root). A point inside is returned as it is.
    pub fn project_outside(&self, y: Vector) -> Vector {
        let a2 = self.radii * self.radii;
        let f = |t: f64| {
            let u = self.radii * y / (a2 + Vector::splat(t));
            let value = u.length_squared() - 1.0;
            // d/dt Σ a_i² y_i² (a_i² + t)^-2 = -2 Σ a_i² y_i² (a_i² + t)^-3
            let slope = -2.0 * (u * u / (a2 + Vector::splat(t))).element_sum();
            (value, slope)
        };
        let mut t = 0.0;
        for _ in 0..100 {
            let (value, slope) = f(t);
            if value <= 0.0 || slope >= 0.0 {
                break;
            }
            let next = t - value / slope;
            if next <= t {
                break;
            }
            t = next;
        }
        if t == 0.0 {
            return y;
        }
        a2 * y / (a2 + Vector::splat(t))
    }
}

/// The closest points of two convex shapes, one of them (or both) an ellipsoid, refined from
/// the engine's GJK estimate (`p1` on shape 1, `p2` on shape 2, world frame): alternate
/// projections, each point onto the other shape, until they stop moving. GJK stops within its
/// tolerance of a smooth surface (5e-6 m off on a 0.3 m sphere); the projections are exact,
/// and their distance never grows.
pub(crate) fn polish(
    (s1, pose1): (&dyn Shape, &parry3d_f64::math::Pose),
    (s2, pose2): (&dyn Shape, &parry3d_f64::math::Pose),
    mut p1: Vector,
    mut p2: Vector,
) -> (Vector, Vector) {
    let project = |s: &dyn Shape, pose: &parry3d_f64::math::Pose, p: Vector| match s
        .as_shape::<Ellipsoid>()
    {
        Some(e) => pose.transform_point(e.project_outside(pose.inverse_transform_point(p))),
        None => s.project_point(pose, p, true).point,
    };
    let mut best = (p2 - p1).length();
    for _ in 0..200 {
        let q2 = project(s2, pose2, p1);
        let q1 = project(s1, pose1, q2);
        let d = (q2 - q1).length();
        // Stop when the distance no longer falls (or is not a number).
        if d.partial_cmp(&best) != Some(std::cmp::Ordering::Less) {
            break;
        }
        let moved = (q1 - p1).length() + (q2 - p2).length();
        (p1, p2, best) = (q1, q2, d);
        if moved < 1e-15 {
            break;
        }
    }
    (p1, p2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::math::Pose;
    use parry3d_f64::query;

    /// A sphere's support and distances, through the ellipsoid of equal semi-axes, equal the
    /// engine's own ball.
    #[test]
    fn equal_axes_is_a_ball() {
        let e = Ellipsoid::new([0.3, 0.3, 0.3]);
        let ball = parry3d_f64::shape::Ball::new(0.3);
        let other = parry3d_f64::shape::Cuboid::new(Vector::new(0.1, 0.2, 0.05));
        let at = Pose::translation(0.5, 0.4, -0.2);
        let d_ball = query::distance(&Pose::IDENTITY, &ball, &at, &other)
            .unwrap()
            .distance;
        let Ok(query::ClosestPoints::WithinMargin(p1, p2)) =
            query::closest_points(&Pose::IDENTITY, &e, &at, &other, f64::MAX)
        else {
            panic!("no closest points")
        };
        // GJK alone is off by its tolerance; polished, it is the ball's exact distance.
        let (q1, q2) = polish((&e, &Pose::IDENTITY), (&other, &at), p1, p2);
        let d = (q2 - q1).length();
        assert!((d - d_ball).abs() < 1e-12, "{d} vs {d_ball}");
        assert!((q1.length() - 0.3).abs() < 1e-15);
    }

    /// A point on an axis: the distance to the ellipsoid is the point's coordinate less the
    /// semi-axis; the support along an axis is the semi-axis's end.
    #[test]
    fn axis_distances_are_the_semi_axes() {
        let e = Ellipsoid::new([0.1, 0.2, 0.4]);
        let ball = parry3d_f64::shape::Ball::new(0.01);
        for (k, r) in [0.1, 0.2, 0.4].into_iter().enumerate() {
            let mut p = Vector::ZERO;
            p[k] = 1.0;
            assert!((e.local_support_point(p) - p * r).length() < 1e-15);
            let at = Pose::from_translation(p * 2.0);
            let d = query::distance(&Pose::IDENTITY, &e, &at, &ball)
                .unwrap()
                .distance;
            assert!((d - (2.0 - r - 0.01)).abs() < 1e-9, "axis {k}: {d}");
        }
    }
}
