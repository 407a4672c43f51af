//! The nonlinear renderer (000 §7): the eye sees the scene directly; every mirror triangle of the
//! S mesh that faces the eye spawns a nonlinear reflection beam (S1 or S3 over the vertex normals),
//! rendered into its texel region; the mirror's pixels are then textured from those regions. Further
//! bounces inside a beam's texels are shaded by the shared Whitted shading (rays). The reference
//! traces the same mirrors with rays reflected about the interpolated (Phong) normal.

use super::atlas::{BeamTexture, render_beam};
use super::smesh::{SFace, SMesh};
use crate::render::{Image, RenderOptions, reflect, shade_point, shading_eps, trace_radiance};
use crate::scene::{Material, Scene};
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_math::nonlinear::{Interpolant, NonlinearBeam, S3};
use rayon::prelude::*;
use std::time::Instant;

/// The S^n parameterization of the beams (000 §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Degree {
    /// Linear (eq. 3): C⁰ across S-mesh edges, so reflections show kinks (000 Fig. 4).
    S1,
    /// Cubic over the vertex normals (eq. 6): C¹ at the S-mesh vertices.
    S3,
}

/// Settings of the nonlinear renderer.
#[derive(Clone, Copy, Debug)]
pub struct NonlinearOptions {
    /// Beam parameterization.
    pub degree: Degree,
    /// Texels per side of each beam's region.
    pub texels: u32,
    /// Shading of everything the beams and the eye see.
    pub shading: RenderOptions,
}

/// What a nonlinear render did (000 §8's statistics).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct NonlinearStats {
    /// Wall time, seconds.
    pub seconds: f64,
    /// `s1` or `s3`.
    pub degree: String,
    /// Beams per level of the beam tree (level 1: reflection beams off the S mesh).
    pub beams_per_level: Vec<u64>,
    /// Mean scene triangles per beam after bounding-cone culling.
    pub triangles_per_beam: f64,
    /// Texels tested in bounding triangles over texels rendered (the overdraw of 000 Fig. 7).
    pub overdraw: f64,
    /// Texels shaded.
    pub texels_shaded: u64,
    /// Image width and height.
    pub width: u32,
    /// Image height.
    pub height: u32,
}

/// The reflection beam off S-mesh face `f` seen from `eye`, rendered and shaded.
fn reflection_texture(scene: &Scene, f: &SFace, eye: Vec3, options: &NonlinearOptions) -> Option<BeamTexture> {
    let dirs = f.reflected_directions(eye);
    match options.degree {
        Degree::S1 => NonlinearBeam::s1(f.v, dirs).map(|b| shaded_texture(scene, &b, f.prim, options)),
        Degree::S3 => {
            NonlinearBeam::new(f.v, dirs, S3 { normals: f.n }).map(|b| shaded_texture(scene, &b, f.prim, options))
        }
    }
}

/// `beam` (off S-mesh triangle `prim`) rendered into its texel region, every texel hit shaded (the
/// fragment stage's shading).
fn shaded_texture<L: Interpolant>(
    scene: &Scene,
    beam: &NonlinearBeam<L>,
    prim: u32,
    options: &NonlinearOptions,
) -> BeamTexture {
    let mut tex = render_beam(scene, beam, options.texels, prim);
    for y in 0..tex.size {
        for x in 0..tex.size {
            let k = (y * tex.size + x) as usize;
            let Some(hit) = tex.hits[k] else { continue };
            let ray = beam.ray_at(tex.barycentric(x, y));
            let seed = u64::from(prim) << 32 | k as u64;
            tex.radiance[k] =
                shade_point(scene, &options.shading, hit.prim, ray.at(hit.t), ray.direction.normalize(), seed);
        }
    }
    tex
}

/// Render `scene` with its mirrors by nonlinear beams.
#[must_use]
pub fn render_nonlinear(scene: &Scene, options: &NonlinearOptions) -> (Image, NonlinearStats) {
    let start = Instant::now();
    let mut camera = scene.camera;
    camera.width = options.shading.width.max(1);
    camera.height = options.shading.height.max(1);
    let eye = camera.position;
    let smesh = SMesh::mirrors(scene);
    let frame = camera.frame();
    let w = camera.width as usize;
    // The eye's view: per pixel centre, the nearest hit; the S-mesh faces it sees are the roots of
    // the beam tree.
    let hits: Vec<Option<(Ray, beam_bvh::Hit)>> = (0..w * camera.height as usize)
        .into_par_iter()
        .map(|i| {
            let ray = camera.ray(&frame, (i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            scene.wide.closest_hit(ray, f32::INFINITY).map(|h| (ray, h))
        })
        .collect();
    let mut seen = vec![false; smesh.faces.len()];
    for (_, h) in hits.iter().flatten() {
        if let Some(&fi) = smesh.face_of.get(&h.prim) {
            seen[fi] = true;
        }
    }
    // Level 1 of the beam tree: a reflection beam per S-mesh face the eye sees.
    let textures: Vec<Option<BeamTexture>> = smesh
        .faces
        .par_iter()
        .zip(&seen)
        .map(|(f, &seen)| if seen { reflection_texture(scene, f, eye, options) } else { None })
        .collect();
    let mut image = Image::new(camera.width, camera.height);
    image.pixels.par_iter_mut().zip(&hits).enumerate().for_each(|(i, (px, hit))| {
        let Some((ray, hit)) = hit else { return };
        let p = ray.at(hit.t);
        let seed = i as u64;
        *px = match (smesh.face_of.get(&hit.prim), scene.material(hit.prim)) {
            (Some(&fi), Material::Mirror { tint }) => match &textures[fi] {
                Some(tex) => tint * tex.sample(smesh.faces[fi].barycentric(p)),
                None => Vec3::ZERO,
            },
            _ => shade_point(scene, &options.shading, hit.prim, p, ray.direction.normalize(), seed),
        };
    });
    let built: Vec<&BeamTexture> = textures.iter().flatten().collect();
    let beams = built.len() as u64;
    let rendered: u64 = built.iter().map(|t| t.texels()).sum();
    let stats = NonlinearStats {
        seconds: start.elapsed().as_secs_f64(),
        degree: match options.degree {
            Degree::S1 => "s1",
            Degree::S3 => "s3",
        }
        .into(),
        beams_per_level: vec![beams],
        triangles_per_beam: built.iter().map(|t| f64::from(t.triangles_after_culling)).sum::<f64>()
            / beams.max(1) as f64,
        overdraw: built.iter().map(|t| t.texels_tested).sum::<u64>() as f64 / rendered.max(1) as f64,
        texels_shaded: built.iter().map(|t| t.hits.iter().flatten().count() as u64).sum(),
        width: camera.width,
        height: camera.height,
    };
    (image, stats)
}

/// The ray-traced ground truth of [`render_nonlinear`]: one ray per pixel centre; on a mirror of
/// the S mesh the ray reflects about the interpolated (Phong) normal, the smooth surface the S mesh
/// stands for; everything else is shaded alike.
#[must_use]
pub fn render_smooth_reference(scene: &Scene, options: &RenderOptions) -> Image {
    let mut camera = scene.camera;
    camera.width = options.width.max(1);
    camera.height = options.height.max(1);
    let smesh = SMesh::mirrors(scene);
    let frame = camera.frame();
    let mut image = Image::new(camera.width, camera.height);
    let w = camera.width as usize;
    let eps = shading_eps(scene);
    image.pixels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, px) in row.iter_mut().enumerate() {
            let ray = camera.ray(&frame, x as f32 + 0.5, y as f32 + 0.5);
            let Some(hit) = scene.wide.closest_hit(ray, f32::INFINITY) else { continue };
            let p = ray.at(hit.t);
            let d = ray.direction.normalize();
            let seed = (y * w + x) as u64;
            *px = match (smesh.face_of.get(&hit.prim), scene.material(hit.prim)) {
                (Some(&fi), Material::Mirror { tint }) => {
                    let f = &smesh.faces[fi];
                    let n = f.normal_at(f.barycentric(p));
                    let side = if n.dot(d) < 0.0 { n } else { -n };
                    tint * trace_radiance(scene, options, Ray::new(p + side * eps, reflect(d, n)), seed)
                }
                _ => shade_point(scene, options, hit.prim, p, d, seed),
            };
        }
    });
    image
}
