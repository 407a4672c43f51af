//! Properties of the beam-math core, each checked against an independent computation.

mod collide;
mod glossy;
mod heuristics;
mod nonlinear;
mod polybeam;
mod roots;

use crate::property::{Backend, Property};

const MATH: &[Backend] = &[Backend::Math];

/// The math properties.
#[must_use]
pub fn properties() -> Vec<Property> {
    vec![
        Property {
            name: "slab_vs_brute_force",
            cites: "004 App. A.1",
            backends: MATH,
            body: collide::slab_vs_brute_force,
        },
        Property {
            name: "watertight_ray_triangle",
            cites: "004 App. A.3",
            backends: MATH,
            body: collide::watertight_ray_triangle,
        },
        Property { name: "sat_vs_sampling", cites: "004 App. A.5", backends: MATH, body: collide::sat_vs_sampling },
        Property {
            name: "clipping_area_vs_monte_carlo",
            cites: "004 App. A.9-A.10",
            backends: MATH,
            body: collide::clipping_area_vs_monte_carlo,
        },
        Property {
            name: "cone_sphere_vs_sampling",
            cites: "000 App. A",
            backends: MATH,
            body: collide::cone_sphere_vs_sampling,
        },
        Property { name: "roots_vs_polynomial", cites: "roots", backends: MATH, body: roots::roots_vs_polynomial },
        Property {
            name: "projection_inverts_intersection",
            cites: "000 §5",
            backends: MATH,
            body: nonlinear::projection_inverts_intersection,
        },
        Property {
            name: "threshold_plane_unique_projection",
            cites: "000 §5, App. B.2",
            backends: MATH,
            body: nonlinear::threshold_plane_unique_projection,
        },
        Property {
            name: "bounding_triangle_s1",
            cites: "000 Alg. 3",
            backends: MATH,
            body: nonlinear::bounding_triangle_s1,
        },
        Property {
            name: "bounding_triangle_s3",
            cites: "000 Alg. 4",
            backends: MATH,
            body: nonlinear::bounding_triangle_s3,
        },
        Property {
            name: "bounding_triangle_bump",
            cites: "000 §6.3 eq. 5",
            backends: MATH,
            body: nonlinear::bounding_triangle_bump,
        },
        Property {
            name: "bounding_cone_contains_beam",
            cites: "000 App. A, B.7",
            backends: MATH,
            body: nonlinear::bounding_cone_contains_beam,
        },
        Property {
            name: "polybeam_split_is_exact",
            cites: "001 §3.2",
            backends: MATH,
            body: polybeam::polybeam_split_is_exact,
        },
        Property {
            name: "gaussian_volume_vs_integration",
            cites: "002 §4.2",
            backends: MATH,
            body: glossy::gaussian_volume_vs_integration,
        },
        Property {
            name: "gaussian_volume_continuous",
            cites: "002 §4.2 Figs. 11-12",
            backends: MATH,
            body: glossy::gaussian_volume_continuous,
        },
        Property {
            name: "glossy_irradiance_vs_integration",
            cites: "002 §4.2 eq. 3",
            backends: MATH,
            body: glossy::glossy_irradiance_vs_integration,
        },
        Property {
            name: "flux_triangle_vs_rays",
            cites: "002 §3.1",
            backends: MATH,
            body: glossy::flux_triangle_vs_rays,
        },
        Property {
            name: "projected_area_vs_sampling",
            cites: "004 §1, App. A.10",
            backends: MATH,
            body: heuristics::projected_area_vs_sampling,
        },
    ]
}
