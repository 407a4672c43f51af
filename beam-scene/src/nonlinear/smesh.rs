//! The S mesh of 000 §7.1: the base triangles of the secondary beams, with smooth vertex normals.

use crate::scene::Scene;
use beam_math::Triangle;
use beam_math::glam::Vec3;
use std::collections::HashMap;

/// One S-mesh triangle: a mirror or glass triangle of the scene with its smooth vertex normals.
#[derive(Clone, Copy, Debug)]
pub struct SFace {
    /// The scene triangle it is.
    pub prim: u32,
    /// Vertices.
    pub v: [Vec3; 3],
    /// Unit vertex normals, on the side of the face's geometric normal.
    pub n: [Vec3; 3],
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

/// The S mesh of every mirror and glass surface of a scene.
#[derive(Clone, Debug, Default)]
pub struct SMesh {
    /// Its triangles.
    pub faces: Vec<SFace>,
    /// Face index of each scene triangle that has one.
    pub face_of: HashMap<u32, usize>,
}

impl SMesh {
    /// The S mesh of the scene's mirror and glass triangles: the triangles themselves (the scene
    /// gives specular surfaces at S-mesh resolution, slivers left out) with the scene's smooth
    /// vertex normals.
    #[must_use]
    pub fn specular(scene: &Scene) -> Self {
        // Slivers (a sphere's pole triangles, narrower than 1e-4 of their longest edge) make no
        // beam worth having; the few pixels on them are traced by rays.
        let sliver = |p: u32| {
            let v = scene.triangles[p as usize].v;
            let longest =
                (v[1] - v[0]).length_squared().max((v[2] - v[1]).length_squared()).max((v[0] - v[2]).length_squared());
            (v[1] - v[0]).cross(v[2] - v[0]).length() < 1e-4 * longest
        };
        let mut prims: Vec<u32> = scene.smooth_normals.keys().copied().filter(|&p| !sliver(p)).collect();
        prims.sort_unstable();
        let faces: Vec<SFace> = prims
            .iter()
            .map(|&p| SFace { prim: p, v: scene.triangles[p as usize].v, n: scene.smooth_normals[&p] })
            .collect();
        let face_of = prims.iter().enumerate().map(|(i, &p)| (p, i)).collect();
        Self { faces, face_of }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_normals_are_radial() {
        let scene = crate::scene::load("mirror-glass").unwrap();
        let s = SMesh::specular(&scene);
        assert!(!s.faces.is_empty());
        // The mirror sphere of the built-in scene: centre (185, 90, 170). Max's weights give a
        // tessellated sphere's exact radial normals.
        let c = Vec3::new(185.0, 90.0, 170.0);
        for f in s.faces.iter().filter(|f| matches!(scene.material(f.prim), crate::scene::Material::Mirror { .. })) {
            for i in 0..3 {
                let radial = (f.v[i] - c).normalize();
                assert!(f.n[i].dot(radial).abs() > 0.9999, "{} {} {}", f.n[i].dot(radial), f.v[i], f.prim);
            }
            // Barycentric coordinates round-trip (slivers at the poles are ill-conditioned).
            if (f.v[1] - f.v[0]).cross(f.v[2] - f.v[0]).length() > 10.0 {
                let w = f.barycentric(0.2 * f.v[0] + 0.3 * f.v[1] + 0.5 * f.v[2]);
                assert!((w - Vec3::new(0.2, 0.3, 0.5)).abs().max_element() < 1e-3, "{w}");
            }
        }
    }
}
