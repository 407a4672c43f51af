//! The MTL parser: the materials of an OBJ file's `mtllib` libraries, as far as they change a
//! picture here: the diffuse colour `Kd` and its texture `map_Kd`, the emission `Ke`, the specular
//! colour `Ks` and its Phong exponent `Ns`, and the bump or normal map (`bump`, `map_Bump`,
//! `norm`) with its `-bm` multiplier; the other texture maps (`map_Ks`, `disp`, …) and dissolve
//! (`d`, `Tr`) are counted, not read, and the rest (`Ka`, `Ni`, `illum`, …) is ignored.
//! Every error names `file:line`.

use crate::error::SceneError;
use crate::read::quote;
use beam_math::glam::Vec3;
use std::path::Path;

/// The diffuse colour of a material without `Kd` (a bare OBJ file's grey).
pub const DEFAULT_KD: f32 = 0.7;

/// One material of an MTL file (`newmtl`).
#[derive(Clone, Debug, PartialEq)]
pub struct MtlMaterial {
    /// Its name (the rest of the `newmtl` statement).
    pub name: String,
    /// Diffuse colour (`Kd`; [`DEFAULT_KD`] grey without one).
    pub kd: Vec3,
    /// Specular colour (`Ks`).
    pub ks: Vec3,
    /// Phong exponent of the specular lobe (`Ns`).
    pub ns: f32,
    /// Emitted radiance (`Ke`).
    pub ke: Vec3,
    /// The diffuse colour's texture (`map_Kd`): its file name as written (the statement's last
    /// word) and whether options (`-s`, `-o`, …) came before it, which are not applied.
    pub map_kd: Option<(String, bool)>,
    /// The alpha map (`map_d`), as `map_kd`.
    pub map_d: Option<(String, bool)>,
    /// The bump or normal map (`bump`, `map_bump`, `map_Bump`, `norm`; a `norm` wins over a bump,
    /// which is then counted in `maps`).
    pub bump: Option<MtlBump>,
    /// The other texture-map statements (`map_Ks`, `disp`, `decal`, `refl`, …).
    pub maps: usize,
    /// Whether it is partly transparent (`d` below 1 or `Tr` above 0).
    pub dissolves: bool,
}

/// A material's bump map (`bump`, `map_bump`, `map_Bump`: heights, or a normal map as Blender
/// writes them) or normal map (`norm`).
#[derive(Clone, Debug, PartialEq)]
pub struct MtlBump {
    /// The image's file name as written (the statement's last word).
    pub file: String,
    /// Whether the statement was `norm` (a tangent-space normal map).
    pub normal: bool,
    /// The `-bm` multiplier (1 without one).
    pub scale: f32,
    /// Whether other options (`-s`, `-o`, …) came before the file name; they are not applied.
    pub options: bool,
}

impl MtlMaterial {
    fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            kd: Vec3::splat(DEFAULT_KD),
            ks: Vec3::ZERO,
            ns: 0.0,
            ke: Vec3::ZERO,
            map_kd: None,
            map_d: None,
            bump: None,
            maps: 0,
            dissolves: false,
        }
    }
}

/// The materials of the MTL text `data` (from the file `path`, which errors name), in file order.
/// `quote_lines`: whether errors may quote the offending line.
pub fn parse_mtl(path: &Path, data: &[u8], quote_lines: bool) -> Result<Vec<MtlMaterial>, SceneError> {
    let text = String::from_utf8_lossy(data);
    let mut materials: Vec<MtlMaterial> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let fail = |what: String| {
            let quoted = if quote_lines { format!(": `{}`", quote(line)) } else { String::new() };
            Err(SceneError::Obj { path: path.to_path_buf(), line: n + 1, message: format!("{what}{quoted}") })
        };
        let data = line.split_once('#').map_or(line, |(d, _)| d).trim();
        let mut tokens = data.split_whitespace();
        let Some(keyword) = tokens.next() else { continue };
        if keyword == "newmtl" {
            let name = data["newmtl".len()..].trim();
            if name.is_empty() {
                return fail("`newmtl` needs a name".into());
            }
            materials.push(MtlMaterial::new(name));
            continue;
        }
        let is_map = keyword.starts_with("map_") || matches!(keyword, "bump" | "disp" | "decal" | "refl" | "norm");
        if !(is_map || matches!(keyword, "Kd" | "Ks" | "Ke" | "Ns" | "d" | "Tr")) {
            continue;
        }
        let Some(m) = materials.last_mut() else {
            return fail(format!("`{keyword}` before any `newmtl`"));
        };
        if matches!(keyword, "map_Kd" | "map_d") {
            let words: Vec<&str> = tokens.collect();
            let Some(file) = words.last() else { return fail(format!("`{keyword}` needs a file name")) };
            let map = Some((file.to_string(), words.len() > 1));
            if keyword == "map_Kd" {
                m.map_kd = map
            } else {
                m.map_d = map
            }
            continue;
        }
        if matches!(keyword, "bump" | "map_bump" | "map_Bump" | "norm") {
            let words: Vec<&str> = tokens.collect();
            let Some((file, options)) = words.split_last() else {
                return fail(format!("`{keyword}` needs a file name"));
            };
            if *file == "-bm" {
                return fail("`-bm` takes a finite number before the file name".into());
            }
            let mut bump = MtlBump { file: file.to_string(), normal: keyword == "norm", scale: 1.0, options: false };
            let mut i = 0;
            while i < options.len() {
                if options[i] == "-bm" {
                    match options.get(i + 1).map(|v| v.parse::<f32>()) {
                        Some(Ok(x)) if x.is_finite() => bump.scale = x,
                        _ => return fail("`-bm` takes a finite number before the file name".into()),
                    }
                    i += 2;
                } else {
                    bump.options = true;
                    i += 1;
                }
            }
            match &m.bump {
                // A normal map wins over heights; the map not used is counted.
                Some(b) if b.normal && !bump.normal => m.maps += 1,
                Some(_) => {
                    m.maps += 1;
                    m.bump = Some(bump);
                }
                None => m.bump = Some(bump),
            }
            continue;
        }
        if is_map {
            m.maps += 1;
            continue;
        }
        let mut values = Vec::new();
        for t in tokens {
            match t.parse::<f32>() {
                Ok(x) if x.is_finite() && x >= 0.0 => values.push(x),
                Ok(_) => return fail(format!("`{keyword}` values must be finite and at least 0")),
                // `Kd spectral file` and `Kd xyz x y z` name other colour spaces.
                Err(_) => {
                    return fail(format!("`{keyword}` takes numbers (spectral and CIE XYZ colours are not read)"));
                }
            }
        }
        let colour = |values: &[f32]| match *values {
            [g] => Some(Vec3::splat(g)),
            [r, g, b] => Some(Vec3::new(r, g, b)),
            _ => None,
        };
        let scalar = |values: &[f32]| match *values {
            [x] => Some(x),
            _ => None,
        };
        match keyword {
            "Kd" | "Ks" | "Ke" => {
                let Some(c) = colour(&values) else {
                    return fail(format!("`{keyword}` takes one grey value or r g b, not {} numbers", values.len()));
                };
                match keyword {
                    "Kd" => m.kd = c,
                    "Ks" => m.ks = c,
                    _ => m.ke = c,
                }
            }
            _ => {
                let Some(x) = scalar(&values) else {
                    return fail(format!("`{keyword}` takes one number, not {}", values.len()));
                };
                match keyword {
                    "Ns" => m.ns = x,
                    "d" => m.dissolves |= x < 1.0,
                    _ => m.dissolves |= x > 0.0,
                }
            }
        }
    }
    Ok(materials)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<MtlMaterial>, String> {
        parse_mtl(Path::new("m.mtl"), text.as_bytes(), true).map_err(|e| e.to_string())
    }

    #[test]
    fn reads_colours_emission_and_counts_maps() {
        let m = parse(
            "# a library\nnewmtl red wall\n  Kd 0.63 0.065 0.05 # red\n  Ka 1 1 1\n  illum 2\n\
             newmtl light\nKe 17 12 4\nKd 0.78\nmap_Kd -s 2 2 1 light.png\nbump -bm 0.5 b.png\nd 0.5\n\
             newmtl box\nKd 0 0 0\nKs 0.7 0.7 0.7\nNs 200\n",
        )
        .unwrap();
        assert_eq!(m.len(), 3);
        assert_eq!(m[0].name, "red wall");
        assert_eq!(m[0].kd, Vec3::new(0.63, 0.065, 0.05));
        assert_eq!((m[0].ke, m[0].maps, m[0].dissolves), (Vec3::ZERO, 0, false));
        assert_eq!((m[1].ke, m[1].kd), (Vec3::new(17.0, 12.0, 4.0), Vec3::splat(0.78)));
        assert_eq!((m[1].maps, m[1].dissolves), (0, true));
        let bump = MtlBump { file: "b.png".into(), normal: false, scale: 0.5, options: false };
        assert_eq!(m[1].bump, Some(bump));
        assert_eq!(m[1].map_kd, Some(("light.png".to_string(), true)));
        assert_eq!(m[0].map_kd, None);
        assert_eq!((m[2].kd, m[2].ks, m[2].ns), (Vec3::ZERO, Vec3::splat(0.7), 200.0));
        let bare = parse("newmtl plain\n").unwrap();
        assert_eq!(bare[0].kd, Vec3::splat(DEFAULT_KD));
    }

    #[test]
    fn a_normal_map_wins_over_heights() {
        let m = parse("newmtl a\nnorm -s 2 2 1 n.png\nmap_Bump -bm 2 h.png\nmap_Ks k.png\n").unwrap();
        let norm = MtlBump { file: "n.png".into(), normal: true, scale: 1.0, options: true };
        assert_eq!((m[0].bump.as_ref(), m[0].maps), (Some(&norm), 2));
        let m = parse("newmtl a\nbump h.png\nnorm n.png\n").unwrap();
        assert!(m[0].bump.as_ref().is_some_and(|b| b.normal && b.file == "n.png"));
        assert_eq!(m[0].maps, 1);
    }

    #[test]
    fn errors_name_the_file_and_line() {
        for (text, line, what) in [
            ("newmtl a\nKd 1 x 1\n", 2, "takes numbers"),
            ("newmtl a\n\nKe 1 -1 1\n", 3, "at least 0"),
            ("newmtl a\nKd 1 1\n", 2, "one grey value or r g b"),
            ("Kd 1 1 1\n", 1, "before any `newmtl`"),
            ("newmtl\n", 1, "needs a name"),
            ("newmtl a\nNs 1 2\n", 2, "one number"),
            ("newmtl a\nKd spectral r.spd\n", 2, "spectral"),
            ("newmtl a\nKd inf 1 1\n", 2, "finite"),
            ("newmtl a\nmap_Kd\n", 2, "needs a file name"),
            ("newmtl a\nbump\n", 2, "needs a file name"),
            ("newmtl a\nmap_Bump -bm x b.png\n", 2, "`-bm` takes a finite number"),
            ("newmtl a\nbump -bm\n", 2, "`-bm` takes a finite number"),
        ] {
            let e = parse(text).unwrap_err();
            assert!(e.starts_with(&format!("m.mtl:{line}: ")) && e.contains(what), "{text:?}: {e}");
        }
    }
}
