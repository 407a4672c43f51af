//! What a surface is made of: [`Material`], and the procedural [`Bump`] map of a mirror.

use beam_math::Triangle;
use beam_math::glam::Vec3;

/// A procedural bump map on a mirror (000 §6.3): reflected rays are tilted by at most `delta`
/// radians, towards the tangential part of the ripple field
/// `B(p) = (sin 2π(y+z)/λ, sin 2π(z+x)/λ, sin 2π(x+y)/λ)/√3` of wavelength `λ = wavelength`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bump {
    /// Largest tilt δ of a reflected ray, radians.
    pub delta: f32,
    /// Wavelength λ of the ripples, scene units.
    pub wavelength: f32,
}

impl Bump {
    /// No bumps.
    pub const NONE: Self = Self { delta: 0.0, wavelength: 1.0 };

    /// The tilt at point `p` of triangle `tri` in the frame `(u, n × u)` that
    /// [`beam_math::nonlinear::perturb`] takes: `u` along the triangle's first edge, `n` the unit
    /// normal on the side the rays leave (so the tilt is the same world vector, the tangential part
    /// of `B(p)`, on either side); length ≤ 1.
    #[must_use]
    pub fn tilt(self, tri: &Triangle, n: Vec3, p: Vec3) -> beam_math::glam::Vec2 {
        let k = std::f32::consts::TAU / self.wavelength.max(f32::MIN_POSITIVE);
        let b = Vec3::new((k * (p.y + p.z)).sin(), (k * (p.z + p.x)).sin(), (k * (p.x + p.y)).sin()) / 3f32.sqrt();
        let u = (tri.v[1] - tri.v[0]).normalize_or_zero();
        beam_math::glam::Vec2::new(b.dot(u), b.dot(n.cross(u)))
    }
}

/// A surface material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    /// Lambertian with linear RGB albedo.
    Diffuse {
        /// Albedo.
        albedo: Vec3,
    },
    /// Perfect mirror with a linear RGB tint, optionally bump-mapped.
    Mirror {
        /// Reflectance.
        tint: Vec3,
        /// Bump map ([`Bump::NONE`] for a smooth mirror).
        bump: Bump,
    },
    /// Smooth dielectric with an index of refraction.
    Glass {
        /// Index of refraction.
        ior: f32,
    },
    /// Glossy micro-facet surface (Gaussian facet distribution of variance `variance`).
    Glossy {
        /// Albedo.
        albedo: Vec3,
        /// Micro-facet variance (radians²).
        variance: f32,
    },
    /// A thin pane of tinted glass (stained glass): light passes straight through its two parallel
    /// faces, tinted, spread by its micro-facets' roughness (the Gaussian of 002 §4.2, standard
    /// deviation `sigma` radians) where the glossy light volumes trace it; eye rays pass straight.
    ThinGlass {
        /// Transmittance.
        tint: Vec3,
        /// Micro-facet roughness: standard deviation of the scatter angle (radians).
        sigma: f32,
    },
    /// An emitter's surface, seen directly.
    Emissive {
        /// Emitted radiance.
        radiance: Vec3,
    },
}

impl Material {
    /// The diffuse albedo used for direct lighting (zero for specular materials).
    #[must_use]
    pub fn albedo(&self) -> Vec3 {
        match *self {
            Material::Diffuse { albedo } | Material::Glossy { albedo, .. } => albedo,
            _ => Vec3::ZERO,
        }
    }
}
