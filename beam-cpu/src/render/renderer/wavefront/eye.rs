//! Exact primary visibility for the wavefront frame (001 §3): every pixel's fragments — the
//! triangles its square sees, their coverages and the centroids of their visible parts — from the
//! backend's eye beams, the pixels it leaves (or all, from a backend without eye beams) by the
//! CPU's exact visible surface through the pixel's square.

use crate::render::primary_beam::visible_surface;
use crate::render::shadow_beam::BeamStats;
use beam_math::glam::Vec2;
use beam_math::polybeam::BeamFrame;
use beam_render::BackendError;
use beam_render::queries::{BeamQueries, PixelFragment, PixelFragments};
use beam_scene::scene::{Camera, Scene};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Sample slots of a pixel in the eye's wavefront: its fragments take the first, up to this many
/// less one (a pixel that sees more shares the last slot), and the background the last.
pub(super) const EYE_SAMPLES: u32 = 64;

/// The fragments of pixel `(x, y)` of `camera` by the CPU's exact visible surface through its
/// square (`None`: the camera cannot make a frame).
#[must_use]
pub fn pixel_fragments(scene: &Scene, camera: &Camera, x: u32, y: u32) -> Option<PixelFragments> {
    Some(PixelSquares::of(camera)?.fragments(scene, x, y))
}

/// The pixels' squares on the image plane of a camera's eye beams (beam-cpu's frame: distance 1
/// along the view, `u` right, `v` down the image).
struct PixelSquares {
    frame: BeamFrame,
    corner: Vec2,
    size: Vec2,
}

impl PixelSquares {
    fn of(camera: &Camera) -> Option<Self> {
        let f = camera.frame();
        let frame = BeamFrame::new(camera.position, camera.position + f.forward, f.forward, f.right)?;
        let size = Vec2::new(2.0 * f.half_width / camera.width as f32, 2.0 * f.half_height / camera.height as f32);
        Some(Self { frame, corner: Vec2::new(-f.half_width, -f.half_height), size })
    }

    /// The fragments of pixel `(x, y)`.
    fn fragments(&self, scene: &Scene, x: u32, y: u32) -> PixelFragments {
        let lo = self.corner + Vec2::new(x as f32, y as f32) * self.size;
        let to_pixel = |c: Vec2| (c - self.corner) / self.size;
        let mut seen: BTreeMap<Option<u32>, (f32, Vec2)> = BTreeMap::new();
        let pieces =
            visible_surface(&scene.bvh, &scene.triangles, &self.frame, lo, lo + self.size, &mut BeamStats::default());
        for piece in pieces {
            let v = piece.section.vertices();
            // The area centroid of the convex piece (shoelace), in pixel coordinates.
            let (mut twice, mut moment) = (0.0f32, Vec2::ZERO);
            for i in 0..v.len() {
                let (a, b) = (to_pixel(v[i]), to_pixel(v[(i + 1) % v.len()]));
                let cross = a.perp_dot(b);
                twice += cross;
                moment += (a + b) * cross;
            }
            let area = 0.5 * twice.abs();
            if area > 0.0 {
                let e = seen.entry(piece.prim).or_insert((0.0, Vec2::ZERO));
                e.0 += area;
                e.1 += moment / (3.0 * twice) * area;
            }
        }
        let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        let mut out = PixelFragments { background_centroid: centre, ..PixelFragments::default() };
        for (prim, (coverage, moment)) in seen {
            let centroid = moment / coverage;
            match prim {
                Some(prim) => out.fragments.push(PixelFragment { prim, coverage, centroid }),
                None => (out.background, out.background_centroid) = (coverage, centroid),
            }
        }
        out
    }
}

/// Every pixel's fragments, row-major: `backend`'s where it gave them, the CPU's elsewhere where
/// `wanted` (row-major; elsewhere none: those pixels are not rendered by eye beams); and how many
/// wanted pixels the backend left to the host (0 for a backend without eye beams).
pub(super) fn eye_view(
    scene: &Scene,
    camera: &Camera,
    backend: &dyn BeamQueries,
    wanted: &[bool],
) -> Result<(Vec<PixelFragments>, u64), BackendError> {
    let given = backend.eye_fragments(scene, camera)?;
    let n = (camera.width * camera.height) as usize;
    let squares = PixelSquares::of(camera);
    let view: Vec<(PixelFragments, bool)> = (0..n)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i as u32 % camera.width, i as u32 / camera.width);
            match given.as_ref().and_then(|g| g.get(i).cloned()) {
                Some(Some(p)) => (p, false),
                _ if !wanted[i] => (PixelFragments::default(), false),
                // Left by the backend (counted), or a backend without eye beams (not counted).
                left => (squares.as_ref().map(|s| s.fragments(scene, x, y)).unwrap_or_default(), left.is_some()),
            }
        })
        .collect();
    let left = view.iter().filter(|(_, left)| *left).count() as u64;
    Ok((view.into_iter().map(|(p, _)| p).collect(), left))
}
