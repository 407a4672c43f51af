// A level of the beam tree kept on the GPU (beam_gpu::nonlinear::level): after a page's nearest
// hits, every texel of its regions that hit a triangle on which the tree goes on (LEVEL_CONTINUES:
// a mirror or glass face that spawns the next level's beams) is appended for the host with its
// point and direction, and the host builds the next level and the composite from it (where
// `params.fits`, the fit of the next level's beams is summed here, lib/fit.wgsl, and the host
// reads back only those sums); every other texel that hit becomes a shading
// input where it lies, never read back. Its point is the hit of its texel's ray (`texel_ray` at
// the texel's point of the base, `origin + t·direction`), its direction the ray's unit direction,
// its seed the host's (`face triangle << 32 | texel`, folded to 32 bits as beam_gpu::shade::seed32
// folds it). Points the shading pass shades (diffuse, glossy, emissive) and the others (mirror and
// glass past the tree, for the Whitted rays) are appended to two lists with their texels in the
// level's radiance. Under a coarse S mesh, every texel's depth is written to `depths` too, where
// the lookups of the level above read them, and the texels for the host carry the face their
// point lies nearest. The host zeroes `counts` before a dispatch. CPU twin: the host's texel hits
// (beam_cpu::nonlinear::trace, `Tree::build`) sorted as beam_gpu::nonlinear::sort sorts them.

// #import shared/nonlinear.wgsl
// #import lib/shade_input.wgsl
// #import lib/record.wgsl
// #import lib/region.wgsl
// #import lib/coarse.wgsl
// #import lib/fit.wgsl

// Twin of beam_gpu::nonlinear::LevelParams (32 bytes).
struct LevelParams {
    // The dispatch's first texel among the page's regions.
    first: u32,
    // Texels of the dispatch.
    count: u32,
    // 1 where the texels' words are inverted (nearest hits by compute), else 0.
    inverted: u32,
    // Beams on the page.
    beams: u32,
    // `level_records`: the scene's diagonal, where a texel's ray leaves the scene (lib/reproject.wgsl).
    far: f32,
    // `level_points`: 1 where every texel's depth goes to `depths` (the level's lookups read them
    // there, under a coarse S mesh), else 0.
    depths: u32,
    // Slots of the level's fit table (lib/fit.wgsl), 0 where the host sums the fits: then
    // `level_points` sums them there, and `level_records` counts the texels on curved triangles
    // without child beams at their face, which the host does not see.
    fits: u32,
    // Faces of the S mesh (the fit table's keys).
    faces: u32,
}

// Twin of beam_gpu::nonlinear::HostTexel (48 bytes).
struct HostTexel {
    // The hit point.
    p: vec3<f32>,
    // The scene triangle hit.
    prim: u32,
    // Unit direction of the texel's ray.
    d: vec3<f32>,
    // The bits of the hit's t.
    t: u32,
    // Its beam on the page.
    beam: u32,
    // Its texel in the beam's square (y · size + x).
    texel: u32,
    // Its beam in the level.
    node: u32,
    // The S-mesh face its point lies nearest among its triangle's candidates (a fine triangle's
    // own face), NONE for none (no candidates bound: the host locates it).
    face: u32,
}

// Twin of beam_gpu::nonlinear::LevelCounts (16 bytes).
struct LevelCounts {
    // Points appended for the shading pass.
    direct: atomic<u32>,
    // Points appended for the Whitted rays.
    other: atomic<u32>,
    // Points on curved (smooth-normal) triangles, of either list.
    curved: atomic<u32>,
    // Texels appended for the host.
    host: atomic<u32>,
}

@group(0) @binding(0) var<uniform> params: LevelParams;
@group(0) @binding(1) var<storage, read> beams: array<Beam>;
// Per beam on the page, its first texel in `texels`; then the number of texels of them all.
@group(0) @binding(2) var<storage, read> firsts: array<u32>;
// Per texel of every region, row by row: (scene triangle + 1, bits of t), (0, 0) for a miss; each
// word inverted where `params.inverted` (zeroes still a miss).
@group(0) @binding(3) var<storage, read> texels: array<vec2<u32>>;
// Per beam on the page: its first texel in the level's radiance, its S-mesh face's scene
// triangle, its beam in the level.
@group(0) @binding(4) var<storage, read> placed: array<vec4<u32>>;
// Per scene triangle: LEVEL_PLAIN where the shading pass shades it, | LEVEL_CURVED where its
// normals are interpolated, | LEVEL_CONTINUES where the tree goes on from it.
@group(0) @binding(5) var<storage, read> kinds: array<u32>;
@group(0) @binding(6) var<storage, read_write> direct: array<ShadeInput>;
@group(0) @binding(7) var<storage, read_write> direct_targets: array<u32>;
@group(0) @binding(8) var<storage, read_write> other: array<ShadeInput>;
@group(0) @binding(9) var<storage, read_write> other_targets: array<u32>;
@group(0) @binding(10) var<storage, read_write> counts: LevelCounts;
// Per texel for the host: its hit, point and direction, beam on the page and texel, beam in the
// level.
@group(0) @binding(11) var<storage, read_write> host: array<HostTexel>;
// `level_records`: per scene triangle, its S-mesh face (a fine one: the triangle itself), else NONE.
@group(0) @binding(12) var<storage, read> face_of: array<u32>;
// Per beam of the level: its first texel in the level's radiance, its S-mesh face's triangle.
@group(0) @binding(13) var<storage, read> nodes: array<vec2<u32>>;
// Per beam of the level, its first entry in `child_entries`; then their number.
@group(0) @binding(14) var<storage, read> child_firsts: array<u32>;
// Per beam, ascending by face: (face, reflection beam, refraction beam or NONE, 0).
@group(0) @binding(15) var<storage, read> child_entries: array<vec4<u32>>;
@group(0) @binding(16) var<storage, read_write> records: array<Record>;
@group(0) @binding(17) var<storage, read_write> record_counts: RecordCounts;
// `level_records` under coarse faces (lib/coarse.wgsl): the S mesh's candidates and corners, the
// next level's beams (their rays and regions in `texel_t`), the mirror and glass triangles.
@group(0) @binding(18) var<storage, read> candidates: array<u32>;
@group(0) @binding(19) var<storage, read> corners: array<vec4<f32>>;
@group(0) @binding(20) var<storage, read> child_beams: array<Beam>;
@group(0) @binding(21) var<storage, read> texel_t: array<f32>;
@group(0) @binding(22) var<storage, read> slots: array<u32>;
@group(0) @binding(23) var specular_prims: texture_2d<u32>;
// `level_points` where `params.depths`: per texel of the level (its place in the level's radiance),
// the ray parameter of its nearest hit, −1 where it hits nothing (lib/reproject.wgsl's `texel_t`).
@group(0) @binding(24) var<storage, read_write> depths: array<f32>;
// `level_points` where `params.fits`: the level's fit table (lib/fit.wgsl).
@group(0) @binding(25) var<storage, read_write> fits: array<atomic<u32>>;

// Loops: a binary search over the page's beams, at most 32 halvings (constant bound), and
// texel_ray's sum over the S^3 coefficients.
@compute @workgroup_size(WORKGROUP_SIZE)
fn level_points(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if k >= params.count { return; }
    let i = params.first + k;
    var word = texels[i];
    if params.inverted != 0u && word.x != 0u { word = ~word; }
    if word.x == 0u && params.depths == 0u { return; }
    // The last beam whose first texel is at most i.
    var lo = 0u;
    var hi = params.beams;
    for (var n = 0u; n < 32u && hi - lo > 1u; n++) {
        let mid = (lo + hi) / 2u;
        if firsts[mid] <= i { lo = mid; } else { hi = mid; }
    }
    let b = beams[lo];
    let s = b.region.z;
    let at = region_texel(i - firsts[lo], s);
    let texel = at.y * s + at.x;
    if params.depths != 0u {
        depths[placed[lo].x + texel] = select(-1.0, bitcast<f32>(word.y), word.x != 0u);
    }
    if word.x == 0u { return; }
    let prim = word.x - 1u;
    let kind = kinds[prim];
    let ray = texel_ray(b, texel_barycentric(at.x, at.y, s));
    let p = ray.origin + ray.direction * bitcast<f32>(word.y);
    let d = normalize(ray.direction);
    if (kind & LEVEL_CONTINUES) != 0u {
        let face = nearest_face(prim, p);
        let j = atomicAdd(&counts.host, 1u);
        host[j] = HostTexel(p, prim, d, word.y, lo, texel, placed[lo].z, face);
        if params.fits != 0u && face != NONE {
            fit_sample(placed[lo].z * params.faces + face + 1u, params.fits, face_barycentric(face, p), d);
        }
        return;
    }
    let input = ShadeInput(p, prim, d, texel ^ placed[lo].y);
    let at_level = placed[lo].x + texel;
    if (kind & LEVEL_CURVED) != 0u { atomicAdd(&counts.curved, 1u); }
    if (kind & LEVEL_PLAIN) != 0u {
        let j = atomicAdd(&counts.direct, 1u);
        direct[j] = input;
        direct_targets[j] = at_level;
    } else {
        let j = atomicAdd(&counts.other, 1u);
        other[j] = input;
        other_targets[j] = at_level;
    }
}

// The child beams of S-mesh face `face` for the texels of beam `node` of the level (lib/coarse.wgsl):
// its entry in `child_entries`, (NONE, NONE) for none. Loops: a binary search over the beam's
// entries, at most 32 halvings (constant bound).
fn children_of(node: u32, face: u32) -> vec2<u32> {
    var lo = child_firsts[node];
    var hi = child_firsts[node + 1u];
    for (var n = 0u; n < 32u && lo < hi; n++) {
        let mid = (lo + hi) / 2u;
        let e = child_entries[mid];
        if e.x == face {
            return e.yz;
        }
        if e.x < face { lo = mid + 1u; } else { hi = mid; }
    }
    return vec2<u32>(NONE, NONE);
}

// The composite of every texel handed to the host (`params.count` of them, `host`), once the tree's
// next level is built: on a face with child beams of its beam, a record looking them up at the hit
// point (a fine face: beam_cpu::nonlinear's `Tree::composite`) or where its own scattered rays
// reach (under a coarse face, at the candidate it lies nearest: lib/coarse.wgsl); else a point for
// the Whitted rays, appended to `other` with its texel in the level's radiance. The host zeroes
// `record_counts` before a dispatch. Loops: `children_of`'s and `coarse_composite`'s.
@compute @workgroup_size(WORKGROUP_SIZE)
fn level_records(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if k >= params.count { return; }
    let h = host[k];
    let node = nodes[h.node];
    let at_level = node.x + h.texel;
    var face = face_of[h.prim];
    let coarse = face == NONE;
    if coarse {
        face = h.face;
    }
    var child = vec2<u32>(NONE, NONE);
    if face != NONE {
        child = children_of(h.node, face);
    }
    if child.x != NONE {
        if !coarse {
            let j = atomicAdd(&record_counts.records, 1u);
            records[j] = Record(h.p, at_level, h.d, face, child.x, child.y, 0u, 0u, h.p, 0u);
            return;
        }
        let r = coarse_composite(h.node, h.prim, face, h.p, h.d, params.far);
        if r.found {
            atomicAdd(&record_counts.coarse, 1u);
            let j = atomicAdd(&record_counts.records, 1u);
            records[j] = Record(r.reflected_p, at_level, h.d, r.face, r.children.x, r.children.y, 0u, 0u, r.refracted_p, 0u);
            return;
        }
        atomicAdd(&record_counts.uncovered, 1u);
        if (kinds[h.prim] & LEVEL_CURVED) != 0u {
            atomicAdd(&record_counts.curved, 1u);
        }
    } else if params.fits != 0u && (kinds[h.prim] & LEVEL_CURVED) != 0u {
        atomicAdd(&record_counts.curved, 1u);
    }
    let j = atomicAdd(&record_counts.rest, 1u);
    other[j] = ShadeInput(h.p, h.prim, h.d, h.texel ^ node.y);
    other_targets[j] = at_level;
}
