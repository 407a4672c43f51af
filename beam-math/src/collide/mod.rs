//! Collision and culling routines: every algorithm of 004 Appendix A and the cone–sphere test of
//! 000 Appendix A, one file each.

mod aabb_aabb;
mod aabb_planes;
mod cone_sphere;
mod distance;
mod frustum;
mod frustum_aabb;
mod point_in;
mod polygon;
mod ray_aabb;
mod ray_plane;
mod ray_triangle;

pub use aabb_aabb::aabb_aabb;
pub use aabb_planes::aabb_outside_planes;
pub use cone_sphere::{Cone, ConeSpheres, cone_sphere};
pub use distance::{closest_point_on_triangle, segment_segment_distance, triangle_triangle_distance};
pub use frustum::Frustum;
pub use frustum_aabb::{frustum_aabb, separating_axes};
pub use point_in::{point_in_aabb, point_in_convex_polygon, point_in_convex_polygon_3d, point_in_frustum};
pub use polygon::{
    CapacityExceeded, ConvexPolygon, convex_hull, order_ccw, segment_intersection, shoelace_area, signed_area,
};
pub use ray_aabb::{SlabHit, ray_aabb, ray_aabb_inv};
pub use ray_plane::{line_plane, ray_plane};
pub use ray_triangle::{TriangleHit, WatertightRay, ray_triangle};
