//! One frame of the nonlinear renderer (000 §7.3): the caustics, the eye's view and the S-mesh
//! faces it sees, the beam tree level by level ([`Tree`]), the radiance flow and the shading, each
//! a stage of the frame's [`StageClock`].

use super::beam_tree::Degree;
use super::caustics::{CausticStats, caustics_by_beams};
use super::composite::composite_levels;
use super::error::NonlinearError;
use super::fit::Fit;
use super::host_shading::{HostShading, shade_points};
use super::radiance::{LevelRadiance, TexelRadiance};
use super::renderer::{BeamRenderer, CoarseByRays, DeviceImage, EyeFaces, FramePixels, TreeShading};
use super::settings::{NonlinearOptions, NonlinearStats};
use super::smesh::SMesh;
use super::stages::StageClock;
use super::texture::ShadePoint;
use super::tree::lookup::Lookups;
use super::tree::trace::{Built, Request};
use super::tree::{Node, Tree, TreeMemos};
use crate::BackendError;
use crate::image::Image;
use crate::irradiance_map::IrradianceMap;
use crate::parallel::par_flatten;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_scene::region::PixelRect;
use beam_scene::scene::{Camera, Scene};
use rayon::prelude::*;
use std::time::Instant;

/// Render `scene` with its mirror and glass surfaces by nonlinear beams (000 §7.3), the eye's view
/// and every level of the beam tree rendered by `renderer` (the CPU's, or a GPU's atlases); the tree
/// logic and the shading are shared; the points `renderer` does not shade are shaded by `host` (beam-cpu's
/// `CpuBeams`). With `options.shading.region`, the eye's rays and the caustics are still
/// the whole frame's (a face's beams are built from every pixel that sees it), but only the beams
/// of faces that the region's pixels see are traced, and only its pixels are shaded.
pub fn render_nonlinear_with(
    scene: &Scene,
    options: &NonlinearOptions,
    renderer: &mut dyn BeamRenderer,
    host: &dyn HostShading,
) -> Result<(Image, NonlinearStats), NonlinearError> {
    match render_nonlinear_frame(scene, options, renderer, host, None)? {
        (FrameImage::Read(image), stats) => Ok((image, stats)),
        (FrameImage::Kept(_), _) => Err(NonlinearError::FrameKept),
    }
}

/// A nonlinear frame's pixels ([`render_nonlinear_frame`]): read back, or left on the renderer's
/// device for display.
#[derive(Debug)]
pub enum FrameImage {
    /// The image, read back.
    Read(Image),
    /// The frame as the renderer kept it on its device ([`FramePixels::Kept`]), handed to the
    /// caller: whoever shows it knows the renderer (beam-gpu's `GpuFrame::from_device`).
    Kept(DeviceImage),
}

impl FrameImage {
    /// The image, where it was read back.
    #[must_use]
    pub fn read(self) -> Option<Image> {
        match self {
            Self::Read(image) => Some(image),
            Self::Kept(_) => None,
        }
    }
}

/// What the nonlinear frames of a scene share while its geometry, materials and lights stay put:
/// its S mesh (000 §7.1, which a coarse one simplifies from the fine mesh: 55 ms on the mirror
/// teapot under 850 faces, more than the rest of the frame's host work on most scenes) and its
/// caustics (000 §9.2, [`caustics_by_beams`]: the irradiance through its mirror and glass surfaces
/// from its lights). Neither depends on the camera or the beam tree, so an interactive renderer
/// makes them once and renders every frame (a camera that moves, a new beam tree) with them
/// ([`render_nonlinear_frame`]). The frames keep their trees' beams here too, each frame's for the
/// next: a beam of the same face and incoming light is made once; so a frame borrows these
/// mutably, one frame at a time.
#[derive(Debug)]
pub struct NonlinearPrecomputed {
    smesh: SMesh,
    map: Option<IrradianceMap>,
    stats: CausticStats,
    /// The scene's triangle count, checked by the frames that share these.
    triangles: usize,
    memos: TreeMemos,
}

impl NonlinearPrecomputed {
    /// The S mesh and the caustics of `scene` as a frame with `options` traces them, the caustics
    /// by `renderer`.
    pub fn new(scene: &Scene, options: &NonlinearOptions, renderer: &dyn BeamRenderer) -> Result<Self, NonlinearError> {
        let caustics = caustics_by_beams(scene, options.degree, options.texels, options.caustic_strata, renderer)?;
        let (map, stats) = caustics.map_or((None, CausticStats::default()), |(m, s)| (Some(m), s));
        Ok(Self { smesh: SMesh::of(scene), map, stats, triangles: scene.triangles.len(), memos: TreeMemos::default() })
    }

    /// What tracing the caustics did.
    #[must_use]
    pub fn stats(&self) -> &CausticStats {
        &self.stats
    }

    /// The S mesh the beams spawn from.
    #[must_use]
    pub fn smesh(&self) -> &SMesh {
        &self.smesh
    }

    /// How many beams the frames that shared these found in the last frame's tree so far, rather
    /// than made.
    #[must_use]
    pub fn beams_reused(&self) -> u64 {
        self.memos.beams.found()
    }
}

/// [`render_nonlinear_with`] with the scene's S mesh and caustics made before
/// ([`NonlinearPrecomputed::new`] on the same scene, with the same options), or made for this
/// frame where `None`: an interactive renderer makes them once while the geometry, the materials
/// and the lights stay put, and renders every frame (a camera that moves, a new beam tree) with
/// them. The frame's pixels are the renderer's where it kept them on its device for display
/// ([`FrameImage::Kept`]). Fails with [`NonlinearError::Precomputed`] where they were made for a
/// scene of another triangle count.
pub fn render_nonlinear_frame(
    scene: &Scene,
    options: &NonlinearOptions,
    renderer: &mut dyn BeamRenderer,
    host: &dyn HostShading,
    precomputed: Option<&mut NonlinearPrecomputed>,
) -> Result<(FrameImage, NonlinearStats), NonlinearError> {
    let start = Instant::now();
    let mut clock = StageClock::start(renderer.waited_seconds());
    let camera = scene.camera.with_size(options.shading.width, options.shading.height);
    // The S mesh, and pass 1 and 2 of the caustics (000 §9.2), before the eye's beam tree that
    // shades with them.
    let mut made;
    let shared = match precomputed {
        Some(given) if given.triangles != scene.triangles.len() => {
            return Err(NonlinearError::Precomputed { made_for: given.triangles, scene: scene.triangles.len() });
        }
        Some(given) => given,
        None => {
            made = NonlinearPrecomputed::new(scene, options, renderer)?;
            &mut made
        }
    };
    clock.lap("S mesh and caustics", renderer.waited_seconds());
    let caustic_stats = shared.stats.clone();
    let tree = Tree {
        scene,
        smesh: &shared.smesh,
        options: *options,
        eye: camera.position,
        caustics: shared.map.as_ref(),
        by_rays: std::sync::atomic::AtomicU64::new(0),
        far: scene.bounds().extent().length(),
    };
    // The eye's view: per pixel centre, the nearest hit; the S-mesh faces it sees are the roots of
    // the beam tree. (A backend that shades the eye's diffuse, glossy and emissive pixels itself may
    // keep those: they see no S-mesh face; one that composites them may keep mirror and glass hits
    // on S-mesh faces, counted per face; what it keeps is the frame's `kept`, which the tree's
    // levels add to and the shading consumes.)
    let (EyeFaces { hits, seen, kept: kept_eye }, mut kept_frame) =
        renderer.eye_faces(scene, tree.smesh, &camera, &options.shading)?;
    clock.lap("eye view", renderer.waited_seconds());
    // Per pixel handed back, the S face it sees: its own triangle's, or on a coarse S mesh the
    // face its point maps to. The eye's beams need only how many pixels see each face (their
    // directions come from the eye itself).
    let locate = |hits: &[(usize, Ray, Hit)]| -> Vec<Option<(usize, Vec3)>> {
        hits.par_iter().map(|&(_, ray, h)| tree.smesh.locate(h.prim, ray.at(h.t))).collect()
    };
    let located = locate(&hits);
    // A face's beams come from every pixel that sees it, but only the faces that pixels of the
    // region see are traced on (with their subtrees): the beams of the others reach no pixel of it.
    let crop = options.shading.region();
    let in_crop = |i: usize| crop.contains((i % camera.width as usize) as u32, (i / camera.width as usize) as u32);
    let mut seen_by = seen.clone();
    for (&(i, ..), l) in hits.iter().zip(&located) {
        if let Some((f, _)) = *l {
            seen_by[f][0] += 1;
            seen_by[f][1] += u32::from(in_crop(i));
        }
    }
    let roots: Vec<Request> = (0..seen_by.len())
        .filter(|&f| seen_by[f][1] > 0)
        .map(|face| Request { parent: None, face, fit: Fit::default(), pixels: seen_by[face][0] as f32 })
        .collect();
    clock.lap("eye view: faces seen", renderer.waited_seconds());
    let Built { roots: children, mut levels, kept, records } =
        tree.build(renderer, &mut shared.memos, roots, &mut kept_frame, &mut clock)?;
    // The eye's view (the region's pixels) is level 0 of the radiance flow, `next` the tree's first.
    fn first(levels: &[Vec<Node>]) -> &[Node] {
        levels.first().map_or(&[], Vec::as_slice)
    }
    let eye_texels =
        |renderer: &dyn BeamRenderer, hits: &[(usize, Ray, Hit)], located: &[Option<(usize, Vec3)>], next: &[Node]| {
            let point = |i: usize, ray: Ray, hit: Hit| ShadePoint {
                prim: hit.prim,
                p: ray.at(hit.t),
                d: ray.direction.normalize(),
                seed: i as u64,
            };
            let to_composite = |k: usize, &(i, ray, hit): &(usize, Ray, Hit)| {
                tree.to_composite(&children, point(i, ray, hit), located[k])
            };
            let points: Option<Vec<_>> = tree
                .looks_up(renderer, next)
                .then(|| hits.par_iter().enumerate().map(|(k, h)| in_crop(h.0).then(|| to_composite(k, h))).collect());
            let looked_up = match &points {
                Some(points) => tree.lookups(renderer, next, points)?,
                None => Lookups::default(),
            };
            Ok::<_, BackendError>(par_flatten(
                hits,
                TexelRadiance::default(),
                |_, &(i, ..)| usize::from(in_crop(i)),
                |k, h, push| {
                    if in_crop(h.0) {
                        let to = points.as_ref().and_then(|p| p[k]).unwrap_or_else(|| to_composite(k, h));
                        let composite = tree.composite(next, &to, looked_up.of(k));
                        push(TexelRadiance { texel: h.0 as u32, point: to.point, composite });
                    }
                },
            ))
        };
    let none = u32::MAX;
    let eye = LevelRadiance {
        regions: Vec::new(),
        len: camera.width as usize * camera.height as usize,
        texels: eye_texels(renderer, &hits, &located, first(&levels))?,
        children: (0..tree.smesh.faces.len())
            .map(|f| {
                children.get(&f).map_or([none; 2], |c| [c.reflected as u32, c.refracted.map_or(none, |r| r as u32)])
            })
            .collect(),
        node_children: Default::default(),
        missed: eye_missed(scene, &camera, crop, &hits),
    };
    let mut flow: Vec<LevelRadiance> =
        std::iter::once(eye).chain(tree.radiance_levels(renderer, &levels, &records)?).collect();
    // Curved (smooth-normal) mirror and glass points traced by rays, looked up in a dense table.
    let mut curved = vec![false; scene.triangles.len()];
    for &prim in scene.smooth_normals.keys() {
        curved[prim as usize] = true;
    }
    let by_rays = |t: &&TexelRadiance| t.composite.is_none() && curved[t.point.prim as usize];
    // The kept pixels of the region on curved fine faces without child beams are traced by rays
    // too (the backend counts those under coarse faces, `TreeShading::Shaded`'s `coarse_by_rays`).
    let kept_by_rays: u64 = (0..seen.len())
        .filter(|&f| !tree.smesh.is_coarse(f))
        .filter(|&f| flow[0].children[f][0] == none && curved[tree.smesh.faces[f].prim as usize])
        .map(|f| u64::from(seen[f][1]))
        .sum();
    // So are the texels on curved faces without child beams of the levels the renderer composites.
    let records_by_rays = levels.iter().zip(&records).filter(|(_, r)| **r).flat_map(|(nodes, _)| nodes);
    let records_by_rays: usize = records_by_rays
        .map(|n| {
            let without = |at: &Option<(usize, Vec3)>| at.is_none_or(|(f, _)| !n.children.contains_key(&f));
            n.hits.iter().zip(&n.located).filter(|(h, at)| curved[h.prim as usize] && without(at)).count()
        })
        .sum();
    let specular_by_rays = flow.iter().map(|l| l.texels.iter().filter(by_rays).count()).sum::<usize>() as u64
        + kept.curved
        + kept_by_rays
        + records_by_rays as u64;
    clock.lap("radiance flow", renderer.waited_seconds());
    let (shading, caustics) = (&options.shading, tree.caustics);
    let (frame, coarse_by_rays) = match renderer.shade_tree(scene, tree.smesh, shading, caustics, &flow, kept_frame)? {
        TreeShading::Shaded { pixels, coarse_by_rays } => (pixels, coarse_by_rays),
        TreeShading::HandedBack(mut kept_frame) => {
            // Shaded here after all: with the eye's pixels the backend kept, and the levels' texels
            // it would have composited.
            if records.contains(&true) {
                tree.kept_level_points(renderer, &kept_frame, &mut levels)?;
                flow.truncate(1);
                flow.extend(tree.radiance_levels(renderer, &levels, &[])?);
            }
            flow[0].texels.extend(renderer.take_kept_eye(&mut kept_frame)?);
            let kept_hits = renderer.take_kept_eye_hits(scene, &mut kept_frame)?;
            flow[0].texels.extend(eye_texels(renderer, &kept_hits, &locate(&kept_hits), first(&levels))?);
            for (level, texels) in renderer.take_kept_levels(&mut kept_frame)? {
                let past = || BackendError::new("renderer", format!("kept texels of level {level}, past the tree"));
                flow.get_mut(level).ok_or_else(past)?.texels.extend(texels);
            }
            let pixels = composite_levels(scene, tree.smesh, &flow, |points| {
                shade_points(renderer, host, scene, shading, caustics, points)
            })?;
            (FramePixels::Read(pixels), CoarseByRays::default())
        }
    };
    clock.lap("shading and composite", renderer.waited_seconds());
    let image = match frame {
        FramePixels::Read(f) => {
            FrameImage::Read(Image { width: crop.width(), height: crop.height(), pixels: crop.cut(f, camera.width) })
        }
        FramePixels::Kept(kept) => FrameImage::Kept(kept),
    };
    let all = || levels.iter().flatten();
    let beams = all().count();
    let texels_tested: u64 = all().map(|n| n.tex.texels_tested).sum();
    let texels_rendered: u64 = all().map(|n| n.tex.texels()).sum();
    let stats = NonlinearStats {
        seconds: start.elapsed().as_secs_f64(),
        degree: match options.degree {
            Degree::S1 => "s1",
            Degree::S3 => "s3",
        }
        .into(),
        beams_per_level: levels.iter().map(|l| l.len() as u64).collect(),
        smesh_faces: tree.smesh.faces.len() as u64,
        coarse_smesh_faces: tree.smesh.coarse_faces() as u64,
        coarse_faces_by_rays: tree.smesh.faces_by_rays() as u64,
        specular_by_rays: specular_by_rays + coarse_by_rays.curved,
        uncovered_by_beams: tree.by_rays.load(std::sync::atomic::Ordering::Relaxed) + coarse_by_rays.uncovered,
        triangles_per_beam: all().map(|n| f64::from(n.tex.triangles_after_culling)).sum::<f64>().max(0.0)
            / beams.max(1) as f64,
        overdraw: texels_tested as f64 / texels_rendered.max(1) as f64,
        texels_rendered,
        texels_shaded: all().map(|n| n.hits.len() as u64).sum::<u64>() + kept.points,
        kept_on_backend: kept_eye + kept.points,
        caustics: caustic_stats,
        stages: {
            clock.lap("image", renderer.waited_seconds());
            clock.stages()
        },
        width: crop.width(),
        height: crop.height(),
    };
    Ok((image, stats))
}

/// The pixels of `crop` that no ray of `hits` (the eye's view handed back) hits, with their rays'
/// directions, where the environment they show is not black. (Pixels a backend kept are among
/// them: the texels it hands back with them later are composited over them.)
fn eye_missed(scene: &Scene, camera: &Camera, crop: PixelRect, hits: &[(usize, Ray, Hit)]) -> Vec<(u32, Vec3)> {
    if scene.environment.is_black() {
        return Vec::new();
    }
    let mut hit = vec![false; camera.width as usize * camera.height as usize];
    for &(i, ..) in hits {
        hit[i] = true;
    }
    let frame = camera.frame();
    crop.frame_indices(camera.width)
        .filter(|&i| !hit[i])
        .map(|i| (i as u32, camera.pixel_ray(&frame, i).direction))
        .collect()
}
