//! `Builder`: the build.rs entry point. Reads each device description, validates it, generates
//! its module into `OUT_DIR/NAME.rs` (for `edsgen_runtime::include_device!("NAME")`), prints
//! `cargo:rerun-if-changed` for every input and warnings as `cargo:warning`, and fails on errors
//! with the rendered diagnostics. A device's overlay (`NAME.toml` beside `NAME.eds`, see
//! [`edsgen_model::overlay`]) is applied before generation.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::emit;
use edsgen_model::diag::{self, Severity};
use edsgen_model::lint::Policy;
use edsgen_model::{load, overlay, render};

/// Generates typed bindings for one or more devices from build.rs.
///
/// ```no_run
/// // build.rs
/// fn main() -> Result<(), edsgen_codegen::builder::BuildError> {
///     edsgen_codegen::Builder::new()
///         .device("eds/cp301.eds")
///         .device("eds/ms300.eds")
///         .generate()
/// }
/// // in the crate: edsgen_runtime::include_device!("cp301");
/// ```
#[derive(Debug, Default, Clone)]
pub struct Builder {
    devices: Vec<(PathBuf, Option<String>)>,
    allowed: Vec<String>,
    out_dir: Option<PathBuf>,
    cargo_output: Option<bool>,
}

/// Why generation failed: the rendered diagnostics or the I/O problem, ready to print.
pub struct BuildError {
    message: String,
}

impl BuildError {
    /// The rendered message.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

// `main` returning `Err` prints the Debug form: make it the readable message.
impl fmt::Debug for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for BuildError {}

/// What [`Builder::generate_to`] wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Output {
    /// (module name, file written) per device, in the order given.
    pub modules: Vec<(String, PathBuf)>,
    /// Warnings, rendered (also printed as `cargo:warning` lines when running under cargo).
    pub warnings: Vec<String>,
}

impl Builder {
    /// A builder with no devices.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a device description file; its module is named after the file stem in snake case.
    pub fn device(mut self, path: impl Into<PathBuf>) -> Self {
        self.devices.push((path.into(), None));
        self
    }

    /// Adds a device description file with an explicit module name.
    pub fn device_as(mut self, path: impl Into<PathBuf>, module: &str) -> Self {
        self.devices.push((path.into(), Some(module.to_owned())));
        self
    }

    /// Silences the warnings of the rule `code` (e.g. `"EDS308"`) for every device, like an
    /// `#[allow]`: for a warning the description cannot avoid without lying about the device.
    /// Errors of that rule still fail the build (the generated code would be wrong); an unknown
    /// code fails the build too.
    pub fn allow(mut self, code: &str) -> Self {
        self.allowed.push(code.to_owned());
        self
    }

    /// Writes into `dir` instead of `$OUT_DIR`.
    pub fn out_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.out_dir = Some(dir.into());
        self
    }

    /// Whether to print `cargo:` lines (default: when `$OUT_DIR` is set, i.e. under build.rs).
    pub fn cargo_output(mut self, on: bool) -> Self {
        self.cargo_output = Some(on);
        self
    }

    /// Generates every device; see [`Builder::generate_to`].
    pub fn generate(self) -> Result<(), BuildError> {
        self.generate_to().map(|_| ())
    }

    /// Generates every device and says what was written. Every device is tried, so one build
    /// shows the errors of all of them.
    pub fn generate_to(self) -> Result<Output, BuildError> {
        let out_dir = match self
            .out_dir
            .clone()
            .or_else(|| std::env::var_os("OUT_DIR").map(PathBuf::from))
        {
            Some(dir) => dir,
            None => {
                return Err(BuildError {
                    message:
                        "edsgen: OUT_DIR is not set; call from build.rs or use Builder::out_dir"
                            .into(),
                })
            }
        };
        let cargo = self
            .cargo_output
            .unwrap_or_else(|| std::env::var_os("OUT_DIR").is_some());
        let mut errors = String::new();
        let mut output = Output {
            modules: Vec::new(),
            warnings: Vec::new(),
        };
        let mut policy = Policy::new();
        for code in &self.allowed {
            match edsgen_model::rules::by_code(code) {
                Some(rule) => policy.allow(rule),
                None => {
                    let near = edsgen_model::rules::nearest(code).map_or(String::new(), |rule| {
                        format!("; did you mean {}?", rule.code)
                    });
                    errors.push_str(&format!(
                        "error: edsgen: Builder::allow(\"{code}\"): no such rule{near} (see `edsgen rules`)\n"
                    ))
                }
            }
        }
        let mut seen = std::collections::BTreeSet::new();
        for (path, module) in &self.devices {
            if cargo {
                println!("cargo:rerun-if-changed={}", path.display());
                // The overlay if there is one; else its folder, so that adding one is noticed.
                let overlay = overlay::path_for(path);
                let watched = if overlay.is_file() {
                    overlay
                } else {
                    overlay.parent().map(Path::to_path_buf).unwrap_or_default()
                };
                if !watched.as_os_str().is_empty() {
                    println!("cargo:rerun-if-changed={}", watched.display());
                }
            }
            let module = emit::module_name(&module.clone().unwrap_or_else(|| default_module(path)));
            if !seen.insert(module.clone()) {
                errors.push_str(&format!(
                    "error: edsgen: two devices would both be module `{module}`; use Builder::device_as\n"
                ));
                continue;
            }
            match generate_device(path, &module, &policy) {
                Ok((code, warnings)) => {
                    let file = out_dir.join(format!("{module}.rs"));
                    if let Err(err) = write_if_changed(&file, &code) {
                        errors.push_str(&format!(
                            "error: edsgen: cannot write `{}`: {err}\n",
                            file.display()
                        ));
                        continue;
                    }
                    if cargo {
                        for line in warnings
                            .iter()
                            .flat_map(|w| w.lines())
                            .filter(|l| !l.trim().is_empty())
                        {
                            println!("cargo:warning={line}");
                        }
                    }
                    output.warnings.extend(warnings);
                    output.modules.push((module, file));
                }
                Err(message) => errors.push_str(&message),
            }
        }
        // Not printed here: build.rs returns it from `main`, which prints it (once).
        if errors.is_empty() {
            Ok(output)
        } else {
            Err(BuildError { message: errors })
        }
    }
}

/// The module name a device gets unless one is given: its file name without the extension (the
/// generator makes it a snake-case identifier).
pub fn default_module(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "device".into())
}

fn write_if_changed(file: &Path, code: &str) -> std::io::Result<()> {
    if std::fs::read(file).ok().as_deref() == Some(code.as_bytes()) {
        return Ok(());
    }
    std::fs::write(file, code)
}

/// Loads ([`edsgen_model::load`]: read, overlay, validate) and generates one device: the module's code
/// and the rendered warnings (less those `policy` allows; denied ones fail), or every error
/// rendered. `edsgen generate` calls it too, so it writes exactly what build.rs gets.
pub fn generate_device(
    path: &Path,
    module: &str,
    policy: &Policy,
) -> Result<(String, Vec<String>), String> {
    generate_chosen_device(path, None, module, policy)
}

/// [`generate_device`] for one device of an ESI file that describes several, chosen by type name
/// or `#x` product code (see [`edsgen_model::read::read_file_device`]); `None` is the first.
pub fn generate_chosen_device(
    path: &Path,
    device: Option<&str>,
    module: &str,
    policy: &Policy,
) -> Result<(String, Vec<String>), String> {
    let mut loaded = load::load(path, device).map_err(|err| format!("error: edsgen: {err}\n"))?;
    generate_loaded(path, &mut loaded, module, policy)
}

/// [`generate_chosen_device`] for a description already loaded from `path`: the caller keeps
/// the model (its diagnostics are taken out of it).
pub fn generate_loaded(
    path: &Path,
    loaded: &mut load::Loaded,
    module: &str,
    policy: &Policy,
) -> Result<(String, Vec<String>), String> {
    let name = path.display().to_string();
    let overlay_errors = loaded
        .overlay
        .as_ref()
        .filter(|o| !o.diagnostics.is_empty())
        .map(|o| o.rendered());
    let mut diags = policy.apply(std::mem::take(&mut loaded.diagnostics));
    let emitted = if diags.iter().any(|d| d.severity == Severity::Error) {
        None
    } else {
        // Infos are not shown, unless the policy makes some errors: then they are made.
        let infos = if policy.raises_infos() {
            emit::Infos::Reported
        } else {
            emit::Infos::Skipped
        };
        // Loading validated the device, and found no error: its sizes fit.
        match emit::generate_validated_module(&loaded.device, module, infos) {
            Ok(generated) => {
                diags.extend(policy.apply(generated.diagnostics));
                Some(generated.code)
            }
            Err(emit_diags) => {
                diags.extend(policy.apply(emit_diags));
                None
            }
        }
    };
    diag::sort(&mut diags);
    let shown: Vec<_> = diags
        .into_iter()
        .filter(|d| d.severity != Severity::Info)
        .collect();
    let warnings: Vec<_> = shown
        .iter()
        .filter(|d| d.severity == Severity::Warning)
        .map(|d| render::human(&name, &loaded.text, std::slice::from_ref(d), false))
        .collect();
    match (emitted, overlay_errors) {
        (Some(code), None) => Ok((code, warnings)),
        (None, overlay) => Err(render::human(&name, &loaded.text, &shown, false)
            + overlay.as_deref().unwrap_or_default()),
        (Some(_), Some(overlay)) => Err(overlay),
    }
}
