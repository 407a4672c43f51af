//! Nonlinear beam tracing (000) on the GPU: the beams' GPU layout, the atlas pipeline of 000 §3 that
//! renders every beam of a tree level at once, the eye's view, the next level's fits, the Whitted
//! rays past the tree, a coarse S mesh's lookups and the final composite, and compute entry
//! points that check the WGSL bounding triangles and rays against beam-math.

mod atlas;
mod beam;
mod check;
mod composite;
mod cull;
mod cut_outs;
mod display;
mod eye;
mod eye_stage;
mod fits;
mod kept;
mod level;
mod lookups;
mod page;
mod page_inputs;
mod prepare;
mod queries;
mod records;
mod renderer;
mod sort;
mod times;
mod whitted;
mod whitted_paths;

pub use beam::{GpuBeam, MAX_CONTROL_POINTS};
pub use check::{CheckCase, GpuBoundingTriangle, LookupFound, NonlinearCheck};
pub use composite::{CompositeParams, GpuComposite, GpuFace, KeptHere, NONE, ShadeRest};
pub use cull::BeamCull;
pub use display::GpuFrame;
pub use eye::{EyeCounts, EyeFaceMap, EyeHit, EyeOut, EyeParams, GpuEye, KeptEyeHits, KeptSpecular};
pub use fits::{FitTable, MIN_FIT_SLOTS, ReadFits, fit_slots};
pub use level::{GpuLevelPoints, HostTexel, KeptLevel, LevelCounts, LevelParams};
pub use lookups::{GpuLookupJob, GpuLookups, LookupBeams};
pub use page::AtlasParams;
pub use records::{CoarseBindings, CompositeRecord, EyeRecords, KeptPoints, LocateTable, RecordCounts};
pub use renderer::GpuBeams;
pub use times::GpuTimes;
pub use whitted::{
    EndWeight, GpuWhitted, RestJob, RestPoints, SpecularPrim, WhittedCounts, WhittedParams, WhittedPath,
};
