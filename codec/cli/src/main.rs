//! `j2735`: SAE J2735 MessageFrames on the command line.
//!
//! - `j2735 decode`: UPER (hex lines or binary, bare or in an IEEE 1609.2 envelope or an RSU
//!   text record) to JER, one line per frame.
//! - `j2735 encode`: JER to UPER hex, bare, as 1609.2 unsecured data or as RSU 4.1 records.
//! - `j2735 info`: a short human summary per frame (MAP lanes, TIM regions and ITIS codes).
//!
//! A frame that fails never stops the others: it gets an error line in its place and the
//! exit status becomes 1. Usage errors and unreadable input exit with 2.
#![forbid(unsafe_code)]

mod args;
mod decode;
mod encode;
mod help;
mod info;
mod input;
mod itis;
mod messages;
mod output;
mod usage;

use std::io::{self, BufWriter, Write};
use std::process::ExitCode;

use args::{ArgError, Command, Source};
use output::Outcome;

/// Why a command could not run (to the end).
enum Failure {
    /// The command line is wrong.
    Usage(ArgError),
    /// The input could not be read.
    Input(String),
    /// The output could not be written.
    Output(io::Error),
}

impl From<io::Error> for Failure {
    fn from(error: io::Error) -> Self {
        Self::Output(error)
    }
}

fn main() -> ExitCode {
    let args: Vec<std::ffi::OsString> = std::env::args_os().skip(1).collect();
    let result = usage::parse(&args).map_err(Failure::Usage).and_then(run);
    match result {
        Ok(Outcome::AllDone) => ExitCode::SUCCESS,
        Ok(Outcome::SomeFailed) => ExitCode::from(1),
        Err(failure) => report(failure),
    }
}

/// Says on standard error why the command could not run; exit status 2.
fn report(failure: Failure) -> ExitCode {
    match failure {
        Failure::Usage(e) => eprintln!("j2735: error: {}\nhint: {}", e.message, e.hint),
        Failure::Input(message) => eprintln!("j2735: error: {message}"),
        Failure::Output(e) => eprintln!("j2735: error: cannot write the output: {e}"),
    }
    ExitCode::from(2)
}

/// Runs one parsed command, writing to standard output.
fn run(command: Command) -> Result<Outcome, Failure> {
    let mut out = BufWriter::new(io::stdout().lock());
    let result = execute(command, &mut out).and_then(|outcome| {
        out.flush()?;
        Ok(outcome)
    });
    match result {
        // A closed pipe (`j2735 decode big.hex | head`) ends the output quietly.
        Err(Failure::Output(e)) if e.kind() == io::ErrorKind::BrokenPipe => Ok(Outcome::AllDone),
        other => other,
    }
}

/// Runs `command`, writing to `out`.
fn execute(command: Command, out: &mut dyn Write) -> Result<Outcome, Failure> {
    match command {
        Command::Help(text) => write!(out, "{text}")?,
        Command::Decode(options) => {
            let items = input::frames(&read(&options.source)?, &options);
            return Ok(decode::run(items, out)?);
        }
        Command::Info(options) => {
            let items = input::frames(&read(&options.source)?, &options);
            return Ok(info::run(items, out)?);
        }
        Command::Encode(options) => {
            let text = String::from_utf8_lossy(&read(&options.source)?).into_owned();
            return Ok(encode::run(&text, &options, out)?);
        }
    }
    Ok(Outcome::AllDone)
}

/// The whole input, or an error that names it and says what to do.
fn read(source: &Source) -> Result<Vec<u8>, Failure> {
    input::read_all(source).map_err(|e| {
        Failure::Input(match source {
            Source::File(path) => format!(
                "cannot read {}: {e}\nhint: give an existing file, or - for standard input",
                path.display()
            ),
            Source::Stdin => format!("cannot read standard input: {e}"),
        })
    })
}
