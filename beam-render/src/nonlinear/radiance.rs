//! The radiance flow of a beam tree (000 §7.3): for each level, the texels that hit, and for those
//! on a specular S-mesh face the child beams they are textured from (bilinear, Fresnel-weighted for
//! glass). [`composite_levels`](super::composite_levels) runs it on the host; beam-gpu keeps it on the GPU.

use super::smesh::SMesh;
use super::texture::ShadePoint;
use crate::specular::dielectric;
use beam_math::glam::Vec3;
use beam_scene::scene::{Material, Scene};

/// The child beams a texel on a specular S-mesh face is textured from, and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Composite {
    /// The S-mesh face.
    pub face: u32,
    /// Its reflection beam (index into the level below).
    pub reflected: u32,
    /// Its refraction beam, for glass.
    pub refracted: Option<u32>,
    /// Barycentric coordinates on the face where the reflection beam is looked up: the point's
    /// own on a face that is a scene triangle.
    pub reflected_at: Vec3,
    /// Where the refraction beam is looked up.
    pub refracted_at: Vec3,
}

/// A texel (or pixel) that hit, and how its radiance is found.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TexelRadiance {
    /// Its index in the level's radiance.
    pub texel: u32,
    /// The point its ray hit.
    pub point: ShadePoint,
    /// `Some` on a specular face with child beams; `None`: shaded by `shade_points`.
    pub composite: Option<Composite>,
}

/// One level of the tree (or the eye's view) for the radiance flow.
#[derive(Clone, Debug, Default)]
pub struct LevelRadiance {
    /// Per beam: its first texel in the level's radiance and its texels per side (empty for the eye).
    pub regions: Vec<(u32, u32)>,
    /// Texels of the level's radiance (pixels for the eye).
    pub len: usize,
    /// Its texels that hit (less those a backend kept, [`super::BeamRasterizer::render_level`],
    /// [`super::EyeView::eye_faces`]).
    pub texels: Vec<TexelRadiance>,
    /// Its texels (pixels) whose ray leaves the scene, with that ray's direction: they show the
    /// environment. Empty where the environment is black.
    pub missed: Vec<(u32, Vec3)>,
    /// Per S-mesh face: its reflection and refraction beams in the level below, [`u32::MAX`] for
    /// none (the eye's view; for the pixels a backend kept).
    pub children: Vec<[u32; 2]>,
    /// Per beam of a tree level whose handed-back texels the backend composites itself
    /// ([`super::KeptTotals::records`]; they are then not in `texels`): the child beams of the
    /// faces they hit. Empty otherwise.
    pub node_children: NodeChildren,
}

/// Per beam of a tree level, the child beams of the S-mesh faces its texels hit (the host's
/// `Tree::composite` on a fine face): what a backend needs to composite those texels itself.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NodeChildren {
    /// Per beam, its first entry; then the number of entries.
    pub firsts: Vec<u32>,
    /// Per beam, ascending by face: the face, its reflection beam and its refraction beam in the
    /// level below ([`u32::MAX`] for none).
    pub entries: Vec<[u32; 3]>,
}

impl NodeChildren {
    /// True where there are no beams.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.firsts.is_empty()
    }
}

/// Bilinear lookup at barycentric `w` of a `size × size` region's radiance (row-major), over its
/// rendered texels (`x + y ≤ size`, [`super::BeamTexture::in_region`]) only.
#[must_use]
pub fn sample_region(radiance: &[Vec3], size: u32, w: Vec3) -> Vec3 {
    let n = size as f32;
    let (fx, fy) = (w.y * n - 0.5, w.z * n - 0.5);
    let (x0, y0) = (fx.floor(), fy.floor());
    let (ax, ay) = (fx - x0, fy - y0);
    let (mut sum, mut weight) = (Vec3::ZERO, 0.0);
    for (dx, dy, k) in
        [(0, 0, (1.0 - ax) * (1.0 - ay)), (1, 0, ax * (1.0 - ay)), (0, 1, (1.0 - ax) * ay), (1, 1, ax * ay)]
    {
        let (x, y) = ((x0 as i64 + dx).clamp(0, n as i64 - 1) as u32, (y0 as i64 + dy).clamp(0, n as i64 - 1) as u32);
        if x + y < size + 1 && k > 0.0 {
            sum += k * radiance.get((y * size + x) as usize).copied().unwrap_or_default();
            weight += k;
        }
    }
    if weight > 0.0 { sum / weight } else { Vec3::ZERO }
}

/// Radiance leaving the point of `t` (on a specular face with child beams) towards the arriving ray:
/// the children's radiance where `c` looks them up (`sample(beam, w)`, at the point's own
/// barycentric coordinates on a face that is a scene triangle), tinted for a mirror,
/// Fresnel-weighted (about the face's interpolated normal there) for glass (reflection only under
/// total internal reflection).
#[must_use]
pub fn composite(
    scene: &Scene,
    smesh: &SMesh,
    point: &ShadePoint,
    c: Composite,
    sample: impl Fn(u32, Vec3) -> Vec3,
) -> Vec3 {
    let f = &smesh.faces[c.face as usize];
    let w = c.reflected_at;
    let reflected = sample(c.reflected, w);
    match (scene.material(f.prim), c.refracted) {
        (Material::Mirror { tint, .. }, _) => tint * reflected,
        (Material::Glass { ior }, Some(refracted)) => {
            let entering = point.d.dot(f.normal) < 0.0;
            let n = if entering { f.normal_at(w) } else { -f.normal_at(w) };
            match dielectric(point.d, n, ior, entering) {
                (fresnel, Some(_)) => fresnel * reflected + (1.0 - fresnel) * sample(refracted, c.refracted_at),
                (_, None) => reflected,
            }
        }
        _ => reflected,
    }
}
