//! The beams the GPU properties compare on: random beams of every kind, and the beams off a scene's
//! S-mesh faces.

use crate::generate::{self, BeamKind, uniform};
use beam_math::glam::Vec3;
use beam_math::nonlinear::BumpBeam;
use beam_render::nonlinear::{Beam, BumpedBeam, Degree, SMesh};
use beam_scene::scene::{self, Bump};

/// Random beams of every kind (diverging, converging, mixed), each as S1, S3 and bump-mapped.
pub(super) fn random_beams(seed: u64, per_kind: usize) -> Vec<Beam> {
    let mut rng = generate::rng(seed);
    let mut beams = Vec::new();
    for kind in BeamKind::ALL {
        for _ in 0..per_kind {
            beams.push(Beam::S1(generate::s1_beam(&mut rng, kind)));
            beams.push(Beam::S3(generate::s3_beam(&mut rng, kind)));
            let delta = uniform(&mut rng, 0.01, 0.15);
            let bump = Bump { delta, wavelength: uniform(&mut rng, 0.2, 2.0) };
            let beam = BumpBeam { beam: generate::s1_beam(&mut rng, kind), delta };
            beams.push(Beam::Bumped(BumpedBeam { beam, bump }));
        }
    }
    beams
}

/// The name of a beam's kind in notes.
pub(super) fn kind(beam: &Beam) -> &'static str {
    match beam {
        Beam::S1(_) => "S1",
        Beam::S3(_) => "S3",
        Beam::Bumped(_) => "bumped",
    }
}

/// The beams of parameterization `degree` off S-mesh faces `faces` of `smesh` lit from `eye`
/// (reflected, and refracted where there is one), each with its face.
pub(super) fn face_beams(
    scene: &scene::Scene,
    smesh: &SMesh,
    (eye, degree): (Vec3, Degree),
    faces: impl Iterator<Item = usize>,
) -> Vec<(Beam, usize)> {
    faces
        .filter_map(|f| {
            let face = &smesh.faces[f];
            let incoming = face.v.map(|v| (v - eye).normalize_or_zero());
            let (reflected, refracted) = beam_render::nonlinear::child_beams(scene, face, incoming, degree)?;
            Some([Some(reflected), refracted.flatten()].into_iter().flatten().map(move |b| (b, f)))
        })
        .flatten()
        .collect()
}

/// The level-1 beams off every third specular S-mesh face of `scene` (the eye's light at its
/// vertices), with their faces' scene triangles.
pub(super) fn level_one_beams(scene: &scene::Scene, degree: Degree) -> Vec<(Beam, u32)> {
    let smesh = SMesh::specular(scene);
    let beams = face_beams(scene, &smesh, (scene.camera.position, degree), (0..smesh.faces.len()).step_by(3));
    beams.into_iter().map(|(b, f)| (b, smesh.faces[f].prim)).collect()
}
