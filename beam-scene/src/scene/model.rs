//! The scene itself: triangles with their materials, lights, camera and environment, with the BVHs,
//! normals and bounding spheres built from them once.

use super::camera::Camera;
use super::camera_path::CameraPath;
use super::cut_out_triangles::CutOutTriangles;
use super::environment::Environment;
use super::light::Light;
use super::material::Material;
use super::merge_emitters;
use super::normals;
use super::smesh_plan::SMeshPlan;
use super::surface;
use beam_bvh::{BuildOptions, Bvh8, FlatBvh};
use beam_math::Triangle;
use beam_math::glam::Vec3;

/// Counts from loading a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneStats {
    /// Triangles kept.
    pub triangles: usize,
    /// Degenerate triangles filtered out (zero area, NaN or infinite coordinates).
    pub degenerate: usize,
    /// OBJ line (`l`) and point (`p`) elements, and glTF point and line primitives, skipped: they
    /// have no area to render.
    pub skipped_elements: usize,
    /// glTF directional lights skipped: there is no light at infinity here.
    pub skipped_lights: usize,
    /// Area lights joined into a neighbour: coplanar emitters of equal radiance that share an edge
    /// and together form a parallelogram are one light (the same image, fewer lights to shade).
    pub merged_lights: usize,
}

/// Content of the scene's source that renders do not use, or use only approximately, counted by
/// kind: `beam render` prints one `warning:` line per notice and `--stats` lists them.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Notice {
    /// What was not used and why, plural-neutral (`"directional light(s) skipped: there is no
    /// light at infinity here"`).
    pub what: String,
    /// How many.
    pub count: usize,
}

/// A scene ready to render: triangles (degenerate ones removed) with a material each, lights, a
/// camera, and the BVH over the triangles.
pub struct Scene {
    /// Name (built-in name or file path).
    pub name: String,
    /// Triangles.
    pub triangles: Vec<Triangle>,
    /// Material index of each triangle.
    pub material_of: Vec<u32>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Camera (at frame 0 of [`Self::camera_path`] when there is one).
    pub camera: Camera,
    /// The animated camera of a scene file's `[[camera.keys]]`; `None`: a still camera.
    pub camera_path: Option<CameraPath>,
    /// What rays that leave the scene see, and the light it sends in ([`Environment::Black`] from
    /// [`Scene::new`]).
    pub environment: Environment,
    /// Load counts.
    pub stats: SceneStats,
    /// What of the source is not used, by kind ([`Scene::notice`]).
    pub notices: Vec<Notice>,
    /// Texture coordinates, vertex colours, textures and cut-outs ([`Scene::albedo_at`],
    /// [`Scene::emission_at`], [`Scene::closest_hit`]); empty for constant materials. Its cut-outs
    /// are taken when the scene is assembled.
    pub surfaces: surface::Surfaces,
    /// Binary BVH (generic traversal for beams).
    pub bvh: FlatBvh,
    /// 8-wide BVH for single rays (AVX2 or AVX-512 kernels chosen at run time; about twice the
    /// 4-wide layout's rays per second on the bench's shadow rays) and for the nonlinear beams'
    /// bounding-cone culling (eight boxes at a time).
    pub wide: Bvh8,
    /// Smooth unit vertex normals of each mirror and glass triangle (the curved surface its mesh
    /// approximates), hashed by `FxHasher` (one multiplication): they are looked up once per point
    /// a specular surface scatters ([`Scene::shading_normal`]), and triangle indices come from the
    /// scene, not from an adversary.
    pub smooth_normals: rustc_hash::FxHashMap<u32, [Vec3; 3]>,
    /// Where the S meshes of the specular surfaces come from (000 §7.1); by default the specular
    /// triangles themselves.
    pub smesh: SMeshPlan,
    /// Per triangle, the bounding sphere [`Scene::bounding_sphere`] returns (made once: beams'
    /// bounding-cone culling asks for it per beam and candidate triangle).
    spheres: Vec<(Vec3, f32)>,
    /// The triangles whose material in [`Self::surfaces`] is a cut-out, when the scene was
    /// assembled ([`Scene::cut_out_triangles`]).
    pub(super) cut_outs: Option<CutOutTriangles>,
}

impl Scene {
    /// Assemble a scene: filter degenerate triangles (counted) and build the BVHs.
    #[must_use]
    pub fn new(
        name: String,
        triangles: Vec<(Triangle, u32)>,
        materials: Vec<Material>,
        lights: Vec<Light>,
        camera: Camera,
    ) -> Self {
        Self::with_surfaces(name, triangles, materials, lights, camera, surface::Surfaces::default())
    }

    /// [`Scene::new`] with the textures and per-corner attributes `surfaces` of the triangles (in
    /// the order of `triangles`, filtered with them).
    #[must_use]
    pub fn with_surfaces(
        name: String,
        triangles: Vec<(Triangle, u32)>,
        materials: Vec<Material>,
        lights: Vec<Light>,
        camera: Camera,
        mut surfaces: surface::Surfaces,
    ) -> Self {
        let total = triangles.len();
        let (lights, merged_lights) = merge_emitters::merge_emitters(lights);
        if !surfaces.is_plain() || !surfaces.normals.is_empty() {
            surfaces.retain(&triangles.iter().map(|(t, _)| t.is_valid()).collect::<Vec<_>>());
        }
        let (triangles, material_of): (Vec<Triangle>, Vec<u32>) =
            triangles.into_iter().filter(|(t, _)| t.is_valid()).unzip();
        let stats = SceneStats {
            triangles: triangles.len(),
            degenerate: total - triangles.len(),
            skipped_elements: 0,
            skipped_lights: 0,
            merged_lights,
        };
        let bvh = FlatBvh::build(&triangles, &BuildOptions::sah());
        let wide = Bvh8::build(&triangles, &BuildOptions::sah());
        let smooth_normals = normals::specular_normals(&triangles, &material_of, &materials);
        let spheres = triangles.iter().map(bounding_sphere).collect();
        let cut_outs = if surfaces.has_cut_outs() {
            CutOutTriangles::of(&triangles, |i| surfaces.cut_out(material_of[i]).is_some())
        } else {
            None
        };
        Self {
            name,
            triangles,
            material_of,
            materials,
            lights,
            camera,
            camera_path: None,
            environment: Environment::Black,
            stats,
            notices: Vec::new(),
            surfaces,
            bvh,
            wide,
            smooth_normals,
            smesh: SMeshPlan::default(),
            spheres,
            cut_outs,
        }
    }

    /// Record that `count` of the content `what` is not used (nothing for a count of zero); a kind
    /// noticed before adds to its count.
    pub fn notice(&mut self, what: impl Into<String>, count: usize) {
        if count == 0 {
            return;
        }
        let what = what.into();
        match self.notices.iter_mut().find(|n| n.what == what) {
            Some(n) => n.count += count,
            None => self.notices.push(Notice { what, count }),
        }
    }

    /// The bounding sphere of triangle `i` (centre, radius): about its centroid, through its
    /// farthest corner.
    #[must_use]
    pub fn bounding_sphere(&self, i: u32) -> (Vec3, f32) {
        self.spheres[i as usize]
    }

    /// The camera at frame `frame` of [`Self::camera_path`]; a still camera has frame 0 only. `None`
    /// past the last frame. Between two keys the position and target are interpolated, so the
    /// camera may stand on its target there: check [`Camera::has_view`] before rendering.
    #[must_use]
    pub fn camera_at(&self, frame: u32) -> Option<Camera> {
        match &self.camera_path {
            Some(path) => path.camera_at(&self.camera, frame),
            None => (frame == 0).then_some(self.camera),
        }
    }

    /// Material of triangle `i`.
    #[must_use]
    pub fn material(&self, i: u32) -> Material {
        self.materials[self.material_of[i as usize] as usize]
    }

    /// Bounding box of the scene's triangles (the unit cube for an empty scene).
    #[must_use]
    pub fn bounds(&self) -> beam_math::Aabb {
        self.bvh.nodes.first().map_or(beam_math::Aabb::new(Vec3::ZERO, Vec3::ONE), |n| n.bounds())
    }

    /// Diffuse albedo of triangle `i` at its point `p`: its material's ([`Material::albedo`]) times
    /// its base-colour texture and vertex colours there.
    #[must_use]
    pub fn albedo_at(&self, i: u32, p: Vec3) -> Vec3 {
        let albedo = self.material(i).albedo();
        if self.surfaces.is_plain() || albedo == Vec3::ZERO {
            return albedo;
        }
        let w = self.triangles[i as usize].barycentric(p).unwrap_or(Vec3::splat(1.0 / 3.0));
        albedo * self.surfaces.base_factor(i, self.material_of[i as usize], w)
    }

    /// Radiance emitted by triangle `i` at its point `p` (zero unless it is emissive): its
    /// material's times its emissive texture there.
    #[must_use]
    pub fn emission_at(&self, i: u32, p: Vec3) -> Vec3 {
        let Material::Emissive { radiance } = self.material(i) else {
            return Vec3::ZERO;
        };
        if self.surfaces.is_plain() {
            return radiance;
        }
        let w = self.triangles[i as usize].barycentric(p).unwrap_or(Vec3::splat(1.0 / 3.0));
        radiance * self.surfaces.emissive_factor(i, self.material_of[i as usize], w)
    }

    /// Geometric unit normal of triangle `i`.
    #[must_use]
    pub fn normal(&self, i: u32) -> Vec3 {
        self.triangles[i as usize].scaled_normal().normalize_or_zero()
    }

    /// Shading normal of diffuse or glossy triangle `i` at its point `p` by its normal texture, else
    /// by its corners' normals ([`Surfaces::smooth_normal`](surface::Surfaces::smooth_normal)), on
    /// the side of `facing` (its geometric unit normal, turned to the viewer): the normal they give
    /// on the front, reversed on the back (glTF's double-sided rule); `facing` itself without them.
    #[must_use]
    pub fn mapped_normal(&self, i: u32, p: Vec3, facing: Vec3) -> Vec3 {
        let material = self.material_of[i as usize];
        let mapped = self.surfaces.maps.get(material as usize).is_some_and(|m| m.normal.is_some());
        if !mapped && self.surfaces.normals.is_empty() {
            return facing;
        }
        let tri = &self.triangles[i as usize];
        let front = self.normal(i);
        let w = tri.barycentric(p).unwrap_or(Vec3::splat(1.0 / 3.0));
        let bent = if mapped {
            self.surfaces.mapped_normal(i, material, &tri.v, front, w)
        } else {
            self.surfaces.smooth_normal(i, front, w)
        };
        match bent {
            Some(n) if front.dot(facing) < 0.0 => -n,
            Some(n) => n,
            None => facing,
        }
    }

    /// Shading normal of triangle `i` at its point `p`: the Phong interpolation of its smooth vertex
    /// normals (mirror and glass), else the geometric normal; on the geometric normal's side.
    #[must_use]
    pub fn shading_normal(&self, i: u32, p: Vec3) -> Vec3 {
        self.smooth_normals
            .get(&i)
            .zip(self.triangles[i as usize].barycentric(p))
            .and_then(|(n, w)| (w.x * n[0] + w.y * n[1] + w.z * n[2]).try_normalize())
            .unwrap_or_else(|| self.normal(i))
    }
}

/// The bounding sphere of `tri` about its centroid, through its farthest corner (one square root:
/// the largest of the distances is the root of the largest square).
fn bounding_sphere(tri: &Triangle) -> (Vec3, f32) {
    let centre = (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0;
    (centre, tri.v.iter().fold(0.0f32, |m, v| m.max(v.distance_squared(centre))).sqrt())
}
