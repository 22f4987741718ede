//! `edsgen generate`: the module build.rs would write for one device, overlay included.

use std::path::Path;
use std::process::ExitCode;

use edsgen_codegen::builder;
use edsgen_model::lint::Policy;
use edsgen_model::load;

use super::{fail, print_stdout};

/// Runs `edsgen generate FILE [-o OUT] [--module NAME] [--device NAME|#xCODE]`.
pub fn run(
    path: &Path,
    output: Option<&Path>,
    module: Option<&str>,
    device: Option<&str>,
) -> ExitCode {
    if !path.is_file() {
        return fail(format!("cannot read `{}`: not a file", path.display()));
    }
    let module = module.map_or_else(|| builder::default_module(path), str::to_owned);
    let mut loaded = match load::load(path, device) {
        Ok(loaded) => loaded,
        Err(err) => {
            eprintln!("error: edsgen: {err}");
            return ExitCode::from(1);
        }
    };
    // What build.rs runs (`generate_chosen_device` loads, then this), overlay included: the
    // output is what build.rs would write.
    let generated = builder::generate_loaded(path, &mut loaded, &module, &Policy::new());
    // The process ends with this command: the model's thousands of allocations are not freed
    // one by one (that was a twentieth of the command's instructions).
    std::mem::forget(loaded);
    let code = match generated {
        Ok((code, warnings)) => {
            for warning in warnings {
                eprint!("{warning}");
            }
            code
        }
        Err(errors) => {
            eprint!("{errors}");
            return ExitCode::from(1);
        }
    };
    match output {
        Some(out) => match std::fs::write(out, code) {
            Ok(()) => ExitCode::SUCCESS,
            Err(err) => fail(format!("cannot write `{}`: {err}", out.display())),
        },
        None => {
            print_stdout(&code);
            ExitCode::SUCCESS
        }
    }
}
