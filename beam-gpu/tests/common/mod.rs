//! What beam-gpu's integration tests share.

use beam_gpu::Gpu;

/// The adapter, or `None` after printing SKIPPED past the test harness's capture (a failure
/// instead under `BEAM_REQUIRE_GPU=1`, as in CI).
pub(crate) fn adapter() -> Option<Gpu> {
    match Gpu::new() {
        Ok(gpu) => Some(gpu),
        Err(e) => {
            assert!(std::env::var("BEAM_REQUIRE_GPU").as_deref() != Ok("1"), "BEAM_REQUIRE_GPU=1 but {e}");
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "SKIPPED: {e}");
            None
        }
    }
}
