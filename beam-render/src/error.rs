//! The errors of the backends behind the renderer's traits ([`RayQueries`](crate::queries::RayQueries)
//! and those of [`nonlinear`](crate::nonlinear)): [`BackendError`].

use std::fmt;

/// An error of a backend behind the renderer's traits (the GPU's device, its buffers, its
/// limits): the backend's own error, boxed, and the backend's name. Its message is the backend
/// error's own.
#[derive(Debug)]
pub struct BackendError {
    /// The backend (`gpu`).
    pub backend: &'static str,
    /// Its error.
    pub error: Box<dyn std::error::Error + Send + Sync>,
}

impl BackendError {
    /// `error` of `backend`.
    pub fn new(backend: &'static str, error: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> Self {
        Self { backend, error: error.into() }
    }
}

impl fmt::Display for BackendError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.error.fmt(f)
    }
}

/// Transparent: the backend error's own source.
impl std::error::Error for BackendError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.error.source()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_scene::SceneError;
    use std::io;
    use std::path::PathBuf;

    /// A backend's error reads as the backend's own message, and keeps its source.
    #[test]
    fn backend_errors_are_transparent() {
        let e = BackendError::new(
            "gpu",
            SceneError::Write { path: PathBuf::from("o.png"), context: None, source: io::Error::other("denied") },
        );
        assert_eq!(e.to_string(), "o.png: denied");
        assert_eq!(e.backend, "gpu");
        assert_eq!(std::error::Error::source(&e).map(ToString::to_string).as_deref(), Some("denied"));
        assert_eq!(BackendError::new("gpu", "no adapter").to_string(), "no adapter");
    }
}
