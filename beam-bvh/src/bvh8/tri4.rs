//! The leaves' data: triangles in blocks of four, structure of arrays (the tests that intersect
//! them are in [`super::leaf`]).

use beam_math::Triangle;
use beam_math::glam::Vec3;

/// Four triangles in structure-of-arrays form: `v[vertex][axis][lane]`. Unused lanes hold NaN
/// vertices, which no ray hits.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub struct Tri4 {
    /// Vertex coordinates by vertex, axis and lane.
    pub v: [[[f32; 4]; 3]; 3],
}

const _: () = assert!(size_of::<Tri4>() == 144);

impl Tri4 {
    /// A block with no triangles (every lane NaN).
    pub const EMPTY: Self = Self { v: [[[f32::NAN; 4]; 3]; 3] };

    /// Set lane `lane` to `t`.
    pub fn set(&mut self, lane: usize, t: &Triangle) {
        for (k, p) in t.v.iter().enumerate() {
            for a in 0..3 {
                self.v[k][a][lane] = p[a];
            }
        }
    }

    /// The triangle in lane `lane`.
    #[must_use]
    pub fn triangle(&self, lane: usize) -> Triangle {
        let p = |k: usize| Vec3::new(self.v[k][0][lane], self.v[k][1][lane], self.v[k][2][lane]);
        Triangle::new(p(0), p(1), p(2))
    }
}
