//! How a scene asks for the S meshes of its mirror and glass surfaces (000 §7.1): the rendered
//! (fine) triangles themselves, a coarse mesh given beside them, or a simplification of them to a
//! face count or an error. The S mesh itself is built by `beam_render::nonlinear::SMesh::of`.

use crate::mesh::Mesh;
use std::ops::Range;

/// Largest S-mesh face count a simplification may ask for.
pub const MAX_SMESH_FACES: u32 = 1 << 24;

/// A simplification target (meshoptimizer's edge-collapse simplifier, `meshopt::simplify`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Simplify {
    /// About this many S-mesh faces in all, shared among the surfaces in proportion to their
    /// triangles (at least 4 each; a surface already that coarse is kept).
    Faces(u32),
    /// Collapse edges while the surface moves by at most this fraction of its size (0 to 1).
    Error(f32),
}

impl Simplify {
    /// The target checked: 4 to [`MAX_SMESH_FACES`] faces, or an error in `(0, 1]`; `Err` says
    /// what is allowed.
    pub fn checked(self) -> Result<Self, &'static str> {
        match self {
            Self::Faces(n) if (4..=MAX_SMESH_FACES).contains(&n) => Ok(self),
            Self::Faces(_) => Err("a face count from 4 to 16777216"),
            Self::Error(e) if e > 0.0 && e <= 1.0 => Ok(self),
            Self::Error(_) => Err("an error above 0 and at most 1 (a fraction of the surface's size)"),
        }
    }
}

/// Where the S mesh of some specular triangles comes from.
#[derive(Clone, Debug)]
pub enum SMeshSource {
    /// The triangles themselves, with their smooth vertex normals (the default).
    Fine,
    /// A coarse mesh given in scene coordinates (a scene file's `smesh = "coarse.obj"`).
    Given(Mesh),
    /// The triangles simplified.
    Simplified(Simplify),
}

/// The S-mesh sources of a scene's specular triangles: per range of scene triangle indices (a
/// scene file's meshes), the first range holding a triangle decides; the rest follow `rest`.
#[derive(Clone, Debug, Default)]
pub struct SMeshPlan {
    /// Ranges of scene triangles with their sources.
    pub parts: Vec<(Range<u32>, SMeshSource)>,
    /// The specular triangles in no part: simplified to this target, or (`None`) their own S mesh.
    pub rest: Option<Simplify>,
}

impl SMeshPlan {
    /// True when every S mesh is the fine mesh itself (the default).
    #[must_use]
    pub fn is_fine(&self) -> bool {
        self.rest.is_none() && self.parts.iter().all(|(_, s)| matches!(s, SMeshSource::Fine))
    }

    /// The source of scene triangle `prim`.
    #[must_use]
    pub fn source_of(&self, prim: u32) -> Option<&SMeshSource> {
        self.parts.iter().find(|(r, _)| r.contains(&prim)).map(|(_, s)| s)
    }
}
