//! Compress the debug sections of the release `beam` binary on Linux (zlib, `SHF_COMPRESSED`).
//!
//! The release profile keeps line tables (`debug = "line-tables-only"`) for backtraces with file
//! and line; uncompressed, they (with the names of every inlined generic function) are 121 MB of
//! the binary's 141 MB. Compressed, the binary is 45 MB, and backtraces still give file and line
//! (std's symbolizer inflates zlib-compressed sections), as do `gdb`, `objdump` and `addr2line`.
//! Only the `beam` binary (not the test binaries), only release-based profiles (dev builds link
//! faster without), only Linux, whose linkers (GNU ld, gold, lld, mold) all take the flag.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let linux = std::env::var("CARGO_CFG_TARGET_OS").is_ok_and(|os| os == "linux");
    let release = std::env::var("PROFILE").is_ok_and(|p| p == "release");
    if linux && release {
        println!("cargo:rustc-link-arg-bins=-Wl,--compress-debug-sections=zlib");
    }
}
