//! The render methods `--method` names.

/// What `--method` names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Beam,
    Ray,
    Nonlinear,
    NonlinearReference,
    Glossy,
    GlossyReference,
}

impl Kind {
    const ALL: [(&'static str, Kind); 6] = [
        ("beam", Kind::Beam),
        ("ray", Kind::Ray),
        ("nonlinear", Kind::Nonlinear),
        ("nonlinear-reference", Kind::NonlinearReference),
        ("glossy", Kind::Glossy),
        ("glossy-reference", Kind::GlossyReference),
    ];

    /// The method `--method s` names, or why none.
    pub(crate) fn parse(s: &str) -> Result<Self, String> {
        Self::ALL
            .iter()
            .find(|(n, _)| *n == s)
            .map(|&(_, k)| k)
            .ok_or_else(|| format!("unknown method `{s}` (expected {})", Self::ALL.map(|(n, _)| n).join(", ")))
    }

    /// The `--method` name.
    pub(crate) fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, k)| *k == self).map_or("?", |(n, _)| n)
    }
}
