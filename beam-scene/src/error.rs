//! The errors of beam-scene: [`SceneError`] for reading scenes and meshes and writing outputs, and
//! [`FaceError`] for OBJ faces that cannot be triangulated.
//!
//! Each error keeps what its message names (the file, the line, the scene file's element) as
//! fields; its `Display` is the message the `beam` binary prints. Paths of input files are shown
//! clipped ([`shown`]), as a scene file may name a path of thousands of characters.

use crate::mesh::limits::MAX_NONCONVEX_CORNERS;
use crate::scene::names::{BUILTIN, GENERATED, PROCEDURAL};
use crate::text::{QUOTE_CHARS, bytes, clip, shown};
use std::io;
use std::path::PathBuf;

/// An error reading a scene, a mesh or an input file, or writing an output file. Messages name
/// the file, and the line (OBJ, TOML) or the scene file's element (`meshes[2].material`) where
/// there is one.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Reading an input file failed, or a file a scene file names does not exist.
    #[error("{}: {source}", shown(path))]
    Read {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: io::Error,
    },
    /// An input that is not a regular file (a FIFO would block, `/dev/zero` never ends): it is
    /// not read.
    #[error("{}: not a regular file ({kind})", shown(path))]
    NotRegularFile {
        /// The input.
        path: PathBuf,
        /// What it is instead, in words (`a FIFO`, `a device`, `a folder`).
        kind: &'static str,
    },
    /// An input file larger than the limit of its kind
    /// ([`MAX_MESH_BYTES`](crate::read::MAX_MESH_BYTES),
    /// [`MAX_SCENE_BYTES`](crate::read::MAX_SCENE_BYTES)).
    #[error("{}: larger than the {} limit", shown(path), bytes(*limit))]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// The limit, bytes.
        limit: u64,
    },
    /// A folder (a scene file's, the scenes folder or one below it) could not be resolved or read.
    #[error("{}: {source}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// What the system said.
        source: io::Error,
    },
    /// A file name in a scene file that names no file (over 4096 bytes, or with a NUL byte).
    #[error("`{}`: not a file name", clip(&name.escape_debug().to_string(), QUOTE_CHARS))]
    NotAFileName {
        /// The name as the scene file gives it.
        name: String,
    },
    /// A file a scene file names that lies outside the scene file's folder, while outside paths
    /// are not allowed (`--allow-outside-paths`).
    #[error(
        "`{}` {} the scene file's folder {}; pass --allow-outside-paths to allow it",
        clip(&name.escape_debug().to_string(), 200),
        if *resolved { "resolves outside" } else { "is outside" },
        dir.display()
    )]
    OutsideFolder {
        /// The name as the scene file gives it.
        name: String,
        /// The scene file's folder.
        dir: PathBuf,
        /// True when the name stays inside but the file it resolves to (through symbolic links)
        /// does not; false when the name itself leads outside.
        resolved: bool,
    },
    /// A malformed line of an OBJ file or of one of its material libraries (MTL).
    #[error("{}:{line}: {message}", shown(path))]
    Obj {
        /// The OBJ or MTL file.
        path: PathBuf,
        /// The line, from 1 (a statement continued by `\` counts from its first line).
        line: usize,
        /// What is wrong, with the line quoted (clipped) where the file may be quoted.
        message: String,
    },
    /// A face of an OBJ file that cannot be triangulated.
    #[error("{}:{line}: {source}", shown(path))]
    Face {
        /// The OBJ file.
        path: PathBuf,
        /// The face's line, from 1.
        line: usize,
        /// Why it cannot be triangulated.
        source: FaceError,
    },
    /// An OBJ file without a triangle.
    #[error(
        "{}: no triangles{}",
        shown(path),
        if *skipped == 0 { String::new() } else { format!(" ({skipped} line or point elements skipped)") }
    )]
    NoTriangles {
        /// The OBJ file.
        path: PathBuf,
        /// Line and point elements skipped in it.
        skipped: usize,
    },
    /// A scene (a scene file or a bare OBJ file) whose triangles are all degenerate.
    #[error("{}: no valid triangle", path.display())]
    NoValidTriangle {
        /// The scene file or OBJ file.
        path: PathBuf,
    },
    /// A scene named by a path that is neither a `.toml` scene file, a `.gltf`/`.glb` model nor an
    /// `.obj` mesh.
    #[error(
        "{}: expected a built-in scene name ({}, {}), a .toml scene, a .gltf/.glb model or an .obj mesh",
        path.display(),
        BUILTIN.join(", "),
        GENERATED.join(", ")
    )]
    UnknownFileType {
        /// The path.
        path: PathBuf,
    },
    /// An image that cannot be encoded, or an image file (PNG, OpenEXR) that cannot be read: the
    /// codec's message, or a tile placement that does not fit its image.
    #[error("{}{message}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    Image {
        /// The image file, when there is one.
        path: Option<PathBuf>,
        /// What is wrong.
        message: String,
    },
    /// A glTF file that cannot be loaded: malformed JSON or GLB, a buffer, accessor or index out of
    /// range, a non-finite value, a node cycle, a buffer file outside the model's folder.
    #[error("{}{}: {message}", shown(path), element.as_ref().map(|e| format!(": {e}")).unwrap_or_default())]
    Gltf {
        /// The `.gltf` or `.glb` file.
        path: PathBuf,
        /// The element (`mesh 2 primitive 0`, `node 4`, `buffer 1`), or none for the file as a
        /// whole.
        element: Option<String>,
        /// What is wrong with it.
        message: String,
    },
    /// A scene file that cannot be parsed: not UTF-8, nested too deeply, or not valid TOML (or
    /// not a scene).
    #[error("{}{}: {message}", path.display(), at(*line, *column))]
    Toml {
        /// The scene file.
        path: PathBuf,
        /// The line, from 1, where known.
        line: Option<usize>,
        /// The column, from 1, where known.
        column: Option<usize>,
        /// What is wrong, with the text around the column quoted (clipped) where known.
        message: String,
    },
    /// A value of a scene file's element that is invalid: not finite, a negative colour, a
    /// zero-area light, an unusable camera, a material that does not exist.
    #[error("{}: {element}: {message}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// The element (`lights[0]`, `camera`, `meshes[2].material`).
        element: String,
        /// What is wrong with it.
        message: String,
    },
    /// A number of a scene file's element outside its range.
    #[error("{}: {element} must be {expected}", path.display())]
    OutOfRange {
        /// The scene file.
        path: PathBuf,
        /// The element (`materials.glass.ior`).
        element: String,
        /// The range, in words (`a positive number`).
        expected: &'static str,
    },
    /// An error in a file a scene file names, or in resolving its name: a mesh of a TOML scene, a
    /// buffer file of a glTF model.
    #[error("{}: {element}: {source}", path.display())]
    InMesh {
        /// The scene file.
        path: PathBuf,
        /// The element naming the file (`meshes[2]`, `buffer 1`).
        element: String,
        /// The named file's error.
        source: Box<SceneError>,
    },
    /// A built-in scene name that does not exist.
    #[error("unknown built-in scene `{name}` (known: {})", BUILTIN.join(", "))]
    UnknownScene {
        /// The name asked for.
        name: String,
    },
    /// An S-mesh resolution outside 2 to 256.
    #[error("S-mesh resolution {resolution} out of range (2 to 256)")]
    SmeshResolution {
        /// The resolution asked for.
        resolution: u32,
    },
    /// An S-mesh resolution asked of a built-in scene that is not procedural.
    #[error("an S-mesh resolution applies to the built-ins {} only, not `{name}`", PROCEDURAL.join(", "))]
    NotProcedural {
        /// The built-in scene asked for.
        name: String,
    },
    /// An S mesh (`smesh`, `smesh_target`, `smesh_error`) asked of a scene file's mesh whose
    /// material is not a mirror or glass.
    #[error("{}: {element}: S meshes are for mirror and glass meshes, not material `{material}`", path.display())]
    SMeshNotSpecular {
        /// The scene file.
        path: PathBuf,
        /// The element (`meshes[2].smesh`).
        element: String,
        /// The mesh's material, as the scene file names it.
        material: String,
    },
    /// A coarse S mesh (`smesh = "coarse.obj"`) that does not lie over its mesh: its bounding box
    /// reaches farther beyond the mesh's than a quarter of the mesh's size (a missing transform, a
    /// mesh of another object).
    #[error(
        "{}: {element}: the S mesh does not lie over its mesh (its box reaches {distance} beyond the mesh's, more than a quarter of the mesh's size {size})",
        path.display()
    )]
    SMeshFar {
        /// The scene file.
        path: PathBuf,
        /// The element (`meshes[2].smesh`).
        element: String,
        /// How far the S mesh's box reaches beyond the mesh's, scene units.
        distance: f32,
        /// The diagonal of the mesh's box, scene units.
        size: f32,
    },
    /// The shared scenes folder was not found.
    #[error("{}", match beam_scenes {
        Some(dir) => format!("BEAM_SCENES={} is not a folder", dir.display()),
        None => "no scenes: set BEAM_SCENES or place the shared scenes at ../shared/scenes".to_string(),
    })]
    NoScenes {
        /// `$BEAM_SCENES` when it is set (and not a folder); `None` when it is unset and no
        /// `../shared/scenes` exists.
        beam_scenes: Option<PathBuf>,
    },
    /// Writing an output file failed (its folder, its temporary, keeping the old file aside), or
    /// the program is stopping ([`remove_temporaries`](crate::io::remove_temporaries)).
    #[error("{}: {}{source}", path.display(), context.as_ref().map(|c| format!("{c}: ")).unwrap_or_default())]
    Write {
        /// The output file.
        path: PathBuf,
        /// The step that failed, where the message names it (`not writable`, `folder out`).
        context: Option<String>,
        /// What the system said.
        source: io::Error,
    },
    /// An output path that may not be written: it names no file or is named twice, its folder is
    /// not a folder, or the target is not a writable regular file (a symbolic link, a FIFO, a
    /// read-only file).
    #[error("{}: {reason}", path.display())]
    Refused {
        /// The output file.
        path: PathBuf,
        /// Why, in words.
        reason: String,
    },
    /// Renaming an output of a group ([`write_atomic_all`](crate::io::write_atomic_all)) into
    /// place failed; the outputs of the group renamed before it were put back, but `unrestored`.
    #[error("{}: {source}{}", path.display(), rollback(*earlier, unrestored))]
    Rename {
        /// The output whose rename failed.
        path: PathBuf,
        /// What the system said.
        source: io::Error,
        /// How many outputs of the group were renamed before it (and were then put back).
        earlier: usize,
        /// Those of them that could not be put back.
        unrestored: Vec<Unrestored>,
    },
    /// Encoding an image as PNG failed.
    #[error("{}{source}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    Png {
        /// The output file, when writing one.
        path: Option<PathBuf>,
        /// What the encoder said.
        source: image::ImageError,
    },
}

/// An output of a group that was replaced before a later rename failed and that could not be put
/// back ([`SceneError::Rename`]).
#[derive(Debug)]
pub struct Unrestored {
    /// The output.
    pub path: PathBuf,
    /// Why putting it back failed.
    pub source: io::Error,
    /// The temporary file that keeps its old content, where it existed before (left in place).
    pub backup: Option<PathBuf>,
}

/// `:line:column`, `:line` or nothing.
fn at(line: Option<usize>, column: Option<usize>) -> String {
    match (line, column) {
        (Some(l), Some(c)) => format!(":{l}:{c}"),
        (Some(l), None) => format!(":{l}"),
        _ => String::new(),
    }
}

/// What became of the outputs renamed before a failed rename, for [`SceneError::Rename`].
fn rollback(earlier: usize, unrestored: &[Unrestored]) -> String {
    let mut out = String::new();
    for u in unrestored {
        out.push_str(&format!("; and {} was replaced and could not be put back ({})", u.path.display(), u.source));
        if let Some(b) = &u.backup {
            out.push_str(&format!("; its old content is in {}", b.display()));
        }
    }
    if earlier > 0 && unrestored.is_empty() {
        out.push_str("; the outputs written before it were put back as they were");
    }
    out
}

/// Why a face of an OBJ file cannot be triangulated ([`triangulate`](crate::mesh::triangulate)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FaceError {
    /// A non-convex face of more than
    /// [`MAX_NONCONVEX_CORNERS`] corners.
    #[error("a non-convex face of {corners} corners (at most {} are supported)", MAX_NONCONVEX_CORNERS)]
    TooManyCorners {
        /// Its corners.
        corners: usize,
    },
    /// A face whose edges cross (seen along its normal).
    #[error("the face crosses itself (seen along its normal)")]
    CrossesItself,
    /// A face that ear clipping could not cut up: it overlaps itself.
    #[error("the face could not be triangulated (it overlaps itself)")]
    Overlaps,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn p(s: &str) -> PathBuf {
        PathBuf::from(s)
    }

    fn os(what: &str) -> io::Error {
        io::Error::other(what)
    }

    /// Each variant's message is the one the loaders and writers printed when they returned
    /// strings: the `beam` binary's output does not change.
    #[test]
    fn messages_name_the_file_and_line_or_element() {
        let cases: Vec<(SceneError, &str)> = vec![
            (SceneError::TooLarge { path: p("s.toml"), limit: 4 << 20 }, "s.toml: larger than the 4 MiB limit"),
            (
                SceneError::NotRegularFile { path: p("/dev/zero"), kind: "a device" },
                "/dev/zero: not a regular file (a device)",
            ),
            (SceneError::NotAFileName { name: "a\0b".into() }, "`a\\0b`: not a file name"),
            (
                SceneError::OutsideFolder { name: "../x.obj".into(), dir: p("d"), resolved: false },
                "`../x.obj` is outside the scene file's folder d; pass --allow-outside-paths to allow it",
            ),
            (
                SceneError::Face { path: p("m.obj"), line: 6, source: FaceError::CrossesItself },
                "m.obj:6: the face crosses itself (seen along its normal)",
            ),
            (SceneError::NoTriangles { path: p("m.obj"), skipped: 0 }, "m.obj: no triangles"),
            (
                SceneError::NoTriangles { path: p("m.obj"), skipped: 2 },
                "m.obj: no triangles (2 line or point elements skipped)",
            ),
            (
                SceneError::Toml { path: p("s.toml"), line: Some(2), column: Some(5), message: "expected `]`".into() },
                "s.toml:2:5: expected `]`",
            ),
            (
                SceneError::Toml { path: p("s.toml"), line: Some(3), column: None, message: "not UTF-8 text".into() },
                "s.toml:3: not UTF-8 text",
            ),
            (SceneError::Toml { path: p("s.toml"), line: None, column: None, message: "m".into() }, "s.toml: m"),
            (
                SceneError::OutOfRange {
                    path: p("s.toml"),
                    element: "materials.g.ior".into(),
                    expected: "a positive number",
                },
                "s.toml: materials.g.ior must be a positive number",
            ),
            (
                SceneError::InMesh {
                    path: p("s.toml"),
                    element: "meshes[0]".into(),
                    source: Box::new(SceneError::Obj { path: p("m.obj"), line: 2, message: "bad".into() }),
                },
                "s.toml: meshes[0]: m.obj:2: bad",
            ),
            (SceneError::SmeshResolution { resolution: 1 }, "S-mesh resolution 1 out of range (2 to 256)"),
            (SceneError::NoScenes { beam_scenes: Some(p("/no")) }, "BEAM_SCENES=/no is not a folder"),
            (SceneError::Write { path: p("o.png"), context: None, source: os("denied") }, "o.png: denied"),
            (
                SceneError::Write { path: p("o.png"), context: Some("not writable".into()), source: os("denied") },
                "o.png: not writable: denied",
            ),
            (
                SceneError::Rename { path: p("o.png"), source: os("busy"), earlier: 0, unrestored: Vec::new() },
                "o.png: busy",
            ),
            (
                SceneError::Rename { path: p("o.png"), source: os("busy"), earlier: 1, unrestored: Vec::new() },
                "o.png: busy; the outputs written before it were put back as they were",
            ),
            (
                SceneError::Rename {
                    path: p("o.png"),
                    source: os("busy"),
                    earlier: 1,
                    unrestored: vec![Unrestored {
                        path: p("s.json"),
                        source: os("gone"),
                        backup: Some(p(".s.json.tmp")),
                    }],
                },
                "o.png: busy; and s.json was replaced and could not be put back (gone); its old content is in .s.json.tmp",
            ),
        ];
        for (e, message) in cases {
            assert_eq!(e.to_string(), message, "{e:?}");
        }
        let e = SceneError::UnknownScene { name: "nope".into() }.to_string();
        assert!(e.starts_with("unknown built-in scene `nope` (known: cornell, "), "{e}");
        assert!(
            SceneError::UnknownFileType { path: Path::new("a.png").into() }
                .to_string()
                .ends_with("a .toml scene, a .gltf/.glb model or an .obj mesh")
        );
    }
}
