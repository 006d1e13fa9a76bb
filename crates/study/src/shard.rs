//! Shards, journals and merging: how a large study is cut into pieces that run anywhere (a Slurm
//! array task, a Dask worker, another terminal) and put back together byte for byte.
//!
//! # The model
//!
//! A study is a list of `N` points, numbered `0..N` in the order of its output table. Each point
//! yields one [`PointRecord`]: the output values, or the message of the error that made it fail.
//! Everything after that — the table, the figures, the summary — is a pure function of the
//! complete, ordered list of records. So:
//!
//! * a **shard** `i/n` ([`ShardSpec`], `1 ≤ i ≤ n`) computes the points `k` with
//!   `k mod n = i − 1` (round robin, so that the expensive corner of a map is spread over all
//!   shards) and writes them as a **partial result**: a [`JournalHeader`] line followed by one
//!   line per point;
//! * [`merge`] checks that the partial results belong to the same study (the [`fingerprint`] of
//!   its canonical description), the same grid and the same shard count, that no point is given
//!   twice with different values and that every point is present, and returns the ordered list —
//!   from which the same rendering code produces outputs identical to an unsharded run;
//! * an unsharded run keeps the same kind of file as a **journal** while it runs
//!   ([`Journal`]): every finished point is appended and flushed at once, so a run stopped by
//!   SIGINT or SIGKILL resumes from the points already done ([`Journal::open`] returns them)
//!   instead of computing them again.
//!
//! Values are stored as the hexadecimal bits of the `f64`, so that a number read back is the
//! number written, bit for bit; NaN payloads included.
//!
//! # Format (`geardyn-points/2`, JSON lines)
//!
//! ```text
//! {"format":"geardyn-points/2","study":"map","fingerprint":"9c1d…","points":1200,"outputs":["rsv","ppv"],"shard":[2,3],"h":"…"}
//! {"i":1,"v":["3ff0000000000000","3fe8000000000000"],"h":"5be0c6a1f2d07e43"}
//! {"i":4,"e":"liu2021: HBM did not converge","h":"0d9b2f6c11a8e7f0"}
//! ```
//!
//! Every line ends in a checksum `"h"`: the FNV-1a 64 hash ([`checksum`]) of the study's
//! fingerprint, a newline and the line's bytes before `,"h"`. A changed bit anywhere in a
//! record — a value, the point index, an error message — or a record copied from another
//! study's file no longer matches its checksum:
//!
//! * a **resumed** run drops such a record with a warning naming the file, the line and the
//!   point, and computes the point again ([`read_points_lenient`], [`Journal::open`]);
//! * a **merge** refuses the part with an error naming the file and the line ([`read_points`]).
//!
//! A torn last line (the writer was killed in the middle of it) is ignored on reading; a torn line
//! anywhere else is an error (merge) or a dropped record (resume).
//!
//! # Locks
//!
//! [`FileLock`] is an OS advisory lock (`flock` on Unix, `LockFileEx` on Windows) on an open
//! lock file: the OS releases it when the process ends, however it ends (SIGKILL, a node
//! failure), so a killed run never leaves a lock that refuses its restart, while a live run
//! still refuses a second one.

use std::collections::BTreeMap;
use std::fmt;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use crate::error::Error;

/// The format tag written in every header.
pub const FORMAT: &str = "geardyn-points/2";

/// The largest number of shards accepted (one per point of a 10⁶-point map, with room to spare).
pub const MAX_SHARDS: usize = 10_000_000;

/// One shard `index/count` of a study, `1 ≤ index ≤ count ≤` [`MAX_SHARDS`].
///
/// ```
/// use geardyn_study::shard::ShardSpec;
/// let s: ShardSpec = "2/3".parse().unwrap();
/// assert!(s.owns(1) && s.owns(4) && !s.owns(0));
/// assert!("0/3".parse::<ShardSpec>().is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardSpec {
    index: usize,
    count: usize,
}

impl ShardSpec {
    /// Shard `index` of `count` (1-based), checked.
    pub fn new(index: usize, count: usize) -> Result<Self, Error> {
        if count == 0 || count > MAX_SHARDS {
            return Err(shard_error(format!(
                "shard count must be in 1..={MAX_SHARDS}, got {count}"
            )));
        }
        if index == 0 || index > count {
            return Err(shard_error(format!(
                "shard index must be in 1..={count}, got {index}"
            )));
        }
        Ok(Self { index, count })
    }

    /// The whole study as one shard (`1/1`).
    pub fn whole() -> Self {
        Self { index: 1, count: 1 }
    }

    /// The 1-based shard number.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The number of shards.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Whether point `k` (0-based, in table order) belongs to this shard: `k mod count =
    /// index − 1`.
    pub fn owns(&self, point: usize) -> bool {
        point % self.count == self.index - 1
    }

    /// The points of a study of `n` points that this shard computes, in order.
    pub fn points(&self, n: usize) -> impl Iterator<Item = usize> + '_ {
        (self.index - 1..n).step_by(self.count)
    }
}

impl fmt::Display for ShardSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for ShardSpec {
    type Err = Error;

    /// Parse `i/n`, e.g. `3/8`.
    fn from_str(s: &str) -> Result<Self, Error> {
        let (a, b) = s
            .split_once('/')
            .ok_or_else(|| shard_error(format!("shard must be written `i/n`, got `{s}`")))?;
        let parse = |t: &str, what: &str| {
            t.trim().parse::<usize>().map_err(|_| {
                shard_error(format!(
                    "shard {what} must be a whole number, got `{t}` in `{s}`"
                ))
            })
        };
        Self::new(parse(a, "index")?, parse(b, "count")?)
    }
}

fn shard_error(msg: String) -> Error {
    Error::Shard(msg)
}

/// The outcome of one point: its output values, or the message of the error that made it fail.
#[derive(Debug, Clone, PartialEq)]
pub struct PointRecord {
    /// The point's 0-based index in table order.
    pub index: usize,
    /// The outputs (empty when the point failed).
    pub values: Vec<f64>,
    /// The error message of a failed point.
    pub error: Option<String>,
}

impl PointRecord {
    /// A point that produced `values`.
    pub fn ok(index: usize, values: Vec<f64>) -> Self {
        Self {
            index,
            values,
            error: None,
        }
    }

    /// A point that failed with `message`.
    pub fn failed(index: usize, message: impl Into<String>) -> Self {
        Self {
            index,
            values: Vec::new(),
            error: Some(message.into()),
        }
    }

    /// Bitwise equality (NaN equals NaN with the same bits): the test of "the same result".
    pub fn same_as(&self, other: &Self) -> bool {
        self.index == other.index
            && self.error == other.error
            && self.values.len() == other.values.len()
            && self
                .values
                .iter()
                .zip(&other.values)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

/// First line of a journal or partial result: what study and grid the records belong to.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JournalHeader {
    /// Always [`FORMAT`].
    pub format: String,
    /// The study's name.
    pub study: String,
    /// [`fingerprint`] of the study's canonical description (model, parameters, grid, solver).
    pub fingerprint: String,
    /// Number of points of the whole study.
    pub points: usize,
    /// Output names, in value order.
    pub outputs: Vec<String>,
    /// `[index, count]` of the shard, absent for a journal of a whole run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<[usize; 2]>,
}

impl JournalHeader {
    /// A header for `study` with `points` points and the given outputs.
    pub fn new(
        study: &str,
        fingerprint: String,
        points: usize,
        outputs: Vec<String>,
        shard: Option<ShardSpec>,
    ) -> Self {
        Self {
            format: FORMAT.to_owned(),
            study: study.to_owned(),
            fingerprint,
            points,
            outputs,
            shard: shard.map(|s| [s.index, s.count]),
        }
    }

    /// The same study and grid (shard aside).
    fn same_study(&self, other: &Self) -> bool {
        self.format == other.format
            && self.study == other.study
            && self.fingerprint == other.fingerprint
            && self.points == other.points
            && self.outputs == other.outputs
    }
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Line {
    i: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    v: Option<Vec<String>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    e: Option<String>,
}

/// The checksum of one line: FNV-1a 64 of `fingerprint`, `\n` and `body` (the line's bytes
/// before `,"h"`), as 16 hexadecimal digits. Ties a record to its bytes and to its study.
pub fn checksum(fingerprint: &str, body: &str) -> String {
    let mut bytes = Vec::with_capacity(fingerprint.len() + 1 + body.len());
    bytes.extend_from_slice(fingerprint.as_bytes());
    bytes.push(b'\n');
    bytes.extend_from_slice(body.as_bytes());
    fingerprint_bytes(&bytes)
}

/// `json` (a serialised object, ending in `}`) with the checksum field appended, and a newline.
fn sealed(fingerprint: &str, json: &str) -> String {
    let body = json.strip_suffix('}').unwrap_or(json);
    format!("{body},\"h\":\"{}\"}}\n", checksum(fingerprint, body))
}

/// The length of the checksum suffix `,"h":"<16 hex>"}`.
const SEAL_LEN: usize = 24;

/// Check the checksum of one line (without its newline) and return the object without the
/// checksum field (`{…}`), ready to parse.
fn unseal(fingerprint: &str, line: &str) -> Result<String, String> {
    let n = line.len();
    let ok_shape = n > SEAL_LEN
        && line.is_char_boundary(n - SEAL_LEN)
        && line[n - SEAL_LEN..].starts_with(",\"h\":\"")
        && line.ends_with("\"}");
    if !ok_shape {
        return Err("no checksum `\"h\"` at the end of the line".to_owned());
    }
    let body = &line[..n - SEAL_LEN];
    let given = &line[n - 18..n - 2];
    let want = checksum(fingerprint, body);
    if given != want {
        return Err(format!(
            "checksum mismatch (the line says {given}, its bytes give {want}): the record was \
             changed after it was written"
        ));
    }
    Ok(format!("{body}}}"))
}

/// One record as a JSON line of the study with `fingerprint` (checksum and trailing newline
/// included).
pub fn record_line(fingerprint: &str, r: &PointRecord) -> String {
    let line = match &r.error {
        Some(e) => Line {
            i: r.index,
            v: None,
            e: Some(e.clone()),
        },
        None => Line {
            i: r.index,
            v: Some(
                r.values
                    .iter()
                    .map(|x| format!("{:016x}", x.to_bits()))
                    .collect(),
            ),
            e: None,
        },
    };
    // A struct of a usize, strings and an Option: serialisation cannot fail.
    sealed(
        fingerprint,
        &serde_json::to_string(&line).unwrap_or_default(),
    )
}

/// The header as a JSON line (checksum and trailing newline included).
pub fn header_line(h: &JournalHeader) -> String {
    sealed(
        &h.fingerprint,
        &serde_json::to_string(h).unwrap_or_default(),
    )
}

fn parse_header(text: &str) -> Result<JournalHeader, String> {
    // The header carries the fingerprint its checksum is keyed with: read it, then check.
    let n = text.len();
    let body = if n > SEAL_LEN && text.is_char_boundary(n - SEAL_LEN) {
        format!("{}}}", &text[..n - SEAL_LEN])
    } else {
        text.to_owned()
    };
    let h: JournalHeader = serde_json::from_str(&body).map_err(|e| format!("header: {e}"))?;
    if h.format != FORMAT {
        return Err(format!("format `{}` is not `{FORMAT}`", h.format));
    }
    unseal(&h.fingerprint, text).map_err(|e| format!("header: {e}"))?;
    Ok(h)
}

fn parse_record(text: &str, header: &JournalHeader) -> Result<PointRecord, String> {
    let body = unseal(&header.fingerprint, text)?;
    let line: Line = serde_json::from_str(&body).map_err(|e| e.to_string())?;
    if line.i >= header.points {
        return Err(format!(
            "point {} is outside the study's {} points",
            line.i, header.points
        ));
    }
    if let Some([i, n]) = header.shard {
        if line.i % n != i - 1 {
            return Err(format!("point {} does not belong to shard {i}/{n}", line.i));
        }
    }
    match (line.v, line.e) {
        (Some(v), None) => {
            if v.len() != header.outputs.len() {
                return Err(format!(
                    "point {} has {} values, the study has {} outputs",
                    line.i,
                    v.len(),
                    header.outputs.len()
                ));
            }
            let values = v
                .iter()
                .map(|h| {
                    if h.len() != 16 {
                        return Err(format!("value `{h}` is not 16 hexadecimal digits"));
                    }
                    u64::from_str_radix(h, 16)
                        .map(f64::from_bits)
                        .map_err(|_| format!("value `{h}` is not hexadecimal"))
                })
                .collect::<Result<Vec<f64>, String>>()?;
            Ok(PointRecord::ok(line.i, values))
        }
        (None, Some(e)) => Ok(PointRecord::failed(line.i, e)),
        _ => Err(format!(
            "point {}: a record has either values `v` or an error `e`",
            line.i
        )),
    }
}

/// The point index a damaged line names, if it can still be read (for warnings).
fn point_of(text: &str) -> Option<usize> {
    let rest = text.strip_prefix("{\"i\":")?;
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

/// The lines of a journal or partial result after its header: `(line number, text)`, with a
/// torn last line (no newline at the very end) left out.
/// Numbered lines of a file's body: `(line number, text without the newline)`.
type NumberedLines<'a> = Vec<(usize, &'a str)>;

fn body_lines(text: &str) -> Result<(JournalHeader, NumberedLines<'_>), String> {
    let mut lines = text.split_inclusive('\n').enumerate().peekable();
    let (_, first) = lines.next().ok_or_else(|| "empty file".to_owned())?;
    let header = parse_header(first.trim_end()).map_err(|m| format!("line 1: {m}"))?;
    if let Some([i, n]) = header.shard {
        ShardSpec::new(i, n).map_err(|e| format!("line 1: {e}"))?;
    }
    let mut out = Vec::new();
    while let Some((k, l)) = lines.next() {
        if lines.peek().is_none() && !l.ends_with('\n') {
            break; // torn tail: the writer was stopped inside this line
        }
        out.push((k + 1, l.trim_end()));
    }
    Ok((header, out))
}

/// Read a journal or partial result **strictly** (for a merge): `source` names it in errors.
/// The records come back in file order; a torn last line (no newline at the very end) is
/// dropped, because a writer killed in the middle of a line leaves exactly that. Any other bad
/// line — not JSON, a checksum that does not match, a point outside the study or the shard —
/// is an error naming the file and the line.
pub fn read_points(text: &str, source: &str) -> Result<(JournalHeader, Vec<PointRecord>), Error> {
    let (header, lines) = body_lines(text).map_err(|m| Error::Shard(format!("{source}, {m}")))?;
    let mut out = Vec::with_capacity(lines.len());
    for (k, l) in lines {
        out.push(
            parse_record(l, &header)
                .map_err(|m| Error::Shard(format!("{source}, line {k}: {m}")))?,
        );
    }
    Ok((header, out))
}

/// Read a journal or partial result **leniently** (for a resumed run): the good records, and
/// one warning per dropped line (naming `source`, the line and the point when it can be read).
/// A dropped record's point is simply computed again. Errors only when the header itself is
/// unreadable.
pub fn read_points_lenient(
    text: &str,
    source: &str,
) -> Result<(JournalHeader, Vec<PointRecord>, Vec<String>), Error> {
    let (header, lines) = body_lines(text).map_err(|m| Error::Shard(format!("{source}, {m}")))?;
    let mut out = Vec::with_capacity(lines.len());
    let mut dropped = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for (k, l) in lines {
        match parse_record(l, &header) {
            Ok(r) if seen.insert(r.index) => out.push(r),
            Ok(r) => dropped.push(format!(
                "{source}, line {k}: point {} is recorded twice; the first record is kept",
                r.index
            )),
            Err(m) => {
                let point = point_of(l).map_or_else(String::new, |p| format!(" (point {p}?)"));
                dropped.push(format!(
                    "{source}, line {k}{point}: {m}; the record is dropped and its point \
                     computed again"
                ));
            }
        }
    }
    Ok((header, out, dropped))
}

/// Write `bytes` to `path` atomically: into a temporary file beside it, synced, then renamed
/// over `path`, so that a reader sees the old file or the new one, never a part.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let io = |p: &Path, e: std::io::Error| Error::Io {
        path: p.display().to_string(),
        source: e,
    };
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(format!(".tmp-{}", std::process::id()));
    let tmp = PathBuf::from(tmp);
    let mut f = File::create(&tmp).map_err(|e| io(&tmp, e))?;
    f.write_all(bytes).map_err(|e| io(&tmp, e))?;
    f.sync_all().map_err(|e| io(&tmp, e))?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(|e| io(path, e))
}

/// FNV-1a (64 bit) of `bytes`, as 16 hexadecimal digits: the fingerprint that ties a partial
/// result to the study that made it. It detects changed study files, it is not a security hash.
pub fn fingerprint(bytes: &[u8]) -> String {
    fingerprint_bytes(bytes)
}

fn fingerprint_bytes(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Merge partial results into the ordered, complete list of records of the whole study.
///
/// Errors (naming the part): an empty list; parts of different studies, grids or shard counts;
/// a point given twice with different results; a point that no part gives.
pub fn merge(
    parts: &[(String, JournalHeader, Vec<PointRecord>)],
) -> Result<(JournalHeader, Vec<PointRecord>), Error> {
    let (first_name, first, _) = parts
        .first()
        .ok_or_else(|| Error::Shard("merge: no partial results given".to_owned()))?;
    let mut by_index: BTreeMap<usize, &PointRecord> = BTreeMap::new();
    let mut seen_shards = BTreeMap::new();
    for (name, h, recs) in parts {
        if !h.same_study(first) {
            return Err(Error::Shard(format!(
                "merge: {name} is from another study or grid than {first_name} \
                 (study `{}` fingerprint {} with {} points, vs `{}` {} with {})",
                h.study, h.fingerprint, h.points, first.study, first.fingerprint, first.points
            )));
        }
        if let (Some([_, n]), Some([_, n0])) = (h.shard, first.shard) {
            if n != n0 {
                return Err(Error::Shard(format!(
                    "merge: {name} is one of {n} shards, {first_name} one of {n0}"
                )));
            }
        }
        if let Some([i, _]) = h.shard {
            if let Some(other) = seen_shards.insert(i, name) {
                return Err(Error::Shard(format!(
                    "merge: shard {i} is given twice ({other} and {name})"
                )));
            }
        }
        for r in recs {
            match by_index.get(&r.index) {
                Some(prev) if !prev.same_as(r) => {
                    return Err(Error::Shard(format!(
                        "merge: point {} has two different results (in {name})",
                        r.index
                    )));
                }
                _ => {
                    by_index.insert(r.index, r);
                }
            }
        }
    }
    if let Some(missing) = (0..first.points).find(|k| !by_index.contains_key(k)) {
        let count = first.points - by_index.len();
        return Err(Error::Shard(format!(
            "merge: {count} of {} points are missing (first: point {missing}); \
             run the missing shards and merge again",
            first.points
        )));
    }
    let mut header = first.clone();
    header.shard = None;
    Ok((header, by_index.into_values().cloned().collect()))
}

/// An append-only record of finished points, flushed after every point so that a killed run
/// loses at most the point it was writing.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    fingerprint: String,
    file: Mutex<File>,
    dropped: Vec<String>,
}

impl Journal {
    /// Open the journal at `path` for the study described by `header`: if a journal of the same
    /// study and grid is there, its records are returned (the run resumes from them) and new
    /// records are appended; if the file is absent, or belongs to another study or grid (the study
    /// file changed), a new journal is started. A torn last line is cut off before appending.
    /// A record whose checksum does not match (or that cannot be read) is dropped — its point
    /// is computed again — with a warning on stderr naming the file, the line and the point
    /// (also kept in [`Journal::dropped`]).
    pub fn open(path: &Path, header: &JournalHeader) -> Result<(Self, Vec<PointRecord>), Error> {
        let io = |e: std::io::Error| Error::Io {
            path: path.display().to_string(),
            source: e,
        };
        let mut done = Vec::new();
        let mut dropped = Vec::new();
        let mut keep = false;
        if path.exists() {
            let bytes = std::fs::read(path).map_err(io)?;
            let text = String::from_utf8_lossy(&bytes);
            let name = path.display().to_string();
            match read_points_lenient(&text, &name) {
                Ok((h, recs, bad)) if h.same_study(header) && h.shard == header.shard => {
                    keep = true;
                    done = recs;
                    dropped = bad;
                }
                Ok(_) => {}
                Err(e) => dropped.push(format!("{e}; the journal is started afresh")),
            }
        }
        for w in &dropped {
            eprintln!("warning: {w}");
        }
        let file = if keep {
            // Rewrite the good part (drops a torn tail and damaged records), then append.
            let mut body = header_line(header);
            for r in &done {
                body.push_str(&record_line(&header.fingerprint, r));
            }
            write_atomic(path, body.as_bytes())?;
            OpenOptions::new().append(true).open(path).map_err(io)?
        } else {
            let mut f = File::create(path).map_err(io)?;
            f.write_all(header_line(header).as_bytes()).map_err(io)?;
            f.sync_data().map_err(io)?;
            f
        };
        Ok((
            Self {
                path: path.to_path_buf(),
                fingerprint: header.fingerprint.clone(),
                file: Mutex::new(file),
                dropped,
            },
            done,
        ))
    }

    /// Append one record and flush it to the file.
    pub fn record(&self, r: &PointRecord) -> Result<(), Error> {
        let io = |e: std::io::Error| Error::Io {
            path: self.path.display().to_string(),
            source: e,
        };
        let mut f = self
            .file
            .lock()
            .map_err(|_| Error::Shard("journal lock poisoned".to_owned()))?;
        f.write_all(record_line(&self.fingerprint, r).as_bytes())
            .map_err(io)?;
        f.flush().map_err(io)
    }

    /// The journal's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The warnings of [`Journal::open`]: one per dropped (damaged) record, naming the file,
    /// the line and the point.
    pub fn dropped(&self) -> &[String] {
        &self.dropped
    }

    /// Remove the journal (after the outputs it fed were written).
    pub fn finish(self) -> Result<(), Error> {
        drop(self.file);
        match std::fs::remove_file(&self.path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(e) => Err(Error::Io {
                path: self.path.display().to_string(),
                source: e,
            }),
        }
    }
}

/// An OS advisory lock on a lock file, held while this value lives.
///
/// The lock is taken on the open file (`flock(LOCK_EX | LOCK_NB)` on Unix), not by the file's
/// existence: when the process ends — normally, by a panic, SIGKILL or a node failure — the OS
/// closes the file and releases the lock, so a restart is never refused by a dead run. The
/// file holds the holder's process id (for the message of a refused second run) and is removed
/// when the lock is dropped.
#[derive(Debug)]
pub struct FileLock {
    path: PathBuf,
    // Held open: closing it releases the lock.
    file: File,
}

/// Why [`FileLock::acquire`] did not get the lock.
#[derive(Debug)]
pub enum LockRefused {
    /// A live process holds it; its process id as written in the file (may be empty).
    Held(String),
    /// The lock file could not be opened or locked.
    Io(Error),
}

impl FileLock {
    /// Take the lock at `path` (created if absent) without waiting.
    pub fn acquire(path: &Path) -> Result<Self, LockRefused> {
        let io = |e: std::io::Error| {
            LockRefused::Io(Error::Io {
                path: path.display().to_string(),
                source: e,
            })
        };
        // A holder that drops its lock removes the file; if that happened between our open and
        // our lock, we hold a lock on a removed file: open again (a bounded number of times).
        for _ in 0..16 {
            let mut file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(path)
                .map_err(io)?;
            // `fs4::FileExt::try_lock` by path: `File::try_lock` of std is newer than our MSRV.
            match fs4::FileExt::try_lock(&file) {
                Ok(()) => {}
                Err(fs4::TryLockError::WouldBlock) => {
                    let holder = std::fs::read_to_string(path).unwrap_or_default();
                    return Err(LockRefused::Held(holder.trim().to_owned()));
                }
                Err(fs4::TryLockError::Error(e)) => return Err(io(e)),
            }
            if !same_file(&file, path) {
                continue;
            }
            file.set_len(0).map_err(io)?;
            writeln!(file, "pid {}", std::process::id()).map_err(io)?;
            let _ = file.flush();
            return Ok(Self {
                path: path.to_path_buf(),
                file,
            });
        }
        Err(LockRefused::Held(
            "the lock file keeps being replaced".to_owned(),
        ))
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for FileLock {
    fn drop(&mut self) {
        // Remove while still holding the lock; the lock goes with the file handle.
        let _ = std::fs::remove_file(&self.path);
        let _ = fs4::FileExt::unlock(&self.file);
    }
}

/// Whether the open `file` is the file now at `path` (same device and inode).
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Whether the open `file` is the file now at `path` (Windows does not remove a file that is
/// open without delete sharing, so the file is still the one at `path`).
#[cfg(not(unix))]
fn same_file(_file: &File, path: &Path) -> bool {
    path.exists()
}

/// Read every partial result in `files`, merge them, and return the complete ordered records.
pub fn merge_files(files: &[PathBuf]) -> Result<(JournalHeader, Vec<PointRecord>), Error> {
    let mut parts = Vec::with_capacity(files.len());
    for f in files {
        let name = f.display().to_string();
        let bytes = std::fs::read(f).map_err(|e| Error::Io {
            path: name.clone(),
            source: e,
        })?;
        // A flipped bit that breaks UTF-8 becomes a checksum error naming the line.
        let text = String::from_utf8_lossy(&bytes);
        let (h, recs) = read_points(&text, &name)?;
        if h.shard.is_none() {
            return Err(Error::Shard(format!(
                "{name} is a journal of an unfinished whole run, not a shard's partial result"
            )));
        }
        parts.push((name, h, recs));
    }
    merge(&parts)
}

/// Settings of a generated Slurm job array ([`sbatch_script`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmOptions {
    /// Number of shards = array tasks (`--array=1-N`).
    pub shards: usize,
    /// Wall-clock limit of one task, `HH:MM:SS`.
    pub time: String,
    /// Memory of one task (`--mem`), e.g. `2G`.
    pub memory: String,
    /// Cores of one task (`--cpus-per-task`; the points of a shard run in parallel on them).
    pub cpus: usize,
    /// Optional partition (`--partition`).
    pub partition: Option<String>,
    /// The `geardyn` executable as the compute nodes see it.
    pub geardyn: String,
}

impl Default for SlurmOptions {
    fn default() -> Self {
        Self {
            shards: 16,
            time: "01:00:00".to_owned(),
            memory: "2G".to_owned(),
            cpus: 1,
            partition: None,
            geardyn: "geardyn".to_owned(),
        }
    }
}

fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// A Slurm batch script that runs a study as a job array of `shards` tasks, each writing its
/// partial result into `OUT-shards/`; submit it with `sbatch`, then merge with
/// `geardyn merge STUDY --out OUT OUT-shards/*.part` (the script prints the merge job line that runs
/// after the array with `--dependency=afterok`).
///
/// Errors: a shard count outside `1..=`[`MAX_SHARDS`], zero cores, or a time/memory/partition
/// containing characters that do not belong in an `#SBATCH` line.
pub fn sbatch_script(
    study: &Path,
    out: &Path,
    name: &str,
    o: &SlurmOptions,
) -> Result<String, Error> {
    ShardSpec::new(1, o.shards)?;
    if o.cpus == 0 || o.cpus > 4096 {
        return Err(Error::Shard(format!(
            "cpus must be in 1..=4096, got {}",
            o.cpus
        )));
    }
    let plain = |what: &str, v: &str| {
        if v.is_empty()
            || !v
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, ':' | '-' | '_' | '.'))
        {
            Err(Error::Shard(format!(
                "{what} `{v}` must be non-empty and use only a-z A-Z 0-9 : - _ ."
            )))
        } else {
            Ok(())
        }
    };
    plain("time", &o.time)?;
    plain("memory", &o.memory)?;
    if let Some(p) = &o.partition {
        plain("partition", p)?;
    }
    crate::error::check_name(name)?;
    let study = shell_quote(&study.display().to_string());
    let out = shell_quote(&out.display().to_string());
    let exe = shell_quote(&o.geardyn);
    let n = o.shards;
    let mut s = String::new();
    s.push_str("#!/bin/bash\n");
    s.push_str(&format!("#SBATCH --job-name=geardyn-{name}\n"));
    s.push_str(&format!("#SBATCH --array=1-{n}\n"));
    s.push_str(&format!("#SBATCH --cpus-per-task={}\n", o.cpus));
    s.push_str(&format!("#SBATCH --mem={}\n", o.memory));
    s.push_str(&format!("#SBATCH --time={}\n", o.time));
    if let Some(p) = &o.partition {
        s.push_str(&format!("#SBATCH --partition={p}\n"));
    }
    s.push_str("#SBATCH --output=geardyn-%x-%A_%a.log\n");
    s.push_str("# Generated by `geardyn study --sbatch`. Submit with:\n");
    s.push_str("#   jobid=$(sbatch --parsable THIS_FILE)\n");
    s.push_str(&format!(
        "#   sbatch --dependency=afterok:$jobid --wrap \"{} merge {} --out {} {}-shards/*.part\"\n",
        o.geardyn.replace('"', ""),
        study.replace('"', ""),
        out.replace('"', ""),
        out.replace('"', "")
    ));
    s.push_str("# A task that is cut off resumes from its journal when it is submitted again.\n");
    s.push_str("set -euo pipefail\n");
    s.push_str(&format!("export RAYON_NUM_THREADS={}\n", o.cpus));
    s.push_str(&format!(
        "exec {exe} study {study} --out {out} --shard \"${{SLURM_ARRAY_TASK_ID}}/{n}\"\n"
    ));
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(shard: Option<ShardSpec>) -> JournalHeader {
        JournalHeader::new(
            "map",
            fingerprint(b"study"),
            7,
            vec!["a".into(), "b".into()],
            shard,
        )
    }

    fn record(k: usize) -> PointRecord {
        if k == 3 {
            PointRecord::failed(k, "did not converge")
        } else {
            PointRecord::ok(k, vec![k as f64 * 0.1, f64::NAN])
        }
    }

    fn partial(s: ShardSpec) -> String {
        let mut t = header_line(&header(Some(s)));
        for k in s.points(7) {
            t.push_str(&record_line(&fingerprint(b"study"), &record(k)));
        }
        t
    }

    #[test]
    fn shard_spec_parses_and_partitions() {
        for bad in ["", "3", "0/2", "3/2", "a/2", "1/0", "1/-1", "1/99999999999"] {
            assert!(bad.parse::<ShardSpec>().is_err(), "{bad}");
        }
        let n = 10;
        let mut seen = vec![0; n];
        for i in 1..=3 {
            let s: ShardSpec = format!("{i}/3").parse().unwrap();
            for k in s.points(n) {
                assert!(s.owns(k));
                seen[k] += 1;
            }
        }
        assert!(
            seen.iter().all(|&c| c == 1),
            "every point in exactly one shard"
        );
    }

    #[test]
    fn records_round_trip_bit_for_bit() {
        let h = header(None);
        let recs = [
            PointRecord::ok(0, vec![0.1, -0.0]),
            PointRecord::ok(
                1,
                vec![f64::MIN_POSITIVE, f64::from_bits(0x7ff8_0000_0000_0001)],
            ),
            PointRecord::failed(2, "boom \"quoted\"\nnewline"),
        ];
        let mut t = header_line(&h);
        for r in &recs {
            t.push_str(&record_line(&h.fingerprint, r));
        }
        let (h2, back) = read_points(&t, "t").unwrap();
        assert_eq!(h2, h);
        assert_eq!(back.len(), 3);
        for (a, b) in recs.iter().zip(&back) {
            assert!(a.same_as(b), "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn torn_tail_is_dropped_but_torn_middle_is_an_error() {
        let mut t = header_line(&header(None));
        t.push_str(&record_line(&fingerprint(b"study"), &record(0)));
        t.push_str(&record_line(&fingerprint(b"study"), &record(1))[..10]);
        let (_, recs) = read_points(&t, "t").unwrap();
        assert_eq!(recs.len(), 1);
        let mut t = header_line(&header(None));
        t.push_str("{\"i\":0,\"v\":[\"zz\n");
        t.push_str(&record_line(&fingerprint(b"study"), &record(1)));
        assert!(read_points(&t, "t").is_err());
        // values out of range or of the wrong length
        let mut t = header_line(&header(None));
        t.push_str("{\"i\":9,\"e\":\"x\"}\n");
        assert!(read_points(&t, "t").is_err());
        let mut t = header_line(&header(None));
        t.push_str("{\"i\":0,\"v\":[\"3ff0000000000000\"]}\n");
        assert!(read_points(&t, "t").is_err());
    }

    #[test]
    fn merge_of_three_shards_is_the_whole_study_in_order() {
        let parts: Vec<_> = [3, 1, 2]
            .iter()
            .map(|&i| {
                let s = ShardSpec::new(i, 3).unwrap();
                let (h, r) = read_points(&partial(s), "p").unwrap();
                (format!("part{i}"), h, r)
            })
            .collect();
        let (h, recs) = merge(&parts).unwrap();
        assert_eq!(h.shard, None);
        assert_eq!(recs.len(), 7);
        for (k, r) in recs.iter().enumerate() {
            assert!(r.same_as(&record(k)));
        }
    }

    #[test]
    fn merge_refuses_missing_mixed_and_conflicting_parts() {
        let p = |i, n| {
            let s = ShardSpec::new(i, n).unwrap();
            let (h, r) = read_points(&partial(s), "p").unwrap();
            (format!("{i}/{n}"), h, r)
        };
        let e = merge(&[p(1, 3), p(2, 3)]).unwrap_err().to_string();
        assert!(e.contains("missing"), "{e}");
        assert!(merge(&[p(1, 3), p(1, 3), p(2, 3), p(3, 3)]).is_err());
        assert!(merge(&[p(1, 2), p(2, 3)]).is_err());
        assert!(merge(&[]).is_err());
        let mut other = p(3, 3);
        other.1.fingerprint = fingerprint(b"another study");
        assert!(merge(&[p(1, 3), p(2, 3), other]).is_err());
        let mut conflict = p(3, 3);
        conflict.2[0].values[0] += 1.0;
        let mut dup = p(3, 3);
        dup.1.shard = None;
        assert!(merge(&[p(1, 3), p(2, 3), conflict, dup]).is_err());
    }

    #[test]
    fn journal_resumes_from_finished_points_and_restarts_on_a_new_study() {
        let dir = std::env::temp_dir().join(format!("geardyn-journal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("map.journal");
        let _ = std::fs::remove_file(&path);
        let h = header(None);
        let (j, done) = Journal::open(&path, &h).unwrap();
        assert!(done.is_empty());
        j.record(&record(0)).unwrap();
        j.record(&record(3)).unwrap();
        drop(j);
        // a torn write, as SIGKILL leaves it
        let mut f = OpenOptions::new().append(true).open(&path).unwrap();
        f.write_all(b"{\"i\":5,\"v\":[\"3ff").unwrap();
        drop(f);
        let (j, done) = Journal::open(&path, &h).unwrap();
        assert_eq!(done.len(), 2);
        assert!(done[1].same_as(&record(3)));
        j.record(&record(5)).unwrap();
        drop(j);
        let (j, done) = Journal::open(&path, &h).unwrap();
        assert_eq!(done.len(), 3);
        // the study changed: start again
        let mut h2 = h.clone();
        h2.fingerprint = fingerprint(b"changed");
        drop(j);
        let (j, done) = Journal::open(&path, &h2).unwrap();
        assert!(done.is_empty());
        j.finish().unwrap();
        assert!(!path.exists());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn sbatch_script_runs_every_shard_once_and_quotes_paths() {
        let o = SlurmOptions {
            shards: 12,
            partition: Some("short".into()),
            ..SlurmOptions::default()
        };
        let s = sbatch_script(Path::new("my dir/map.toml"), Path::new("out"), "map", &o).unwrap();
        assert!(s.starts_with("#!/bin/bash\n"));
        assert!(s.contains("#SBATCH --array=1-12\n"));
        assert!(s.contains("#SBATCH --partition=short\n"));
        assert!(
            s.contains("study 'my dir/map.toml' --out 'out' --shard \"${SLURM_ARRAY_TASK_ID}/12\"")
        );
        for bad in [
            SlurmOptions {
                shards: 0,
                ..SlurmOptions::default()
            },
            SlurmOptions {
                cpus: 0,
                ..SlurmOptions::default()
            },
            SlurmOptions {
                time: "1:00\n#SBATCH --x".into(),
                ..SlurmOptions::default()
            },
        ] {
            assert!(sbatch_script(Path::new("a.toml"), Path::new("o"), "map", &bad).is_err());
        }
        assert!(sbatch_script(Path::new("a.toml"), Path::new("o"), "../x", &o).is_err());
    }

    #[test]
    fn fingerprint_is_stable() {
        // FNV-1a 64 reference values (the algorithm's published test vectors).
        assert_eq!(fingerprint(b""), "cbf29ce484222325");
        assert_eq!(fingerprint(b"a"), "af63dc4c8601ec8c");
    }
}
