//! One face of the S mesh (000 §7.1) and the scene triangles its beams skip: what the S mesh, the
//! coarse meshes, the beams of the tree and their jobs all build on, below each of them.

use beam_math::Triangle;
use beam_math::glam::Vec3;

/// One S-mesh triangle: a mirror or glass triangle of the scene, or a face of a coarse S mesh over
/// several of them, with its smooth vertex normals.
#[derive(Clone, Copy, Debug)]
pub struct SFace {
    /// The scene triangle it is; on a coarse S mesh, the one under its centre (its material).
    pub prim: u32,
    /// Vertices.
    pub v: [Vec3; 3],
    /// Unit vertex normals, on the side of the face's geometric normal: the fine mesh's smooth
    /// normals at (or nearest to) the vertices.
    pub n: [Vec3; 3],
    /// Unit geometric normal, on the side of the fine surface's (the scene triangle's normal for a
    /// fine S mesh).
    pub normal: Vec3,
}

impl SFace {
    /// The interpolated (Phong) unit normal at barycentric coordinates `w`.
    #[must_use]
    pub fn normal_at(&self, w: Vec3) -> Vec3 {
        (w.x * self.n[0] + w.y * self.n[1] + w.z * self.n[2]).normalize_or_zero()
    }

    /// Mirror reflections about the vertex normals of the directions from `eye` to the vertices:
    /// the boundary directions of the face's reflection beam (000 §7.2).
    #[must_use]
    pub fn reflected_directions(&self, eye: Vec3) -> [Vec3; 3] {
        [0, 1, 2].map(|i| crate::specular::reflect((self.v[i] - eye).normalize_or_zero(), self.n[i]))
    }

    /// Area.
    #[must_use]
    pub fn area(&self) -> f32 {
        Triangle { v: self.v }.area()
    }

    /// Barycentric coordinates of point `p` (projected onto the face's plane).
    #[must_use]
    pub fn barycentric(&self, p: Vec3) -> Vec3 {
        Triangle { v: self.v }.barycentric(p).unwrap_or(Vec3::splat(1.0 / 3.0))
    }
}

/// True for a triangle narrower than 1e-4 of its longest edge.
pub(super) fn sliver_face(v: &[Vec3; 3]) -> bool {
    let longest =
        (v[1] - v[0]).length_squared().max((v[2] - v[1]).length_squared()).max((v[0] - v[2]).length_squared());
    (v[1] - v[0]).cross(v[2] - v[0]).length() < 1e-4 * longest
}

/// The scene triangles under a beam's base (its S-mesh face, 000 §7.1), which its rays must not
/// take for hits: the face's scene triangle, or under a coarse S-mesh face the fine triangles its
/// points map to (its patch, never hit) and those of the faces sharing a vertex with it (its ring:
/// hits nearer than the self-hit distance, with the surface's `thickness` about the face's plane
/// taken as the beam's lift, are the surface meeting itself; as for a fine face's neighbours).
#[derive(Clone, Copy, Debug)]
pub struct Exclude<'a> {
    /// The scene triangle the face is (on a coarse S mesh, one of its patch).
    pub prim: u32,
    /// The fine triangles under a coarse face, ascending (empty for a fine face).
    pub patch: &'a [u32],
    /// The fine triangles under the faces sharing a vertex with it, ascending, outside the patch.
    pub ring: &'a [u32],
    /// Largest distance of its patch's vertices from the face's plane (0 for a fine face).
    pub thickness: f32,
}

impl Exclude<'static> {
    /// A beam off scene triangle `prim` itself (a fine S mesh's face).
    #[must_use]
    pub const fn base(prim: u32) -> Self {
        Self { prim, patch: &[], ring: &[], thickness: 0.0 }
    }
}

impl Exclude<'_> {
    /// True when scene triangle `prim` is never a hit of the beam's rays.
    #[must_use]
    pub fn skips(&self, prim: u32) -> bool {
        prim == self.prim || self.patch.binary_search(&prim).is_ok()
    }

    /// True when hits on scene triangle `prim` within the self-hit distance are the surface
    /// meeting itself (besides the triangles that share a vertex with the base).
    #[must_use]
    pub fn near(&self, prim: u32) -> bool {
        self.ring.binary_search(&prim).is_ok()
    }
}
