//! Bounding-cone culling of the scene for one beam (000 App. A): the triangles a beam may meet.

use super::beam_tree::{TexelBeam, self_hit_at_rise};
use super::face::Exclude;
use beam_bvh::Node8;
use beam_math::Triangle;
use beam_math::collide::{Cone, ConeSpheres};
use beam_math::glam::Vec3;
use beam_math::nonlinear::BeamBounds;
use beam_scene::scene::Scene;

/// The scene triangles that may meet `beam` (of bounds `bounds`), less those it skips (`exclude`,
/// the surface under its base): bounding-cone culling (000 App. A) of the 8-wide BVH's boxes, eight
/// at a time, then of each triangle's bounding sphere; then the triangles next to the base that
/// lie wholly below the height that no hit past the self-hit distance reaches (`SelfHitFloor`).
#[must_use]
pub fn cone_candidates(
    scene: &Scene,
    beam: &(impl TexelBeam + ?Sized),
    bounds: &BeamBounds,
    exclude: Exclude<'_>,
) -> Vec<u32> {
    let (cull, _) = cone_cull(scene, beam, bounds, exclude);
    let mut prims = Vec::new();
    scene.wide.gather(|n| cull.spheres.meets_boxes(bounds_of(n, 0), bounds_of(n, 1)), &mut prims);
    prims.retain(|&i| cull.keeps(scene, i, exclude));
    prims
}

/// [`cone_candidates`] in two halves, for a device that culls triangle by triangle: the blocks of
/// the 8-wide BVH's leaves whose boxes meet the beam's bounding cone (block `b`: the triangles
/// `scene.wide.prims[4b..4b + 4]`), and what each of their triangles is tested with
/// ([`ConeCull::keeps`] is the host's test).
#[must_use]
pub fn cone_blocks(
    scene: &Scene,
    beam: &(impl TexelBeam + ?Sized),
    bounds: &BeamBounds,
    exclude: Exclude<'_>,
) -> (ConeCull, Vec<u32>) {
    let (cull, _) = cone_cull(scene, beam, bounds, exclude);
    (cull, blocks_meeting(scene, &cull.spheres))
}

/// The first half of [`cone_blocks`] alone: how each triangle is tested, and the beam's bounding
/// cone (000 App. A), whose blocks [`blocks_meeting`] gathers (or those of any cone holding it:
/// a superset, of which the triangle tests keep the same triangles).
#[must_use]
pub fn cone_cull(
    scene: &Scene,
    beam: &(impl TexelBeam + ?Sized),
    bounds: &BeamBounds,
    exclude: Exclude<'_>,
) -> (ConeCull, Cone) {
    let cone = beam.culling_cone(bounds);
    (ConeCull::with_cone(scene, beam, &cone, bounds, exclude), cone)
}

/// The blocks of the 8-wide BVH's leaves whose boxes' bounding spheres meet the cone of `spheres`.
#[must_use]
pub fn blocks_meeting(scene: &Scene, spheres: &ConeSpheres) -> Vec<u32> {
    let mut blocks = Vec::new();
    scene.wide.gather_blocks(|n| spheres.meets_boxes(bounds_of(n, 0), bounds_of(n, 1)), &mut blocks);
    blocks
}

/// How one beam culls a scene triangle its BVH boxes let through: by the triangle's bounding
/// sphere against the beam's bounding cone, by what the beam skips, and by its self-hit floor.
#[derive(Clone, Copy, Debug)]
pub struct ConeCull {
    /// The bounding cone (000 App. A), prepared for spheres.
    pub spheres: ConeSpheres,
    /// The self-hit floor; `None` where a ray may run parallel to the base.
    pub floor: Option<SelfHitFloor>,
}

impl ConeCull {
    /// The culling of `beam` (of bounds `bounds` and bounding cone `cone`, skipping `exclude`) in
    /// `scene`.
    fn with_cone(
        scene: &Scene,
        beam: &(impl TexelBeam + ?Sized),
        cone: &Cone,
        bounds: &BeamBounds,
        exclude: Exclude<'_>,
    ) -> Self {
        let extent = scene.bounds().extent().length();
        let floor = SelfHitFloor::new(beam, (cone, bounds.mu_b), exclude.thickness, extent);
        Self { spheres: ConeSpheres::new(cone), floor }
    }

    /// Whether scene triangle `i` may meet the beam: not skipped (`exclude`), its bounding sphere
    /// meeting the cone, and not a neighbour of the base wholly below the floor.
    #[must_use]
    pub fn keeps(&self, scene: &Scene, i: u32, exclude: Exclude<'_>) -> bool {
        let (centre, radius) = scene.bounding_sphere(i);
        !exclude.skips(i)
            && self.spheres.meets(centre, radius)
            && !self.floor.is_some_and(|f| f.culls(&scene.triangles[i as usize], exclude.near(i)))
    }
}

/// The eight children's box planes of `n`: their minima (`side` 0) or maxima (1) by axis.
fn bounds_of(n: &Node8, side: usize) -> [&[f32; 8]; 3] {
    [&n.bounds[side], &n.bounds[2 + side], &n.bounds[4 + side]]
}

/// How far below the floor a triangle must lie, as a fraction of the scene's diagonal (f32
/// rounding of the heights and of the intersection's distance).
const FLOOR_MARGIN: f32 = 1e-6;

/// The self-hit floor of a beam: the triangles next to its base (sharing a vertex with it, or in a
/// coarse face's ring) take no hit nearer than the self-hit distance `s(rise)`
/// ([`super::self_hit_at`]: `max(TEXEL_EPS·extent, 2·lift / max(rise, MIN_RISE))` along a ray of
/// rise `d̂·n` over the base plane). Every ray starts within `μ_b` of the base plane and rises at
/// least `r_min`, the cosine of the cone's axis's angle to the normal plus the cone's half-angle (a
/// half-line inside a cone points into it); the distance times the rise grows with the rise, so no
/// such hit lies lower than `floor = r_min·s(r_min) − μ_b`. A triangle next to the base wholly
/// below the floor is never hit: on a convex mirror or a flat one, every neighbour of the base,
/// each of which would otherwise be tested over the whole region (000 Alg. 3's brute-force case, as
/// it straddles the beam's side).
#[derive(Clone, Copy, Debug, Default)]
pub struct SelfHitFloor {
    /// The beam's base triangle (a neighbour shares a vertex with it).
    pub base: [Vec3; 3],
    /// The base's inner unit normal.
    pub normal: Vec3,
    /// The height over `base[0]` below which a neighbour lies wholly to be culled.
    pub floor: f32,
}

impl SelfHitFloor {
    /// The floor of `beam` (rays in `cone`, their origins within `mu_b` of the base plane: its
    /// [`TexelBeam::lift`], taken from its bounds; its self-hits judged with the surface's
    /// `thickness` off the base plane; `extent` the scene's diagonal); `None` where a ray may run
    /// parallel to the base or below it.
    fn new(beam: &(impl TexelBeam + ?Sized), (cone, mu_b): (&Cone, f32), thickness: f32, extent: f32) -> Option<Self> {
        let normal = beam.base_normal();
        // A milliradian over the angles for acos's rounding near 1.
        let steepest_away = normal.dot(cone.axis).clamp(-1.0, 1.0).acos() + cone.angle + 1e-3;
        if !(steepest_away < core::f32::consts::FRAC_PI_2) {
            return None;
        }
        let rise = steepest_away.cos();
        let lift = mu_b.max(thickness);
        let climb = rise * self_hit_at_rise(lift, rise, extent);
        let floor = climb - 1.25 * mu_b - FLOOR_MARGIN * extent;
        Some(Self { base: beam.base(), normal, floor })
    }

    /// True when `tri` is next to the base (`near`: in a coarse face's ring) and wholly below the
    /// floor.
    fn culls(&self, tri: &Triangle, near: bool) -> bool {
        (near || tri.v.iter().any(|v| self.base.contains(v)))
            && tri.v.iter().all(|&v| self.normal.dot(v - self.base[0]) < self.floor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nonlinear::self_hit_at;
    use beam_math::collide::WatertightRay;
    use beam_math::glam::Vec3;
    use beam_math::nonlinear::{NonlinearBeam, S3};
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg32;

    /// No texel ray of an S1 or S3 beam hits a triangle the floor culls beyond the self-hit
    /// distance; the floor culls a flat neighbour and a convex one, and keeps one folded up.
    #[test]
    fn culled_neighbours_are_never_hit() {
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let dirs =
            [Vec3::new(-0.3, -0.2, 1.0), Vec3::new(0.4, -0.1, 1.0), Vec3::new(-0.1, 0.5, 1.0)].map(Vec3::normalize);
        let normals = [Vec3::new(-0.1, -0.1, 1.0).normalize(), Vec3::Z, Vec3::new(0.05, 0.1, 1.0).normalize()];
        let extent = 10.0;
        let mut rng = Pcg32::seed_from_u64(7);
        let s1 = check(&NonlinearBeam::s1(base, dirs).unwrap(), extent, &mut rng);
        let s3 = check(&NonlinearBeam::new(base, dirs, S3 { normals }).unwrap(), extent, &mut rng);
        for (culled, kept) in [s1, s3] {
            assert!(culled > 50 && kept > 50, "{culled} culled, {kept} kept");
        }
        let beam = NonlinearBeam::s1(base, dirs).unwrap();
        let bounds = beam.bounds();
        let floor = SelfHitFloor::new(&beam, (&beam.culling_cone(&bounds), bounds.mu_b), 0.0, extent).unwrap();
        let flat = Triangle::new(Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
        let convex = Triangle::new(Vec3::X, Vec3::new(1.5, 1.0, -0.3), Vec3::Y);
        let folded_up = Triangle::new(Vec3::X, Vec3::new(1.0, 1.0, 0.2), Vec3::Y);
        assert!(floor.culls(&flat, false) && floor.culls(&convex, false) && !floor.culls(&folded_up, false));
        // Only triangles next to the base.
        let apart = Triangle::new(Vec3::new(2.0, 2.0, -1.0), Vec3::new(3.0, 2.0, -1.0), Vec3::new(2.0, 3.0, -1.0));
        assert!(!floor.culls(&apart, false) && floor.culls(&apart, true));
    }

    /// Random neighbours of `beam`'s base checked against its texel rays on a grid: how many were
    /// culled (never hit) and kept.
    fn check<L: beam_math::nonlinear::Interpolant>(
        beam: &NonlinearBeam<L>,
        extent: f32,
        rng: &mut Pcg32,
    ) -> (usize, usize) {
        let bounds = beam.bounds();
        let floor = SelfHitFloor::new(beam, (&beam.culling_cone(&bounds), bounds.mu_b), 0.0, extent).unwrap();
        let (mut culled, mut kept) = (Vec::new(), 0);
        for k in 0..600 {
            let mut point = || Vec3::new(rng.random_range(-2.0..3.0), rng.random_range(-2.0..3.0), 0.0);
            let (a, mut b) = (point(), point());
            b.z = rng.random_range(-0.3..0.2) * if k % 2 == 0 { 1.0 } else { 1e-3 };
            let tri = Triangle::new(beam.base[k % 3], a, b);
            if floor.culls(&tri, false) {
                culled.push(tri);
            } else {
                kept += 1;
            }
        }
        let n = 40;
        for i in 0..=n {
            for j in 0..=n - i {
                let w = Vec3::new((n - i - j) as f32, i as f32, j as f32) / n as f32;
                let ray = TexelBeam::texel_ray(beam, w);
                let t_min = self_hit_at(beam.lift(), beam.normal, ray, extent) / ray.direction.length();
                for tri in &culled {
                    assert!(WatertightRay::new(ray).intersect(tri, t_min, f32::INFINITY).is_none(), "{tri:?} at {w}");
                }
            }
        }
        (culled.len(), kept)
    }
}
