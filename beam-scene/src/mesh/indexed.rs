//! An indexed triangle mesh: the data every mesh reader and builder produces.

use beam_math::Triangle;
use beam_math::glam::Vec3;

/// An indexed triangle mesh.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles as vertex indices.
    pub indices: Vec<[u32; 3]>,
}

impl Mesh {
    /// The triangles, one per index triple (degenerate ones included; the BVH counts and skips them).
    #[must_use]
    pub fn triangles(&self) -> Vec<Triangle> {
        self.indices.iter().map(|t| Triangle { v: t.map(|i| self.positions[i as usize]) }).collect()
    }

    /// Append another mesh.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.indices.extend(other.indices.iter().map(|t| t.map(|i| i + base)));
    }
}
