//! Our layouts as [`Tracer`]s: the binary tree, the 4-wide collapse of it, and the 8-wide tree
//! built directly (on the kernel the CPU picked, or forced to the portable one).

use crate::bench::tracer::Tracer;
use beam_bvh::{Bvh8, FlatBvh, TraversalStats, WideBvh};
use beam_math::{Ray, Triangle};

/// Our binary BVH.
pub(super) struct Binary<'a> {
    pub name: String,
    pub bvh: FlatBvh,
    pub tris: &'a [Triangle],
    pub build_ms: f64,
}

/// Our 4-wide layout.
pub(super) struct Wide4 {
    pub name: String,
    pub bvh: WideBvh,
    pub build_ms: f64,
}

/// Our 8-wide layout.
pub(super) struct Wide8 {
    pub name: String,
    pub bvh: Bvh8,
    pub build_ms: f64,
}

impl Tracer for Binary<'_> {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn build_ms(&self) -> f64 {
        self.build_ms
    }
    fn closest(&self, ray: &Ray) -> Option<f32> {
        self.bvh.closest_hit(self.tris, *ray, f32::INFINITY).map(|h| h.t)
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.bvh.any_hit(self.tris, *ray, t_max)
    }
}

/// A layout's work counters: closest hit and any hit of one ray into a statistics sink.
pub(super) trait Counted {
    fn name(&self) -> String;
    fn closest_stats(&self, ray: Ray, stats: &mut TraversalStats);
    fn any_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats);
}

impl Counted for Binary<'_> {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn closest_stats(&self, ray: Ray, stats: &mut TraversalStats) {
        _ = self.bvh.closest_hit_stats(self.tris, ray, f32::INFINITY, stats);
    }
    fn any_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats) {
        _ = self.bvh.any_hit_stats(self.tris, ray, t_max, stats);
    }
}

/// [`Tracer`] and [`Counted`] for our wide layouts, whose queries take the ray alone.
macro_rules! wide_layout {
    ($($layout:ty),*) => {$(
        impl Tracer for $layout {
            fn name(&self) -> String {
                self.name.clone()
            }
            fn build_ms(&self) -> f64 {
                self.build_ms
            }
            fn closest(&self, ray: &Ray) -> Option<f32> {
                self.bvh.closest_hit(*ray, f32::INFINITY).map(|h| h.t)
            }
            fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
                self.bvh.any_hit(*ray, t_max)
            }
        }

        impl Counted for $layout {
            fn name(&self) -> String {
                self.name.clone()
            }
            fn closest_stats(&self, ray: Ray, stats: &mut TraversalStats) {
                _ = self.bvh.closest_hit_stats(ray, f32::INFINITY, stats);
            }
            fn any_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats) {
                _ = self.bvh.any_hit_stats(ray, t_max, stats);
            }
        }
    )*};
}

wide_layout!(Wide4, Wide8);
