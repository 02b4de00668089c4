//! `orbifold`: classify, enumerate and (as the project grows) lay out, tile, build, trace and
//! render two-dimensional kaleidoscopic orbifolds and their mirror rooms.

mod args;
mod commands;
mod error;
mod output;
mod report;

use std::process::ExitCode;

use clap::Parser;

use crate::args::{Cli, Command};
use crate::error::CliError;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(args) => commands::info::run(&args),
        Command::Enumerate(args) => commands::enumerate::run(&args),
        Command::Layout(args) => commands::layout::run(&args),
        Command::Cover(args) => commands::cover::run(&args),
        Command::Tiling(args) => commands::tiling::run(&args),
        Command::Scene(command) => commands::scene::run(&command),
        Command::Room(args) => commands::room::run(&args),
        Command::Trace(args) => commands::trace::run(&args),
        Command::Render(args) => commands::render::run(&args),
        Command::Animate(args) => commands::animate::run(&args),
        Command::Preview(args) => commands::preview::run(&args),
        Command::Listen(args) => commands::listen::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(CliError::BrokenPipe) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("{error}");
            ExitCode::from(error.exit_code())
        }
    }
}
