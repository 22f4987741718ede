//! The project's python venv for the examples and benches that time python `canopen` beside
//! edsgen: `scripts/python-venv.sh`, the one place that knows where it is and what it holds,
//! creates or completes it and names its python.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The venv's python, with the pinned `canopen` and `python-can`, or why there is none.
pub fn python() -> Result<PathBuf, String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/python-venv.sh");
    let out = Command::new(&script)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("no python venv: cannot run {}: {e}", script.display()))?;
    if !out.status.success() {
        return Err(format!(
            "no python venv: scripts/python-venv.sh failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()))
}
