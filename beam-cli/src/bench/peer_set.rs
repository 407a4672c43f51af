//! The peers of this build: every peer library compiled in (none without the `peers` feature).

use super::tracer::Tracer;

/// The peers available in this build (none without the `peers` feature).
pub(super) fn peers(triangles: &[beam_math::Triangle]) -> Result<Vec<Box<dyn Tracer>>, String> {
    #[cfg(feature = "peers")]
    return super::peers::all(triangles);
    #[cfg(not(feature = "peers"))]
    {
        let _ = triangles;
        Ok(Vec::new())
    }
}

/// One more build of the peer named `name` over `triangles`, in milliseconds: `None` for a peer
/// whose build cannot be repeated alone (the BVH bench times Embree's in alternation with ours).
pub(super) fn peer_build_ms(name: &str, triangles: &[beam_math::Triangle]) -> Option<f64> {
    #[cfg(feature = "peers")]
    return super::peers::build_ms(name, triangles);
    #[cfg(not(feature = "peers"))]
    {
        let _ = (name, triangles);
        None
    }
}
