//! The names of the scenes beam builds without a scene file: the built-ins and the suite's generated
//! cases. The builders ([`super::builtin`], [`super::suite`]) and the errors that list the known
//! names ([`crate::error`]) both use them.

/// Names of the built-in scenes; the first is the default of `beam render`.
pub const BUILTIN: [&str; 17] = [
    "cornell",
    "mirror-glass",
    "cornell-point",
    "mirror-glass-coarse",
    "facing-mirrors",
    "facing-mirrors-coarse",
    "glass-lens",
    "glass-lens-coarse",
    "mirror-teapot",
    "mirror-teapot-coarse",
    "wavy-lake",
    "wavy-lake-coarse",
    "bumpy-mirror",
    "cardioid-ring",
    "pool-caustics",
    "stained-glass",
    "foliage",
];

/// The procedural built-ins whose specular surfaces [`super::builtin_with_smesh`] can tessellate.
pub const PROCEDURAL: [&str; 4] = ["facing-mirrors", "glass-lens", "mirror-teapot", "wavy-lake"];

/// The cases built without files, which [`super::builtin`] also knows by these names.
pub const GENERATED: [&str; 5] = ["spheres", "spheres-36", "spheres-256", "plant", "ground"];
