//! Model caches on disk (POD bases, convolution-ROM identifications, kriging trainings): one
//! sealed file format and one atomic writer for all of them.
//!
//! A cache holds what a model built from its inputs; the model's fingerprint says which inputs.
//! The seal adds what a fingerprint cannot: a checksum of the content as written, so a cache
//! whose numbers were edited, truncated or torn is refused here (and rebuilt by the model,
//! which says so) instead of being used or tripping an index deep inside the model. Files are
//! written to a temporary name and renamed, so a reader never sees half a file.

use std::io;
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::value::RawValue;

/// The seal's format name (the first key of every cache file).
pub const SEAL_FORMAT: &str = "hsv-cache-1";

/// FNV-1a, 64 bits, over `bytes`: a stable hash (unlike `DefaultHasher`, the same across builds
/// and platforms) for fingerprints and checksums.
pub fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in bytes {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

/// Why a cache file was not used.
#[derive(Debug, thiserror::Error)]
pub enum CacheError {
    #[error("cache `{}` does not exist", path.display())]
    Missing { path: PathBuf },
    #[error("cannot read cache `{}`: {source}", path.display())]
    Unreadable { path: PathBuf, source: io::Error },
    /// Not a sealed file, or its seal does not match its content.
    #[error("cache `{}` is damaged ({reason})", path.display())]
    Damaged { path: PathBuf, reason: String },
    #[error("cannot write cache `{}`: {source}", path.display())]
    Unwritable { path: PathBuf, source: io::Error },
    #[error("cannot encode cache `{}`: {reason}", path.display())]
    Encoding { path: PathBuf, reason: String },
}

impl CacheError {
    /// The file exists but cannot be trusted (a rebuild should say so; a missing file is the
    /// ordinary first run).
    pub fn is_damaged(&self) -> bool {
        matches!(self, Self::Damaged { .. } | Self::Unreadable { .. })
    }
}

#[derive(Serialize, serde::Deserialize)]
struct Sealed<'a> {
    seal: String,
    /// FNV-1a 64 of `content`'s JSON text, 16 hex digits.
    checksum: String,
    /// Length of `content`'s JSON text, bytes.
    bytes: usize,
    #[serde(borrow)]
    content: &'a RawValue,
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename (creating
/// the folder), so concurrent readers see the old file or the new one, never a torn one.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    static WRITES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let unique = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let mut temporary = path.as_os_str().to_owned();
    temporary.push(format!(".{}-{unique}.tmp", std::process::id()));
    let temporary = PathBuf::from(temporary);
    std::fs::write(&temporary, bytes)?;
    std::fs::rename(&temporary, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&temporary);
    })
}

/// Seals `content` and writes it to `path` atomically.
pub fn save<T: Serialize>(path: &Path, content: &T) -> Result<(), CacheError> {
    let encoding = |reason: String| CacheError::Encoding {
        path: path.to_owned(),
        reason,
    };
    let text = serde_json::to_string(content).map_err(|e| encoding(e.to_string()))?;
    let raw = RawValue::from_string(text).map_err(|e| encoding(e.to_string()))?;
    let sealed = Sealed {
        seal: SEAL_FORMAT.to_owned(),
        checksum: format!("{:016x}", fnv1a(raw.get().bytes())),
        bytes: raw.get().len(),
        content: &raw,
    };
    let file = serde_json::to_string(&sealed).map_err(|e| encoding(e.to_string()))?;
    write_atomic(path, file.as_bytes()).map_err(|source| CacheError::Unwritable {
        path: path.to_owned(),
        source,
    })
}

/// Reads a cache written by [`save`]: the content, if the seal matches it byte for byte and it
/// parses as `T`.
pub fn load<T: DeserializeOwned>(path: &Path) -> Result<T, CacheError> {
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Err(CacheError::Missing {
                path: path.to_owned(),
            });
        }
        Err(source) => {
            return Err(CacheError::Unreadable {
                path: path.to_owned(),
                source,
            });
        }
    };
    let damaged = |reason: String| CacheError::Damaged {
        path: path.to_owned(),
        reason,
    };
    let sealed: Sealed<'_> = serde_json::from_str(&text)
        .map_err(|e| damaged(format!("not a sealed cache file: {e}")))?;
    if sealed.seal != SEAL_FORMAT {
        return Err(damaged(format!(
            "seal `{}`, expected `{SEAL_FORMAT}`",
            sealed.seal
        )));
    }
    let content = sealed.content.get();
    let checksum = format!("{:016x}", fnv1a(content.bytes()));
    if content.len() != sealed.bytes || checksum != sealed.checksum {
        return Err(damaged(format!(
            "content of {} bytes with checksum {checksum}, sealed as {} bytes with {}: edited \
             or torn",
            content.len(),
            sealed.bytes,
            sealed.checksum
        )));
    }
    serde_json::from_str(content).map_err(|e| damaged(format!("content: {e}")))
}

/// Tells the user a damaged cache is being rebuilt (on standard error, where the command line
/// prints its warnings).
pub fn warn_rebuilding(error: &CacheError) {
    eprintln!("warning: {error}: rebuilding it");
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("hsv-cache-{}-{name}.json", std::process::id()))
    }

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        // Fowler, Noll & Vo, the FNV reference test suite: "" and "a" for FNV-1a 64.
        assert_eq!(fnv1a(*b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(*b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(*b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn a_saved_cache_loads_back_bit_for_bit() {
        let path = scratch("roundtrip");
        let content = vec![0.1_f64, 1.0 / 3.0, -2.5e-300, f64::MAX];
        save(&path, &content).unwrap();
        let loaded: Vec<f64> = load(&path).unwrap();
        let _ = std::fs::remove_file(&path);
        assert_eq!(loaded.len(), content.len());
        for (a, c) in content.iter().zip(&loaded) {
            assert_eq!(a.to_bits(), c.to_bits());
        }
    }

    #[test]
    fn an_edited_truncated_or_unsealed_cache_is_damaged_and_a_missing_one_is_not() {
        let path = scratch("edited");
        save(&path, &vec![1.0_f64, 2.0, 3.0]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        for (what, bad) in [
            ("scaled", text.replace("[1.0,2.0,3.0]", "[2.0,4.0,6.0]")),
            ("entry removed", text.replace("[1.0,2.0,3.0]", "[1.0,2.0]")),
            ("truncated", text[..text.len() / 2].to_owned()),
            ("unsealed", "[1.0,2.0,3.0]".to_owned()),
        ] {
            std::fs::write(&path, bad).unwrap();
            let error = load::<Vec<f64>>(&path).unwrap_err();
            assert!(error.is_damaged(), "{what}: {error}");
            assert!(error.to_string().contains("damaged"), "{what}: {error}");
        }
        let _ = std::fs::remove_file(&path);
        let error = load::<Vec<f64>>(&path).unwrap_err();
        assert!(matches!(error, CacheError::Missing { .. }), "{error}");
        assert!(!error.is_damaged());
    }
}
