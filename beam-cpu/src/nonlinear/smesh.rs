//! The S mesh of 000 §7.1: the base triangles of the secondary beams, with smooth vertex normals.

use crate::scene::{Material, Scene};
use beam_math::glam::Vec3;
use std::collections::HashMap;

/// One S-mesh triangle: a mirror triangle of the scene with its vertex normals.
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
        [0, 1, 2].map(|i| crate::render::reflect((self.v[i] - eye).normalize_or_zero(), self.n[i]))
    }

    /// Barycentric coordinates of point `p` (projected onto the face's plane).
    #[must_use]
    pub fn barycentric(&self, p: Vec3) -> Vec3 {
        let (e1, e2, q) = (self.v[1] - self.v[0], self.v[2] - self.v[0], p - self.v[0]);
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (q1, q2) = (q.dot(e1), q.dot(e2));
        let det = d11 * d22 - d12 * d12;
        let u = (d22 * q1 - d12 * q2) / det;
        let v = (d11 * q2 - d12 * q1) / det;
        Vec3::new(1.0 - u - v, u, v)
    }
}

/// The S mesh of every mirror in a scene.
#[derive(Clone, Debug, Default)]
pub struct SMesh {
    /// Its triangles.
    pub faces: Vec<SFace>,
    /// Face index of each scene triangle that has one.
    pub face_of: HashMap<u32, usize>,
}

impl SMesh {
    /// The S mesh of the scene's mirror triangles: the triangles themselves (the scene gives the
    /// mirror at S-mesh resolution), with vertex normals averaged, weighted by area, over the mirror
    /// triangles sharing a position (welded to 1e-5 of the scene's size) whose normals lie within 60°
    /// (so that creases stay sharp).
    #[must_use]
    pub fn mirrors(scene: &Scene) -> Self {
        let prims: Vec<u32> = (0..scene.triangles.len() as u32)
            .filter(|&p| matches!(scene.material(p), Material::Mirror { .. }))
            .collect();
        let extent = scene.bounds().extent().max_element();
        let tol = 1e-5 * extent.max(f32::MIN_POSITIVE);
        let key = |p: Vec3| ((p.x / tol).round() as i64, (p.y / tol).round() as i64, (p.z / tol).round() as i64);
        let mut at: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
        for &p in &prims {
            for v in scene.triangles[p as usize].v {
                at.entry(key(v)).or_default().push(p);
            }
        }
        let mut faces = Vec::with_capacity(prims.len());
        let mut face_of = HashMap::new();
        for &p in &prims {
            let tri = scene.triangles[p as usize];
            let own = tri.scaled_normal().normalize_or_zero();
            let n = tri.v.map(|v| {
                let sum: Vec3 = at[&key(v)]
                    .iter()
                    .map(|&q| scene.triangles[q as usize].scaled_normal())
                    .filter(|m| m.normalize_or_zero().dot(own) > 0.5)
                    .sum();
                sum.try_normalize().unwrap_or(own)
            });
            face_of.insert(p, faces.len());
            faces.push(SFace { prim: p, v: tri.v, n });
        }
        Self { faces, face_of }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_normals_are_radial() {
        let scene = crate::scene::load("mirror-glass").unwrap();
        let s = SMesh::mirrors(&scene);
        assert!(!s.faces.is_empty());
        // The mirror sphere of the built-in scene: centre (185, 90, 170). Averaged normals of a
        // tessellated sphere point nearly radially (within 18°; least near the poles).
        let c = Vec3::new(185.0, 90.0, 170.0);
        for f in &s.faces {
            for i in 0..3 {
                let radial = (f.v[i] - c).normalize();
                if radial.y.abs() > 0.9 {
                    continue; // the poles, where slivers meet
                }
                assert!(f.n[i].dot(radial).abs() > 0.95, "{}", f.n[i].dot(radial));
            }
            // Barycentric coordinates round-trip (slivers at the poles are ill-conditioned).
            if (f.v[1] - f.v[0]).cross(f.v[2] - f.v[0]).length() > 10.0 {
                let w = f.barycentric(0.2 * f.v[0] + 0.3 * f.v[1] + 0.5 * f.v[2]);
                assert!((w - Vec3::new(0.2, 0.3, 0.5)).abs().max_element() < 1e-3, "{w}");
            }
        }
    }
}
