//! `edsgen sdo write --file` and `edsgen sdo read --out`: a value of any length streamed between
//! a file (or standard input or output) and an entry, by block transfer unless the node refuses
//! it, and a one-line summary (bytes, the transfer the wire carried, time) on standard error;
//! a progress bar there meanwhile when it is a terminal ([`progress`]).
//!
//! `--out FILE` never leaves a partial value under FILE's name: the bytes go to `FILE.partial`
//! beside it, renamed to FILE once the upload has completed, removed when it fails (a FILE that
//! was there stays as it was). Only a process killed during the transfer leaves the
//! `.partial` file, named for what it is.

use std::fs::{self, File};
use std::io::{self, BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use edsgen_host::master::blocking::MasterError;
use edsgen_model::model::BasicType;
use edsgen_runtime::master::{Mode, SdoError, Transfer};

use super::{fail, master_failed, progress, Resolved, Target};

/// Which way a file transfer goes, and its file (`-`: standard input or output).
pub enum Stream<'a> {
    /// `--file`: from the file into the entry.
    Download(&'a Path),
    /// `--out`: from the entry into the file.
    Upload(&'a Path),
}

/// The abort of a node that does not do block transfers: command specifier unknown.
const NO_BLOCK: u32 = 0x0504_0001;

/// How many of a download's first bytes are kept for a segmented second attempt: more than the
/// master reads before a node confirms (or refuses) a block transfer, its window of 889 bytes
/// and one chunk.
const KEPT: usize = 4096;

/// Runs a file transfer: `--segmented` forces segmented, `--block` forbids the fallback.
pub fn run(target: &Target, stream: Stream<'_>, segmented: bool) -> ExitCode {
    let resolved = match target.resolve() {
        Ok(resolved) => resolved,
        Err(message) => return fail(message),
    };
    if let Some(basic) = resolved.data_type.filter(|&basic| !takes_files(basic)) {
        return fail(format!(
            "{} is {}: a file goes only to or from a DOMAIN, a string or an octet string",
            resolved.label(),
            basic.name()
        ));
    }
    let plan = Plan {
        first: if segmented { Mode::Normal } else { Mode::Block },
        fallback: !segmented && !target.block,
    };
    match stream {
        Stream::Download(path) => download(target, &resolved, path, plan),
        Stream::Upload(path) => upload(target, &resolved, path, plan),
    }
}

/// The data types a file can fill: of any length, their bytes taken as they are.
fn takes_files(basic: BasicType) -> bool {
    matches!(
        basic,
        BasicType::Domain
            | BasicType::VisibleString
            | BasicType::OctetString
            | BasicType::UnicodeString
    )
}

/// The transfer tried first, and whether a node's refusal of block transfer leads to a
/// segmented one.
#[derive(Clone, Copy)]
struct Plan {
    first: Mode,
    fallback: bool,
}

impl Plan {
    /// Whether `result` is a refused block transfer to be made again segmented.
    fn falls_back<T>(self, result: &Result<T, MasterError>) -> bool {
        self.fallback
            && self.first == Mode::Block
            && matches!(
                result,
                Err(MasterError::Sdo {
                    error: SdoError::Server(NO_BLOCK),
                    ..
                })
            )
    }
}

fn download(target: &Target, resolved: &Resolved, path: &Path, plan: Plan) -> ExitCode {
    let reader: Box<dyn Read> = if is_std(path) {
        Box::new(io::stdin().lock())
    } else {
        match open(path) {
            Ok(file) => Box::new(file),
            Err(message) => return fail(message),
        }
    };
    let length = if is_std(path) {
        None
    } else {
        fs::metadata(path).ok().map(|m| m.len())
    };
    let mut source = Source::new(progress::Counted::new(reader, length));
    let mut master = match target.bus.connect() {
        Ok(master) => master,
        Err(message) => return fail(message),
    };
    target.bus.for_writes(&mut master);
    let (node_id, mux) = (resolved.node_id, resolved.mux);
    let started = Instant::now();
    let mut mode = plan.first;
    let mut result = master.download_from(node_id, mux, mode, &mut source);
    if plan.falls_back(&result) && source.rewind() {
        mode = Mode::Normal;
        result = master.download_from(node_id, mux, mode, &mut source);
    }
    match result {
        Ok(size) => {
            source.reader.finish();
            let summary = Summary {
                upload: false,
                transfer: master.last_transfer().unwrap_or(Transfer::Segmented),
                refused_block: mode != plan.first,
            };
            summary.print(resolved, size, started);
            ExitCode::SUCCESS
        }
        Err(MasterError::Io(e)) if source.failed => fail(format!(
            "cannot read {}: {e}",
            shown(path, "standard input")
        )),
        Err(error) => master_failed(error),
    }
}

fn upload(target: &Target, resolved: &Resolved, path: &Path, plan: Plan) -> ExitCode {
    let partial = partial_path(path);
    let file = if is_std(path) {
        None
    } else if path.is_dir() {
        return fail(format!(
            "cannot write `{}`: it is a directory",
            path.display()
        ));
    } else {
        match File::create(&partial) {
            Ok(file) => Some(file),
            Err(e) => return fail(format!("cannot write `{}`: {e}", path.display())),
        }
    };
    // A transfer that fails leaves no partial file behind.
    let discard = |code: ExitCode| {
        if !is_std(path) {
            let _ = fs::remove_file(&partial);
        }
        code
    };
    let inner: Box<dyn Write> = match file {
        Some(file) => Box::new(file),
        None => Box::new(io::stdout().lock()),
    };
    let mut sink = Sink {
        inner: BufWriter::new(progress::Counted::new(inner, None)),
        written: 0,
        failed: false,
    };
    let mut master = match target.bus.connect() {
        Ok(master) => master,
        Err(message) => return discard(fail(message)),
    };
    let (node_id, mux) = (resolved.node_id, resolved.mux);
    let started = Instant::now();
    let mut mode = plan.first;
    let mut result = master.upload_to(node_id, mux, mode, &mut sink);
    if plan.falls_back(&result) && sink.written == 0 {
        mode = Mode::Normal;
        result = master.upload_to(node_id, mux, mode, &mut sink);
    }
    let result = result.and_then(|size| match sink.flush() {
        Ok(()) => Ok(size),
        Err(e) => Err(MasterError::Io(e)),
    });
    sink.inner.get_mut().finish();
    match result {
        Ok(size) => {
            let summary = Summary {
                upload: true,
                transfer: master.last_transfer().unwrap_or(Transfer::Segmented),
                refused_block: mode != plan.first,
            };
            summary.print(resolved, size, started);
            if target.block && summary.transfer != Transfer::Block {
                eprintln!(
                    "error: {}: the node answered the block upload with {}; --block takes only \
                     a block transfer (leave it out to accept the node's choice)",
                    resolved.label(),
                    summary.how()
                );
                return discard(ExitCode::from(1));
            }
            // Only a complete value takes the file's name.
            if !is_std(path) {
                if let Err(e) = fs::rename(&partial, path) {
                    return discard(fail(format!("cannot write `{}`: {e}", path.display())));
                }
            }
            ExitCode::SUCCESS
        }
        Err(MasterError::Io(e)) if sink.failed => discard(fail(format!(
            "cannot write {}: {e}",
            shown(path, "standard output")
        ))),
        Err(error) => discard(master_failed(error)),
    }
}

/// Where `--out PATH` collects an upload until it completes: `PATH.partial`, in the same
/// directory so that the rename cannot cross file systems.
fn partial_path(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".partial");
    PathBuf::from(name)
}

/// `-` names standard input or output.
fn is_std(path: &Path) -> bool {
    path == Path::new("-")
}

/// `` `PATH` ``, or `what` for `-`.
fn shown(path: &Path, what: &str) -> String {
    if is_std(path) {
        what.to_string()
    } else {
        format!("`{}`", path.display())
    }
}

/// Opens `--file`, a directory or a missing file being a usage error.
fn open(path: &Path) -> Result<File, String> {
    let cannot = |why: String| format!("cannot read `{}`: {why}", path.display());
    if path.is_dir() {
        return Err(cannot("it is a directory".into()));
    }
    File::open(path).map_err(|e| cannot(e.to_string()))
}

/// How a file transfer went: `2001h:00h Program: 65536 bytes written by block transfer in
/// 0.412 s`.
struct Summary {
    upload: bool,
    /// The transfer that carried the value on the wire (the server may answer a block upload
    /// request with a normal upload).
    transfer: Transfer,
    /// Whether the node refused a block transfer first.
    refused_block: bool,
}

impl Summary {
    /// The transfer, as the summary names it.
    fn how(&self) -> &'static str {
        match self.transfer {
            Transfer::Block => "block transfer",
            Transfer::Expedited => "expedited transfer",
            Transfer::Segmented if self.refused_block => {
                "segmented transfer (the node refused block transfer)"
            }
            Transfer::Segmented => "segmented transfer",
        }
    }

    fn print(&self, resolved: &Resolved, size: u32, started: Instant) {
        let how = self.how();
        let done = if self.upload { "read" } else { "written" };
        eprintln!(
            "{}: {size} bytes {done} by {how} in {:.3} s",
            resolved.label(),
            started.elapsed().as_secs_f64()
        );
    }
}

/// A download's bytes: the file or standard input, its first [`KEPT`] bytes kept so that a
/// transfer the node refused as a block transfer can start again segmented (standard input
/// cannot be read twice), and its own failure told apart from the bus's.
struct Source<R> {
    reader: R,
    kept: Vec<u8>,
    /// Where the next read starts in `kept` (its end while reading `reader`).
    at: usize,
    /// Whether `kept` holds every byte read so far (not yet rewound nor past [`KEPT`]).
    keeping: bool,
    /// Whether `reader` failed.
    failed: bool,
}

impl<R: Read> Source<R> {
    fn new(reader: R) -> Self {
        Source {
            reader,
            kept: Vec::new(),
            at: 0,
            keeping: true,
            failed: false,
        }
    }

    /// Reads again from the first byte, if every byte read is still kept.
    fn rewind(&mut self) -> bool {
        let whole = self.keeping;
        if whole {
            self.keeping = false;
            self.at = 0;
        }
        whole
    }
}

impl<R: Read> Read for Source<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.at < self.kept.len() {
            let n = buf.len().min(self.kept.len() - self.at);
            buf[..n].copy_from_slice(&self.kept[self.at..self.at + n]);
            self.at += n;
            return Ok(n);
        }
        let n = self.reader.read(buf).inspect_err(|_| self.failed = true)?;
        if self.keeping && self.kept.len() + n <= KEPT {
            self.kept.extend_from_slice(&buf[..n]);
            self.at = self.kept.len();
        } else {
            self.keeping = false;
        }
        Ok(n)
    }
}

/// An upload's destination, counting what it took and telling its own failure apart from the
/// bus's.
struct Sink<W: Write> {
    inner: BufWriter<W>,
    written: u64,
    failed: bool,
}

impl<W: Write> Write for Sink<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf).inspect_err(|_| self.failed = true)?;
        self.written += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush().inspect_err(|_| self.failed = true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_upload_collects_beside_its_file_under_a_partial_name() {
        assert_eq!(
            partial_path(Path::new("dir/program.bin")),
            Path::new("dir/program.bin.partial")
        );
        assert_eq!(partial_path(Path::new("out")), Path::new("out.partial"));
    }

    #[test]
    fn a_rewound_source_gives_its_bytes_again_then_the_rest() {
        let data: Vec<u8> = (0..=255).cycle().take(3000).collect();
        let mut source = Source::new(data.as_slice());
        let mut first = [0; 1000];
        source.read_exact(&mut first).unwrap();
        assert!(source.rewind());
        let mut all = Vec::new();
        source.read_to_end(&mut all).unwrap();
        assert_eq!(all, data);
        assert!(!source.rewind(), "a second rewind");
    }

    #[test]
    fn a_source_tells_its_own_failure_from_the_bus() {
        struct Gone;
        impl Read for Gone {
            fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
                Err(io::Error::other("disk gone"))
            }
        }
        let mut source = Source::new(Gone);
        assert!(!source.failed);
        let error = source.read(&mut [0; 8]).unwrap_err();
        assert_eq!(error.to_string(), "disk gone");
        assert!(source.failed);
    }

    #[test]
    fn a_source_read_past_what_it_keeps_cannot_rewind() {
        let data = vec![7u8; KEPT + 1];
        let mut source = Source::new(data.as_slice());
        let mut all = Vec::new();
        source.read_to_end(&mut all).unwrap();
        assert_eq!(all.len(), KEPT + 1);
        assert!(!source.rewind());
    }
}
