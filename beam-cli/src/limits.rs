//! Memory: what a render or a comparison will need, estimated before it starts, and the limit it
//! must fit in: `$BEAM_MAX_MEMORY` (bytes, or with a K, M, G or T suffix, powers of 1024), else half
//! of the memory available now (`MemAvailable` of /proc/meminfo on Linux; no limit elsewhere).

/// Estimates above this are printed before the work starts.
pub(crate) const REPORT_ABOVE: u64 = 1 << 30;

/// The limit in bytes and where it comes from, or `None` where none is known.
pub(crate) fn limit() -> Result<Option<(u64, String)>, String> {
    if let Some(v) = std::env::var_os("BEAM_MAX_MEMORY") {
        let s = v.to_string_lossy();
        let bytes = parse_size(&s).ok_or_else(|| {
            format!("BEAM_MAX_MEMORY={s:?}: expected a size in bytes, optionally with a K, M, G or T suffix")
        })?;
        return Ok(Some((bytes, "BEAM_MAX_MEMORY".into())));
    }
    Ok(mem_available().map(|a| (a / 2, format!("half of the {} available", human(a)))))
}

/// `MemAvailable` in bytes, on Linux.
fn mem_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// `123`, `512M`, `8G`, `1.5G`, `2TiB`: bytes, powers of 1024.
fn parse_size(s: &str) -> Option<u64> {
    let s = s.trim();
    let unit_at = s.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(s.len());
    let (num, unit) = s.split_at(unit_at);
    let scale: u64 = match unit.to_ascii_uppercase().as_str() {
        "" | "B" => 1,
        "K" | "KB" | "KIB" => 1 << 10,
        "M" | "MB" | "MIB" => 1 << 20,
        "G" | "GB" | "GIB" => 1 << 30,
        "T" | "TB" | "TIB" => 1 << 40,
        _ => return None,
    };
    let x: f64 = num.trim().parse().ok()?;
    let bytes = x * scale as f64;
    (x.is_finite() && x >= 0.0 && bytes < u64::MAX as f64).then_some(bytes as u64)
}

/// `1.5 GiB`.
pub(crate) fn human(bytes: u64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut x = bytes as f64;
    let mut i = 0;
    while x >= 1024.0 && i + 1 < units.len() {
        x /= 1024.0;
        i += 1;
    }
    if i == 0 { format!("{bytes} B") } else { format!("{x:.1} {}", units[i]) }
}

/// Refuse `need` bytes (for `what`) above the limit; print it when large. `quiet` leaves out the print.
pub(crate) fn admit(what: &str, need: u64, quiet: bool) -> Result<(), String> {
    let limit = limit()?;
    if let Some((max, source)) = &limit {
        if need > *max {
            return Err(format!(
                "{what} needs about {} of memory, over the limit of {} ({source}); use a smaller size, or set \
                 BEAM_MAX_MEMORY to raise the limit",
                human(need),
                human(*max)
            ));
        }
    }
    if need > REPORT_ABOVE && !quiet {
        match &limit {
            Some((max, source)) => {
                eprintln!("{what}: about {} of memory (limit {}, {source})", human(need), human(*max))
            }
            None => eprintln!("{what}: about {} of memory", human(need)),
        }
    }
    Ok(())
}

/// Saturating sum of products, for estimates that must not wrap.
pub(crate) fn bytes(terms: &[(u64, u64)]) -> u64 {
    terms.iter().fold(0u64, |acc, &(n, each)| acc.saturating_add(n.saturating_mul(each)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(parse_size("123"), Some(123));
        assert_eq!(parse_size("2K"), Some(2048));
        assert_eq!(parse_size("1.5g"), Some(3 << 29));
        assert_eq!(parse_size("8GiB"), Some(8 << 30));
        for bad in ["", "x", "-1G", "nan", "1Q", "1e400"] {
            assert_eq!(parse_size(bad), None, "{bad}");
        }
        assert_eq!(human(512), "512 B");
        assert_eq!(human(3 << 29), "1.5 GiB");
        assert_eq!(bytes(&[(u64::MAX, 2), (1, 1)]), u64::MAX);
    }
}
