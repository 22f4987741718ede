//! The loader: a description read, its overlay (`NAME.toml` beside it, see [`crate::overlay`])
//! applied, and judged by the validator. `Builder` and every command of the CLI that reads a
//! description start here, so they all see the same model and the same diagnostics.

use std::path::{Path, PathBuf};

use crate::diag::Diagnostic;
use crate::lint::Policy;
use crate::model::Device;
use crate::read::{self, Read, ReadError};
use crate::{overlay, render, validate};

/// A description as the later stages take it.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The model, the overlay applied.
    pub device: Device,
    /// The decoded text of the description (diagnostics are rendered against it).
    pub text: String,
    /// What the reader and then the validator say about the description ([`crate::diag::sort`] puts
    /// them in display order). The validator does not run when nothing could be read
    /// ([`Read::nothing_read`]).
    pub diagnostics: Vec<Diagnostic>,
    /// Whether nothing could be read (an empty, binary or malformed file).
    pub nothing_read: bool,
    /// The overlay, when there is one beside the description.
    pub overlay: Option<Overlay>,
}

/// An overlay file that was applied.
#[derive(Debug, Clone)]
pub struct Overlay {
    /// Where it is.
    pub path: PathBuf,
    /// Its text.
    pub text: String,
    /// What is wrong with it (spans in `text`); what they name was not applied.
    pub diagnostics: Vec<Diagnostic>,
}

impl Overlay {
    /// Its diagnostics rendered rustc-style, without colour (empty when there are none).
    pub fn rendered(&self) -> String {
        if self.diagnostics.is_empty() {
            return String::new();
        }
        render::human(
            &self.path.display().to_string(),
            &self.text,
            &self.diagnostics,
            false,
        )
    }
}

/// Why nothing could be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// The description cannot be read.
    Read(ReadError),
    /// The overlay beside it exists but cannot be read.
    Overlay(PathBuf, std::io::Error),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Read(err) => err.fmt(f),
            LoadError::Overlay(path, err) => {
                write!(f, "cannot read the overlay `{}`: {err}", path.display())
            }
        }
    }
}

impl std::error::Error for LoadError {}

/// Loads the description at `path`: one device of an ESI file that describes several when
/// `device` names it (see [`read::read_file_device`]).
pub fn load(path: &Path, device: Option<&str>) -> Result<Loaded, LoadError> {
    let read = read::read_file_device(path, device).map_err(LoadError::Read)?;
    load_read(path, read)
}

/// Finishes loading a description already read from `path` (from bytes built into a binary,
/// say): applies the overlay beside `path`, if there is one, and validates.
pub fn load_read(path: &Path, read: Read) -> Result<Loaded, LoadError> {
    let overlay_path = overlay::path_for(path);
    let overlay = if overlay_path.is_file() {
        let text = std::fs::read_to_string(&overlay_path)
            .map_err(|err| LoadError::Overlay(overlay_path.clone(), err))?;
        Some((overlay_path, text))
    } else {
        None
    };
    Ok(finish(read, overlay))
}

/// Loads a description built into a binary (a bundled card), with the overlay built in beside
/// it, if it has one: what [`load`] gives for the same two files on disk, without the disk.
pub fn load_bundled(path: &Path, bytes: &[u8], overlay: Option<&str>) -> Loaded {
    let read = read::read_bytes(path, bytes);
    let overlay = overlay.map(|text| (overlay::path_for(path), text.to_owned()));
    finish(read, overlay)
}

/// Applies an overlay (its path and text), then judges.
fn finish(mut read: Read, overlay: Option<(PathBuf, String)>) -> Loaded {
    let overlay = overlay.map(|(path, text)| {
        let diagnostics = overlay::apply(&text, &mut read.device);
        Overlay {
            path,
            text,
            diagnostics,
        }
    });
    let mut loaded = judge(read);
    loaded.overlay = overlay;
    loaded
}

/// Validates a description read from bytes built into a binary (a bundled card), without an
/// overlay: there is no file beside it.
pub fn judge(read: Read) -> Loaded {
    let nothing_read = read.nothing_read();
    let Read {
        device,
        mut diagnostics,
        text,
    } = read;
    if !nothing_read {
        diagnostics.extend(validate::validate(&device));
    }
    Loaded {
        device,
        text,
        diagnostics,
        nothing_read,
        overlay: None,
    }
}

/// Why a simulator refuses a description ([`Loaded::servable`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    /// The errors that refuse it, rendered rustc-style as `edsgen validate` prints them.
    pub rendered: String,
    /// One line: how many errors of which codes, and the `--allow` that serves it anyway.
    pub summary: String,
}

impl Loaded {
    /// The rule every simulator applies before serving the description read from `name`: a
    /// description (or its overlay) with errors is refused, unless `policy` allows each of
    /// their codes ([`Policy::refusing`]).
    pub fn servable(&self, name: &str, policy: &Policy) -> Result<(), Refusal> {
        let own = policy.refusing(&self.diagnostics);
        let overlay = policy.refusing(self.overlay_diagnostics());
        if own.is_empty() && overlay.is_empty() {
            return Ok(());
        }
        let mut rendered = render::human(name, &self.text, &own, false);
        if let Some(o) = self.overlay.as_ref().filter(|_| !overlay.is_empty()) {
            let overlay_name = o.path.display().to_string();
            rendered.push_str(&render::human(&overlay_name, &o.text, &overlay, false));
        }
        let mut codes: Vec<&str> = own.iter().chain(&overlay).map(Diagnostic::code).collect();
        codes.sort_unstable();
        codes.dedup();
        let count = own.len() + overlay.len();
        let allow: Vec<String> = codes.iter().map(|c| format!("--allow {c}")).collect();
        let summary = format!(
            "`{name}` has {count} error{s} ({codes}): not served; `{allow}` serves it anyway",
            s = if count == 1 { "" } else { "s" },
            codes = codes.join(", "),
            allow = allow.join(" "),
        );
        Err(Refusal { rendered, summary })
    }

    /// The overlay's diagnostics (none without an overlay).
    pub fn overlay_diagnostics(&self) -> &[Diagnostic] {
        self.overlay.as_ref().map_or(&[], |o| &o.diagnostics)
    }
}
