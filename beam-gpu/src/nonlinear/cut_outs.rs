//! Nonlinear beams through cut-outs (glTF `MASK`, `BLEND`): the GPU's atlas takes every triangle
//! as opaque, so a beam one of whose texels' nearest hits lies where a cut-out's surface is not
//! there ([`Scene::is_there`] for the texel's ray, as rays decide) is rendered again on the host by
//! [`render_beam`], which tests the alpha at every hit as a rasterizer's alpha test does and goes
//! on to the next nearest. Its texture is then the CPU's, texel for texel.

use beam_bvh::Hit;
use beam_render::nonlinear::{BeamJob, BeamTexture, render_beam};
use beam_scene::scene::Scene;
use rayon::prelude::*;

/// Render again on the host each of `jobs` whose texture (the GPU's, in `textures`) has a texel
/// hit where a cut-out is not there; how many were.
pub(super) fn see_through_cut_outs(scene: &Scene, jobs: &[BeamJob<'_>], textures: &mut [BeamTexture]) -> u64 {
    if !scene.has_cut_outs() {
        return 0;
    }
    jobs.par_iter()
        .zip(textures.par_iter_mut())
        .filter(|(job, tex)| sees_through(scene, job, tex))
        .map(|(job, tex)| *tex = render_beam(scene, job.beam.texel_beam(), job.size, job.exclude))
        .count() as u64
}

/// Whether a texel of `tex`, the texture of `job`, hits a cut-out where its surface is not there.
fn sees_through(scene: &Scene, job: &BeamJob<'_>, tex: &BeamTexture) -> bool {
    let beam = job.beam.texel_beam();
    let size = tex.size as usize;
    tex.hits.iter().enumerate().any(|(k, hit)| {
        let Some(hit) = hit.as_ref().filter(|h| scene.cut_out(h.prim).is_some()) else { return false };
        let Some(tri) = scene.triangles.get(hit.prim as usize) else { return false };
        let ray = beam.texel_ray(tex.barycentric((k % size) as u32, (k / size) as u32));
        !scene.is_there(&ray, &Hit::on(tri, hit.prim, &ray, hit.t))
    })
}
