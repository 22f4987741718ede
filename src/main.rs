//! The `edsgen` command line: validate, dump, generate, and list the rules.
//!
//! Exit codes (design.md): 0 clean, 1 the input has errors (or warnings under `--deny
//! warnings`), 2 usage or I/O problems.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use edsgen_codegen::diag::{self, Severity};
use edsgen_codegen::{builder, read, render, rules, validate};

mod cmd;

#[derive(Parser)]
#[command(
    name = "edsgen",
    version,
    about = "Typed Rust from CANopen device descriptions (EDS, DCF, XDD, XDC)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check description files against CiA 306 / CiA 311 and print diagnostics.
    Validate {
        /// Output format.
        #[arg(long, value_enum, default_value_t = OutputFormat::Human)]
        format: OutputFormat,
        /// Treat warnings as errors (`--deny warnings`).
        #[arg(long, value_enum)]
        deny: Vec<Deny>,
        /// Description files (.eds, .dcf, .xdd, .xdc).
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Print the resolved model of one file as JSON.
    Dump {
        /// Output format (only JSON).
        #[arg(long, value_enum, default_value_t = DumpFormat::Json)]
        format: DumpFormat,
        /// The description file.
        file: PathBuf,
    },
    /// Generate the Rust module build.rs would produce for one device.
    Generate {
        /// The description file.
        file: PathBuf,
        /// Write to this file instead of standard output.
        #[arg(short = 'o', long = "output")]
        output: Option<PathBuf>,
        /// The module name (default: from the file name).
        #[arg(long)]
        module: Option<String>,
    },
    /// List every validation rule: code, severity and meaning.
    Rules {
        /// Output format.
        #[arg(long, value_enum, default_value_t = OutputFormat::Human)]
        format: OutputFormat,
    },
    /// Read or write an entry of a node on a live bus (SDO).
    Sdo {
        #[command(subcommand)]
        command: cmd::sdo::SdoCommand,
    },
    /// Send an NMT command to a node or to all nodes.
    Nmt {
        #[command(flatten)]
        bus: cmd::BusArgs,
        /// The command.
        #[arg(value_enum)]
        verb: cmd::nmt::NmtVerb,
        /// The node-ID, or `all`.
        node: String,
    },
    /// Find the nodes on a bus: node-ID, NMT state and identity.
    Scan {
        #[command(flatten)]
        bus: cmd::BusArgs,
    },
    /// Compare a live device with its description (every readable entry, and its identity).
    Check(cmd::check::CheckArgs),
    /// Run a CAN bus on TCP (a socketcand hub for python-can and edsgen) until Ctrl-C.
    Bus(cmd::bus::BusArgs),
}

#[derive(Clone, Copy, ValueEnum)]
enum OutputFormat {
    Human,
    Json,
}

#[derive(Clone, Copy, ValueEnum)]
enum DumpFormat {
    Json,
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
enum Deny {
    Warnings,
}

/// Exit code for usage and I/O problems.
const EXIT_USAGE: u8 = 2;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => {
            let _ = err.print();
            return match err.kind() {
                clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion => {
                    ExitCode::SUCCESS
                }
                _ => ExitCode::from(EXIT_USAGE),
            };
        }
    };
    match cli.command {
        Command::Validate {
            format,
            deny,
            files,
        } => cmd_validate(format, deny.contains(&Deny::Warnings), &files),
        Command::Dump { format: _, file } => cmd_dump(&file),
        Command::Generate {
            file,
            output,
            module,
        } => cmd_generate(&file, output.as_deref(), module.as_deref()),
        Command::Rules { format } => cmd_rules(format),
        Command::Sdo { command } => cmd::sdo::run(&command),
        Command::Nmt { bus, verb, node } => cmd::nmt::run(&bus, verb, &node),
        Command::Scan { bus } => cmd::scan::run(&bus),
        Command::Check(args) => cmd::check::run(&args),
        Command::Bus(args) => cmd::bus::run(&args),
    }
}

/// Writes to standard output, ignoring a closed pipe (`edsgen dump f.eds | head` must not panic).
fn print_stdout(text: &str) {
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(EXIT_USAGE)
}

fn cmd_validate(format: OutputFormat, deny_warnings: bool, files: &[PathBuf]) -> ExitCode {
    let color = std::io::stdout().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    let mut failed = false;
    let mut io_error = false;
    let mut all_json = Vec::new();
    let (mut errors, mut warnings) = (0usize, 0usize);
    let mut out = std::io::stdout().lock();
    for path in files {
        let read = match read::read_file(path) {
            Ok(read) => read,
            Err(err) => {
                eprintln!("error: {err}");
                io_error = true;
                continue;
            }
        };
        let mut diags = read.diagnostics;
        diags.extend(validate::validate(&read.device));
        diag::sort(&mut diags);
        for d in &diags {
            match d.severity {
                Severity::Error => errors += 1,
                Severity::Warning => warnings += 1,
                Severity::Info => {}
            }
        }
        failed |= diags.iter().any(|d| {
            d.severity == Severity::Error || (deny_warnings && d.severity == Severity::Warning)
        });
        let name = path.display().to_string();
        match format {
            OutputFormat::Human => {
                let _ = out.write_all(render::human(&name, &read.text, &diags, color).as_bytes());
            }
            OutputFormat::Json => all_json.extend(render::json(&name, &diags)),
        }
    }
    match format {
        OutputFormat::Human => {
            let _ = writeln!(
                out,
                "{} file(s) checked: {errors} error(s), {warnings} warning(s)",
                files.len()
            );
        }
        OutputFormat::Json => {
            let text = serde_json::to_string_pretty(&all_json).unwrap_or_else(|_| "[]".into());
            let _ = writeln!(out, "{text}");
        }
    }
    if io_error {
        ExitCode::from(EXIT_USAGE)
    } else if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

fn cmd_dump(path: &std::path::Path) -> ExitCode {
    let read = match read::read_file(path) {
        Ok(read) => read,
        Err(err) => return fail(err),
    };
    let json = edsgen_codegen::dump::to_json(&read.device);
    match serde_json::to_string_pretty(&json) {
        Ok(text) => {
            print_stdout(&format!("{text}\n"));
            ExitCode::SUCCESS
        }
        Err(err) => fail(err),
    }
}

fn cmd_generate(
    path: &std::path::Path,
    output: Option<&std::path::Path>,
    module: Option<&str>,
) -> ExitCode {
    if !path.is_file() {
        return fail(format!("cannot read `{}`: not a file", path.display()));
    }
    let module = module.map_or_else(|| builder::default_module(path), str::to_owned);
    // The same function build.rs runs, overlay included: the output is what build.rs would write.
    let code = match builder::generate_device(path, &module, &[]) {
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

fn cmd_rules(format: OutputFormat) -> ExitCode {
    match format {
        OutputFormat::Human => {
            let table: String = rules::ALL
                .iter()
                .map(|rule| {
                    format!(
                        "{}  {:<7}  {}\n",
                        rule.code,
                        rule.severity.as_str(),
                        rule.summary
                    )
                })
                .collect();
            print_stdout(&table);
        }
        OutputFormat::Json => {
            let list: Vec<_> = rules::ALL
                .iter()
                .map(|r| {
                    serde_json::json!({"code": r.code, "severity": r.severity.as_str(), "summary": r.summary})
                })
                .collect();
            print_stdout(&format!(
                "{}\n",
                serde_json::to_string_pretty(&list).unwrap_or_else(|_| "[]".into())
            ));
        }
    }
    ExitCode::SUCCESS
}
