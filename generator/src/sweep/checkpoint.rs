//! The checkpoint of a running sweep, `<output>.checkpoint` beside the
//! output: JSON lines, a header and then one line per finished piece of a
//! path (all its pressures, or one pressure without continuation), appended
//! and flushed to disk as each task finishes. A killed run loses only the
//! tasks in flight; `tcgen sweep --resume` reads the finished ones back
//! (floating-point values as their IEEE-754 bit patterns, so a resumed table
//! is bit-identical) and drops a torn last line.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use crate::io::table::{PointRecord, PointStatus, PointValues, SampleSurfaces};
use crate::sweep::Shard;
use crate::sweep::path::PathPiece;
use crate::{Error, Result};

const FORMAT: &str = "tcgen-checkpoint";
const VERSION: u32 = 1;

/// The checkpoint path of an output file: `<output>.checkpoint`.
pub fn checkpoint_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".checkpoint");
    PathBuf::from(s)
}

/// What a checkpoint belongs to.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Header {
    format: String,
    version: u32,
    /// SHA-256 of the resolved configuration.
    pub config_sha256: String,
    /// `[index, count]` of the shard.
    pub shard: [usize; 2],
    /// Grid shape `[n_p, n_h, n_θ, n_s]`.
    pub shape: [usize; 4],
}

impl Header {
    /// The header of a run.
    pub fn new(config_sha256: &str, shard: Shard, shape: [usize; 4]) -> Self {
        Header {
            format: FORMAT.into(),
            version: VERSION,
            config_sha256: config_sha256.into(),
            shard: [shard.index, shard.count],
            shape,
        }
    }
}

#[derive(Serialize, Deserialize)]
struct PointLine {
    /// Status code.
    s: i8,
    /// Reason.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    r: String,
    /// Bits of jump, conductance, contact fraction, mean gap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    v: Option<[u64; 4]>,
    /// Self-consistency and Newton iterations.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    i: Option<[u32; 2]>,
    /// Bits of the jump's error estimate.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    e: Option<u64>,
    /// Whether the estimate met the target.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    m: Option<bool>,
    /// Unknowns.
    #[serde(default)]
    d: u32,
}

#[derive(Serialize, Deserialize)]
struct PathLine {
    path: usize,
    /// Index of the first pressure of the piece.
    #[serde(default)]
    from: usize,
    points: Vec<PointLine>,
    surfaces: Option<[u64; 4]>,
    setup: f64,
    solve: f64,
}

fn to_line(k: usize, o: &PathPiece) -> PathLine {
    PathLine {
        path: k,
        from: o.from,
        points: o
            .points
            .iter()
            .map(|p| PointLine {
                s: p.status as i8,
                r: p.reason.clone(),
                v: p.values.map(|v| {
                    [v.jump, v.conductance, v.contact_fraction, v.mean_gap].map(f64::to_bits)
                }),
                i: p.values
                    .map(|v| [v.self_consistency_iterations, v.newton_iterations]),
                e: p.values.and_then(|v| v.jump_error.map(f64::to_bits)),
                m: p.values.and_then(|v| v.error_target_met),
                d: p.values.map_or(0, |v| v.dofs),
            })
            .collect(),
        surfaces: o.surfaces.map(|s| {
            [
                s.upper_rms,
                s.lower_rms,
                s.upper_fit_error,
                s.lower_fit_error,
            ]
            .map(f64::to_bits)
        }),
        setup: o.setup_seconds,
        solve: o.solve_seconds,
    }
}

fn from_line(l: PathLine) -> Option<(usize, PathPiece)> {
    let mut points = Vec::with_capacity(l.points.len());
    for p in l.points {
        let status = PointStatus::from_code(p.s)?;
        let values = match (status, p.v, p.i) {
            (PointStatus::Converged, Some(v), Some(i)) => {
                let v = v.map(f64::from_bits);
                Some(PointValues {
                    jump: v[0],
                    conductance: v[1],
                    contact_fraction: v[2],
                    mean_gap: v[3],
                    self_consistency_iterations: i[0],
                    newton_iterations: i[1],
                    jump_error: p.e.map(f64::from_bits),
                    error_target_met: p.m,
                    dofs: p.d,
                })
            }
            (PointStatus::Converged, _, _) => return None,
            _ => None,
        };
        points.push(PointRecord {
            status,
            reason: p.r,
            values,
        });
    }
    let surfaces = l.surfaces.map(|s| {
        let s = s.map(f64::from_bits);
        SampleSurfaces {
            upper_rms: s[0],
            lower_rms: s[1],
            upper_fit_error: s[2],
            lower_fit_error: s[3],
        }
    });
    Some((
        l.path,
        PathPiece {
            from: l.from,
            points,
            surfaces,
            setup_seconds: l.setup,
            solve_seconds: l.solve,
        },
    ))
}

/// An open checkpoint, appended to by the worker threads.
pub struct Checkpoint {
    path: PathBuf,
    file: Mutex<File>,
}

fn io_err(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::Io {
        path: path.display().to_string(),
        source: e,
    }
}

impl Checkpoint {
    /// Starts a new checkpoint at `path` (replacing nothing: the caller checks).
    pub fn create(path: &Path, header: &Header) -> Result<Self> {
        let mut f = File::create(path).map_err(io_err(path))?;
        let line = serde_json::to_string(header).expect("serializable");
        writeln!(f, "{line}").map_err(io_err(path))?;
        f.sync_data().map_err(io_err(path))?;
        Ok(Checkpoint {
            path: path.to_path_buf(),
            file: Mutex::new(f),
        })
    }

    /// Opens an existing checkpoint for `--resume`: checks that it belongs to
    /// `header`, returns the finished paths, and drops a torn last line.
    pub fn resume(path: &Path, header: &Header) -> Result<(Self, Vec<(usize, PathPiece)>)> {
        let text = std::fs::read(path).map_err(io_err(path))?;
        let complete = text.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let body = String::from_utf8_lossy(&text[..complete]);
        let mut lines = body.lines();
        let bad = |what: String| Error::Config(format!("{}: {what}", path.display()));
        let first = lines
            .next()
            .ok_or_else(|| bad("empty checkpoint (delete it to start afresh)".into()))?;
        let found: Header =
            serde_json::from_str(first).map_err(|e| bad(format!("not a tcgen checkpoint: {e}")))?;
        if found.format != FORMAT || found.version != VERSION {
            return Err(bad(format!(
                "checkpoint format {} v{}; this tcgen writes {FORMAT} v{VERSION}",
                found.format, found.version
            )));
        }
        if found.config_sha256 != header.config_sha256 {
            return Err(bad(format!(
                "the checkpoint belongs to another configuration (sha256 {} ≠ {}): delete it or restore the configuration",
                found.config_sha256, header.config_sha256
            )));
        }
        if found.shard != header.shard || found.shape != header.shape {
            return Err(bad(format!(
                "the checkpoint is of shard {:?} and grid {:?}, this run is shard {:?} and grid {:?}",
                found.shard, found.shape, header.shard, header.shape
            )));
        }
        let mut done = Vec::new();
        for (n, line) in lines.enumerate() {
            let parsed = serde_json::from_str::<PathLine>(line)
                .ok()
                .and_then(from_line)
                .filter(|(_, o)| o.from + o.points.len() <= header.shape[0]);
            match parsed {
                Some(p) => done.push(p),
                None => {
                    return Err(bad(format!(
                        "line {} is not a finished path; delete the checkpoint to start afresh",
                        n + 2
                    )));
                }
            }
        }
        let f = OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(io_err(path))?;
        f.set_len(complete as u64).map_err(io_err(path))?;
        let mut f = f;
        use std::io::Seek;
        f.seek(std::io::SeekFrom::End(0)).map_err(io_err(path))?;
        Ok((
            Checkpoint {
                path: path.to_path_buf(),
                file: Mutex::new(f),
            },
            done,
        ))
    }

    /// Appends a finished path and flushes it to disk.
    pub fn append(&self, k: usize, outcome: &PathPiece) -> Result<()> {
        let line = serde_json::to_string(&to_line(k, outcome)).expect("serializable");
        let mut f = self.file.lock().unwrap_or_else(|e| e.into_inner());
        f.write_all(format!("{line}\n").as_bytes())
            .and_then(|_| f.sync_data())
            .map_err(io_err(&self.path))
    }

    /// Removes the checkpoint (after the table is written).
    pub fn remove(self) -> Result<()> {
        drop(self.file);
        std::fs::remove_file(&self.path).map_err(io_err(&self.path))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(j: f64) -> PathPiece {
        PathPiece {
            from: 0,
            points: vec![
                PointRecord::converged(PointValues {
                    jump: j,
                    conductance: 1.0 / 3.0,
                    contact_fraction: 0.1,
                    mean_gap: 1e-7,
                    self_consistency_iterations: 4,
                    newton_iterations: 22,
                    jump_error: Some(0.01 * j),
                    error_target_met: Some(j > 1.0),
                    dofs: 1234,
                }),
                PointRecord::failed("diverged \"x\"\nline"),
            ],
            surfaces: Some(SampleSurfaces {
                upper_rms: 0.1 + 0.2,
                lower_rms: 0.0,
                upper_fit_error: 1e-300,
                lower_fit_error: 0.0,
            }),
            setup_seconds: 1.0,
            solve_seconds: 2.0,
        }
    }

    #[test]
    fn resume_reads_finished_paths_bit_for_bit_and_drops_a_torn_line() {
        let dir = std::env::temp_dir().join(format!("tcgen-ckpt-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.h5.checkpoint");
        let h = Header::new("abc", Shard::ALL, [2, 1, 1, 3]);
        let c = Checkpoint::create(&p, &h).unwrap();
        c.append(0, &outcome(std::f64::consts::PI)).unwrap();
        c.append(2, &outcome(1e-17)).unwrap();
        drop(c);
        // A torn line, as a kill in the middle of a write leaves.
        let mut f = OpenOptions::new().append(true).open(&p).unwrap();
        f.write_all(b"{\"path\":1,\"poi").unwrap();
        drop(f);
        let (c, done) = Checkpoint::resume(&p, &h).unwrap();
        assert_eq!(done.len(), 2);
        assert_eq!(done[0], (0, outcome(std::f64::consts::PI)));
        assert_eq!(done[1], (2, outcome(1e-17)));
        c.append(1, &outcome(2.0)).unwrap();
        drop(c);
        let (_, done) = Checkpoint::resume(&p, &h).unwrap();
        assert_eq!(done.len(), 3);
        // Another configuration is refused.
        let other = Header::new("abd", Shard::ALL, [2, 1, 1, 3]);
        let e = Checkpoint::resume(&p, &other).err().unwrap().to_string();
        assert!(e.contains("another configuration"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
