//! # beam-bvh
//!
//! One canonical binary BVH over triangles, built once and converted into layouts, as tinybvh
//! does: a compact depth-first CPU layout ([`FlatBvh`]) that every generic (beam) traversal runs
//! on, a `#[repr(C)]` bytemuck GPU layout ([`gpu`]), and a 4-wide SIMD CPU layout ([`WideBvh`]).
//! The canonical tree references triangles by index; the wide and GPU layouts add leaf-order
//! copies for memory locality.
//!
//! For single rays at Embree's speed there is [`Bvh8`]: eight-wide nodes collapsed from a binary
//! SAH tree by a dynamic program (or binned straight into them, as Embree builds them), with
//! leaves of four-triangle blocks and traversal kernels picked at run time
//! ([`Kernel`]: AVX-512, AVX2, or a portable four-lane one), every one watertight like the scalar
//! test. The default build makes a light reinsertion pass ([`BuildOptions::refine`]); for static
//! scenes, [`BuildOptions::high_quality`] optimizes the tree by full reinsertion first, and
//! [`BuildOptions::spatial_splits`] splits triangles across nodes where that pays.
//!
//! - Builders ([`BuildOptions`]): binned SAH; the projected-area heuristic (PAH) of 004 for a
//!   declared ray distribution (a parallel bundle or a pencil through a point), falling back to SAH
//!   where the distribution does not apply; splitting-plane facing (004): extra partition
//!   directions perpendicular to the rays.
//! - Traversal: closest hit and any hit (watertight triangle test), batches over slices (rayon),
//!   and a generic front-to-back traversal driven by a node test and a leaf visitor, for beams.
//! - Refit after vertices move, and statistics (node visits, triangle tests, SAH cost, depth,
//!   leaf sizes) as data.
//! - Degenerate triangles (zero area, NaN or infinite coordinates) are left out and counted.
//!
//! ```
//! use beam_bvh::beam_math::glam::Vec3;
//! use beam_bvh::beam_math::{Ray, Triangle};
//! use beam_bvh::{BuildOptions, FlatBvh};
//!
//! // Two triangles making the unit square at z = 0.
//! let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]].map(Vec3::from);
//! let triangles = vec![Triangle::new(v[0], v[1], v[2]), Triangle::new(v[0], v[2], v[3])];
//! let bvh = FlatBvh::build(&triangles, &BuildOptions::sah());
//!
//! let down = Ray::new(Vec3::new(0.25, 0.75, 2.0), Vec3::NEG_Z);
//! let hit = bvh.closest_hit(&triangles, down, f32::INFINITY).unwrap();
//! assert_eq!((hit.prim, hit.t), (1, 2.0));
//! // Any hit before t = 1 (a shadow ray that stops half way): none.
//! assert!(!bvh.any_hit(&triangles, down, 1.0));
//! ```
//!
//! `cargo run --release -p beam-bvh --example trace` does more: batches, shadow rays, statistics.

mod binning;
mod build;
mod bvh8;
mod flat;
pub mod gpu;
mod options;
mod refine;
mod refit;
mod reinsert;
mod stats;
mod traverse;
mod tree;
mod wide;

pub use build::build;
pub use bvh8::{Bvh8, Kernel, Node8, Tri4};
pub use flat::{FlatBvh, FlatNode};
pub use options::{BuildOptions, Collapse, Heuristic, RayDistribution};
pub use stats::{TraversalStats, TreeStats};
pub use traverse::{Control, Hit, NodeVisitor};
pub use tree::{Bvh, Node};
pub use wide::{WideBvh, WideNode};

pub use beam_math;
