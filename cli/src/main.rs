//! The `threadcut` command. Only this binary prints or exits: 0 ok, 1 other failures, 2 bad input.

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::main()
}
