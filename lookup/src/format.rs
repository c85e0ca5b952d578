//! The binary law file, format version 2 (specified in `schemas/law.md`;
//! version 1, without the discretization-error array, is still read):
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `89 54 43 4C 41 57 0D 0A` (`\x89TCLAW\r\n`) |
//! | 8 | 4 | format version, u32 = 2 |
//! | 12 | 4 | `n_p`, u32 ≥ 1 |
//! | 16 | 4 | `n_h`, u32 ≥ 1 |
//! | 20 | 4 | `n_θ`, u32 ≥ 1 |
//! | 24 | 8 | `M`, metadata length in bytes, u64 |
//! | 32 | M | metadata, UTF-8 `key = value` lines |
//! | 32 + M | 8 (n_p + n_h + n_θ + 3N) | f64 arrays: pressure, flux, contact temperature, jump_mean, jump_std, jump_error (`N = n_p n_h n_θ`; version 1: no jump_error) |
//! | end − 4 | 4 | CRC-32 of all preceding bytes, u32 |
//!
//! All integers and floats little-endian. The reader checks, in order: size
//! limit, magic, version, declared size against the actual size, checksum,
//! metadata, values; it allocates only after the declared size has been checked
//! against the bytes at hand, and it never panics.

use crate::checksum::crc32;
use crate::error::{Axis, Error};
use crate::info;
use crate::law::{Axes, Law};
use std::path::Path;

/// The 8 magic bytes that open a law file.
pub const MAGIC: [u8; 8] = *b"\x89TCLAW\r\n";
/// The format version this crate writes (and the newest it reads).
pub const FORMAT_VERSION: u32 = 2;
/// The oldest format version this crate reads.
pub const OLDEST_READ_VERSION: u32 = 1;
/// Size of the fixed header in bytes.
pub const HEADER_BYTES: usize = 32;
/// Largest law file the reader accepts (1 GiB).
pub const MAX_FILE_BYTES: u64 = 1 << 30;

/// Number of per-entry arrays of a format version (version 1: mean, std;
/// version 2: mean, std, discretization error).
const fn arrays(version: u32) -> u128 {
    if version >= 2 { 3 } else { 2 }
}

/// Bytes of a file with these counts, or `None` on overflow.
fn declared_size(counts: [u64; 3], meta_len: u64, version: u32) -> Option<u128> {
    let n = counts[0] as u128 * counts[1] as u128 * counts[2] as u128;
    let floats = counts.iter().map(|&c| c as u128).sum::<u128>() + arrays(version) * n;
    Some(HEADER_BYTES as u128 + meta_len as u128 + 8 * floats + 4)
}

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    /// Reads `n` f64 (the caller has checked that they are there).
    fn f64s(&mut self, n: usize) -> Vec<f64> {
        let end = self.pos + 8 * n;
        let v = self.bytes[self.pos..end]
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
            .collect();
        self.pos = end;
        v
    }
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    let mut b = [0u8; 4];
    b.copy_from_slice(&bytes[at..at + 4]);
    u32::from_le_bytes(b)
}

impl Law {
    /// Reads a law file (see `schemas/law.md`).
    pub fn open(path: impl AsRef<Path>) -> Result<Law, Error> {
        let path = path.as_ref();
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        let size = std::fs::metadata(path).map_err(io)?.len();
        if size > MAX_FILE_BYTES {
            return Err(Error::TooLarge {
                size,
                limit: MAX_FILE_BYTES,
            });
        }
        let bytes = std::fs::read(path).map_err(io)?;
        Law::from_bytes(&bytes)
    }

    /// Writes the law file (the file's default extrapolation policy, not the
    /// caller's override, is written).
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        std::fs::write(path, self.to_bytes()).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })
    }

    /// The law file as bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let meta = info::to_text(&self.info, self.error_estimated);
        let counts = Axis::ALL.map(|a| self.axes.get(a).len());
        let n = self.jump_mean.len();
        let mut out = Vec::with_capacity(
            HEADER_BYTES + meta.len() + 8 * (counts.iter().sum::<usize>() + 3 * n) + 4,
        );
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        for c in counts {
            // from_grid guarantees each count fits in u32.
            out.extend_from_slice(&(c as u32).to_le_bytes());
        }
        out.extend_from_slice(&(meta.len() as u64).to_le_bytes());
        out.extend_from_slice(meta.as_bytes());
        for axis in Axis::ALL {
            for x in self.axes.get(axis) {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        for x in self
            .jump_mean
            .iter()
            .chain(&self.jump_std)
            .chain(&self.jump_error)
        {
            out.extend_from_slice(&x.to_le_bytes());
        }
        let crc = crc32(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        out
    }

    /// Parses a law file held in memory. Every malformed, truncated, extended,
    /// wrong-version or corrupted input gives an [`Error`] naming the problem.
    pub fn from_bytes(bytes: &[u8]) -> Result<Law, Error> {
        let actual = bytes.len() as u64;
        if actual > MAX_FILE_BYTES {
            return Err(Error::TooLarge {
                size: actual,
                limit: MAX_FILE_BYTES,
            });
        }
        let mut found = [0u8; 8];
        let k = bytes.len().min(8);
        found[..k].copy_from_slice(&bytes[..k]);
        if bytes.len() < 8 || found != MAGIC {
            if bytes.len() < 8 && MAGIC.starts_with(&bytes[..k]) {
                return Err(Error::Truncated {
                    expected: HEADER_BYTES as u64 + 4,
                    actual,
                });
            }
            return Err(Error::BadMagic { found });
        }
        if bytes.len() < 12 {
            return Err(Error::Truncated {
                expected: HEADER_BYTES as u64 + 4,
                actual,
            });
        }
        let version = u32_at(bytes, 8);
        if !(OLDEST_READ_VERSION..=FORMAT_VERSION).contains(&version) {
            return Err(Error::UnsupportedVersion {
                found: version,
                supported: FORMAT_VERSION,
            });
        }
        if bytes.len() < HEADER_BYTES + 4 {
            return Err(Error::Truncated {
                expected: HEADER_BYTES as u64 + 4,
                actual,
            });
        }
        let counts = [u32_at(bytes, 12), u32_at(bytes, 16), u32_at(bytes, 20)].map(u64::from);
        let meta_len = u64::from(u32_at(bytes, 24)) | (u64::from(u32_at(bytes, 28)) << 32);
        let expected = declared_size(counts, meta_len, version).unwrap_or(u128::MAX);
        if expected != actual as u128 {
            let expected = u64::try_from(expected).unwrap_or(u64::MAX);
            return Err(if expected > actual {
                Error::Truncated { expected, actual }
            } else {
                Error::TrailingBytes { expected, actual }
            });
        }
        // From here on every declared length is bounded by the bytes at hand.
        let body = bytes.len() - 4;
        let stored = u32_at(bytes, body);
        let computed = crc32(&bytes[..body]);
        if stored != computed {
            return Err(Error::Checksum { stored, computed });
        }
        for (axis, &c) in Axis::ALL.iter().zip(&counts) {
            if c == 0 {
                return Err(Error::invalid(
                    format!("header n_{}", axis.name()),
                    "0 nodes; expected at least 1",
                ));
            }
        }
        let meta_end = HEADER_BYTES + meta_len as usize;
        let text = std::str::from_utf8(&bytes[HEADER_BYTES..meta_end])
            .map_err(|e| Error::metadata(0, format!("not UTF-8: {e}")))?;
        let (info, error_estimated) = info::from_text(text, version)?;
        let mut r = Reader {
            bytes,
            pos: meta_end,
        };
        let [np, nh, nt] = counts.map(|c| c as usize);
        let axes = Axes {
            pressure: r.f64s(np),
            flux: r.f64s(nh),
            contact_temperature: r.f64s(nt),
        };
        let n = np * nh * nt;
        let jump_mean = r.f64s(n);
        let jump_std = r.f64s(n);
        let jump_error = if version >= 2 {
            r.f64s(n)
        } else {
            vec![0.0; n]
        };
        if !error_estimated && let Some(i) = jump_error.iter().position(|&e| e != 0.0) {
            return Err(Error::invalid(
                format!("jump_error[{i}]"),
                format!(
                    "{}: the metadata says discretization_error = not_estimated (the array must be 0)",
                    jump_error[i]
                ),
            ));
        }
        let error = error_estimated.then_some(jump_error);
        Law::from_grid_with_error(axes, jump_mean, jump_std, error, info)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::info::{LawInfo, Statistic};

    fn small() -> Law {
        let axes = Axes {
            pressure: vec![1e3, 1e4, 1e5],
            flux: vec![1e5, 1e6],
            contact_temperature: vec![300.0],
        };
        let mean: Vec<f64> = (0..6).map(|i| 1.0 + i as f64).collect();
        let std: Vec<f64> = (0..6).map(|i| 0.1 * i as f64).collect();
        let info = LawInfo {
            statistic: Statistic::EnsembleMean { samples: 8 },
            ..LawInfo::default()
        };
        Law::from_grid(axes, mean, std, info).unwrap()
    }

    #[test]
    fn bytes_round_trip_bit_identically() {
        let law = small();
        let bytes = law.to_bytes();
        let back = Law::from_bytes(&bytes).unwrap();
        assert_eq!(back, law);
        assert_eq!(back.to_bytes(), bytes);
    }

    #[test]
    fn header_errors_name_the_problem() {
        let bytes = small().to_bytes();
        assert!(matches!(
            Law::from_bytes(&bytes[..5]),
            Err(Error::Truncated { .. })
        ));
        assert!(matches!(
            Law::from_bytes(b"hello world, no law"),
            Err(Error::BadMagic { .. })
        ));
        let mut v3 = bytes.clone();
        v3[8] = 3;
        assert!(matches!(
            Law::from_bytes(&v3),
            Err(Error::UnsupportedVersion {
                found: 3,
                supported: 2
            })
        ));
        let mut long = bytes.clone();
        long.push(0);
        assert!(matches!(
            Law::from_bytes(&long),
            Err(Error::TrailingBytes { .. })
        ));
        assert!(matches!(
            Law::from_bytes(&bytes[..bytes.len() - 1]),
            Err(Error::Truncated { .. })
        ));
        let mut flipped = bytes.clone();
        let last = flipped.len() - 20;
        flipped[last] ^= 0x10;
        assert!(matches!(
            Law::from_bytes(&flipped),
            Err(Error::Checksum { .. })
        ));
    }

    #[test]
    fn huge_declared_counts_do_not_allocate() {
        let mut bytes = small().to_bytes();
        bytes[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        bytes[16..20].copy_from_slice(&u32::MAX.to_le_bytes());
        bytes[24..32].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(matches!(
            Law::from_bytes(&bytes),
            Err(Error::Truncated { .. })
        ));
    }
}
