//! Real models look right: a textured box shows its texture, a vertex-coloured box its colours, and
//! a box with no camera and no light has every face the default camera sees lit. The glTF files
//! are written here (a box of 24 corners, a 2 × 2 PNG), rendered by the default method.

use beam_cpu::render::render;
use beam_math::glam::{Vec2, Vec3};
use beam_render::options::RenderOptions;
use beam_scene::scene::{Environment, Scene, load};
use std::path::Path;

/// The six faces: normal, and the two edges `a`, `b` with `a × b = n`.
const FACES: [[[f32; 3]; 3]; 6] = [
    [[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
    [[-1., 0., 0.], [0., 1., 0.], [0., 0., -1.]],
    [[0., 1., 0.], [0., 0., 1.], [1., 0., 0.]],
    [[0., -1., 0.], [0., 0., -1.], [1., 0., 0.]],
    [[0., 0., 1.], [1., 0., 0.], [0., 1., 0.]],
    [[0., 0., -1.], [-1., 0., 0.], [0., 1., 0.]],
];

/// Linear colours of the faces' vertices (one colour per face).
const FACE_COLOURS: [[f32; 4]; 6] =
    [[1., 0., 0., 1.], [0., 1., 0., 1.], [0., 0., 1., 1.], [1., 1., 0., 1.], [0., 1., 1., 1.], [1., 0., 1., 1.]];

/// The 2 × 2 texture, sRGB: red, green on the top row; blue, white below.
const TEXELS: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];

/// Write a unit box (centred at the origin) as `box.gltf` in `dir`, with texture coordinates
/// spanning each face and, as `extra` says, vertex colours or the 2 × 2 texture.
fn write_box(dir: &Path, extra: &str) -> std::path::PathBuf {
    let (mut pos, mut uv, mut col, mut idx) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (f, [n, a, b]) in FACES.iter().enumerate() {
        let (n, a, b) = (Vec3::from(*n), Vec3::from(*a), Vec3::from(*b));
        let base = (pos.len() / 3) as u16;
        for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            pos.extend((0.5 * (n + s * a + t * b)).to_array());
            uv.extend([(s + 1.0) / 2.0, (1.0 - t) / 2.0]);
            col.extend(FACE_COLOURS[f]);
        }
        idx.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    for bytes in [
        pos.iter().flat_map(|v: &f32| v.to_le_bytes()).collect::<Vec<u8>>(),
        uv.iter().flat_map(|v: &f32| v.to_le_bytes()).collect(),
        col.iter().flat_map(|v: &f32| v.to_le_bytes()).collect(),
        idx.iter().flat_map(|v: &u16| v.to_le_bytes()).collect(),
    ] {
        views.push(format!(r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#, bin.len(), bytes.len()));
        bin.extend(bytes);
    }
    std::fs::write(dir.join("box.bin"), &bin).unwrap();
    let rgb: Vec<u8> = TEXELS.iter().flatten().copied().collect();
    std::fs::write(dir.join("tex.png"), beam_scene::io::encode_png(2, 2, &rgb).unwrap()).unwrap();
    let (attributes, material) = match extra {
        "colours" => (r#""POSITION":0,"TEXCOORD_0":1,"COLOR_0":2"#, r#"{"pbrMetallicRoughness":{"metallicFactor":0}}"#),
        "texture" => (
            r#""POSITION":0,"TEXCOORD_0":1"#,
            r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0}}"#,
        ),
        _ => (r#""POSITION":0"#, r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.8,0.8,1],"metallicFactor":0}}"#),
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "buffers":[{{"uri":"box.bin","byteLength":{}}}],"bufferViews":[{}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":24,"type":"VEC3","min":[-0.5,-0.5,-0.5],"max":[0.5,0.5,0.5]}},
          {{"bufferView":1,"componentType":5126,"count":24,"type":"VEC2"}},
          {{"bufferView":2,"componentType":5126,"count":24,"type":"VEC4"}},
          {{"bufferView":3,"componentType":5123,"count":36,"type":"SCALAR"}}],
        "images":[{{"uri":"tex.png"}}],"samplers":[{{"magFilter":9728,"minFilter":9728}}],
        "textures":[{{"source":0,"sampler":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{{attributes}}},"indices":3,"material":0}}]}}],
        "materials":[{material}]}}"#,
        bin.len(),
        views.join(",")
    );
    let path = dir.join(format!("box-{extra}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

/// Per pixel of a 64 × 64 render of `scene` by the default method: the rendered radiance and
/// the triangle and point its centre's primary ray hits.
fn rendered(scene: &mut Scene) -> Vec<(Vec3, Option<(u32, Vec3)>)> {
    scene.camera.width = 64;
    scene.camera.height = 64;
    let options = RenderOptions::exact(64, 64);
    let (image, _) = render(scene, &options, || {});
    let frame = scene.camera.frame();
    (0..64 * 64)
        .map(|i| {
            let ray = scene.camera.pixel_ray(&frame, i);
            let hit = scene.wide.closest_hit(ray, f32::INFINITY).map(|h| (h.prim, ray.at(h.t)));
            (image.pixels[i], hit)
        })
        .collect()
}

/// The colour's share of each channel (independent of how bright it is lit).
fn chroma(c: Vec3) -> Vec3 {
    c / c.element_sum().max(f32::MIN_POSITIVE)
}

#[test]
fn a_textured_box_shows_its_texture() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = load(write_box(dir.path(), "texture").to_str().unwrap()).unwrap();
    // Under the key light alone (white), whose colour the texture's does not mix with.
    scene.environment = Environment::Black;
    assert_eq!(scene.surfaces.textures.len(), 1);
    // The loader: each quarter of the +z face reads its texel (v down the image).
    let front = (0..scene.triangles.len() as u32).find(|&i| scene.normal(i).z > 0.9).unwrap();
    for (uv, texel) in [(Vec2::new(0.25, 0.25), 0), (Vec2::new(0.75, 0.25), 1), (Vec2::new(0.25, 0.75), 2)] {
        // The +z face spans x, y ∈ [−½, ½] with u = x + ½ and v = ½ − y.
        let p = Vec3::new(uv.x - 0.5, 0.5 - uv.y, 0.5);
        let prim =
            (front..front + 2).find(|&i| scene.triangles[i as usize].barycentric(p).unwrap().min_element() >= 0.0);
        let albedo = scene.albedo_at(prim.unwrap(), p);
        let want = Vec3::from(TEXELS[texel].map(|c| f32::from(c) / 255.0));
        assert!((albedo - want).abs().max_element() < 1e-3, "texel {texel}: {albedo} vs {want}");
    }
    // The render: every pixel on the box has the chroma of the texel under it.
    let mut seen = [false; 4];
    let mut on_box = 0;
    for (radiance, hit) in rendered(&mut scene) {
        let Some((prim, p)) = hit else { continue };
        on_box += 1;
        let albedo = scene.albedo_at(prim, p);
        let texel = TEXELS.iter().position(|t| (Vec3::from(t.map(|c| f32::from(c) / 255.0)) - albedo).length() < 1e-3);
        if let Some(k) = texel {
            seen[k] = true;
        }
        if radiance.element_sum() > 1e-3 {
            let (got, want) = (chroma(radiance), chroma(albedo));
            assert!((got - want).abs().max_element() < 0.02, "pixel at {p}: {radiance} for albedo {albedo}");
        }
    }
    assert!(on_box > 500, "the default camera frames the box ({on_box} pixels)");
    assert_eq!(seen, [true; 4], "all four texels are seen");
}

#[test]
fn a_vertex_coloured_box_shows_its_colours() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = load(write_box(dir.path(), "colours").to_str().unwrap()).unwrap();
    scene.environment = Environment::Black;
    let mut faces = std::collections::BTreeSet::new();
    for (radiance, hit) in rendered(&mut scene) {
        let Some((prim, _)) = hit else { continue };
        let n = scene.normal(prim);
        let f = FACES.iter().position(|f| Vec3::from(f[0]).dot(n) > 0.99).unwrap();
        faces.insert(f);
        let want = chroma(Vec3::from_slice(&FACE_COLOURS[f][..3]));
        assert!((chroma(radiance) - want).abs().max_element() < 0.02, "face {f}: {radiance}");
    }
    assert_eq!(faces.len(), 3, "the default camera sees three faces");
}

#[test]
fn a_box_without_camera_or_light_has_every_visible_face_lit() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = load(write_box(dir.path(), "plain").to_str().unwrap()).unwrap();
    let mut darkest = [f32::INFINITY; 6];
    for (radiance, hit) in rendered(&mut scene) {
        let Some((prim, _)) = hit else { continue };
        let n = scene.normal(prim);
        let f = FACES.iter().position(|f| Vec3::from(f[0]).dot(n) > 0.99).unwrap();
        darkest[f] = darkest[f].min(radiance.min_element());
    }
    let seen: Vec<f32> = darkest.into_iter().filter(|d| d.is_finite()).collect();
    assert_eq!(seen.len(), 3, "three faces seen: {darkest:?}");
    assert_eq!(scene.environment, Environment::neutral_sky(), "a model without lights gets the neutral sky");
    // Lit by the key light: at least a tenth of the radiance of a white face facing it (0.8).
    assert!(seen.iter().all(|&d| d > 0.08 * 0.8), "{darkest:?}");
}
