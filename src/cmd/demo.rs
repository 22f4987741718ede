//! `edsgen demo`: the bundled cards at work on the in-memory bus (see the library's `demo`
//! module); exit 0 only if every step behaved as the manuals say.

use std::process::ExitCode;

use super::print_stdout;

/// Runs the demo, prints its trace and summary.
pub fn run() -> ExitCode {
    let report = edsgen::demo::run();
    let mut text = report.lines.join("\n");
    let failed = report.steps.iter().filter(|s| s.outcome.is_err()).count();
    text.push_str(&format!(
        "\n\n{} step(s): {} as the manuals say, {failed} not\n",
        report.steps.len(),
        report.steps.len() - failed
    ));
    print_stdout(&text);
    if report.passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
