//! `vref`: the command line of vref.
//!
//! Exit codes: the rule of every binary (vref_logging::exit): 0 success,
//! 1 failure while running, 2 bad input (usage, configuration, data set);
//! `vref query` also 3, 4 and 5 for a bad_request, not_ready or stale
//! answer (query.rs, exit_code).

mod bench;
mod bench_client;
mod bench_perception;
mod bench_plot;
mod bench_query;
mod bench_remote;
mod bench_ros2;
mod bench_segment;
mod bench_solver;
mod cli;
mod config_cmd;
mod demo;
mod eval;
mod harness;
mod import;
mod inject;
mod match_frames;
mod progress;
mod query;
mod record;
mod scenes;
mod segment;
mod soak;
mod stdout;
mod sweep;
mod table;
mod up;
mod view;
mod viz;
mod wire_layout;

use std::process::ExitCode;

use clap::Parser;
use vref_logging::exit::{Blame, Failure};

use crate::cli::{BenchCommand, Cli, Command, ConfigCommand, ImportCommand};

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Zenoh warns of every failed connection attempt before its error
    // reaches vref, which then says the same once: its own warnings only
    // with RUST_LOG.
    vref_logging::init("warn,zenoh=error");
    match vref_match::check_simd_setting()
        .bad_input()
        .and_then(|()| run(cli.command))
    {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("vref: {:#}", failure.error());
            failure.exit_code()
        }
    }
}

fn run(command: Command) -> Result<(), Failure> {
    match command {
        Command::Eval(args) => eval::run(&args),
        Command::Import(ImportCommand::CmuHouse(args)) => import::cmu_house(&args),
        Command::Import(ImportCommand::Bop(args)) => import::bop(&args),
        Command::Config(ConfigCommand::Check(args)) => config_cmd::check(&args),
        Command::Scenes(args) => scenes::run(&args),
        Command::Viz(args) => viz::run(&args),
        Command::Query(args) => query::run(&args),
        Command::Record(args) => record::run(&args),
        Command::View(args) => view::run(&args),
        Command::Inject(args) => inject::run(&args),
        Command::Demo(args) => demo::run(&args),
        Command::Soak(args) => soak::run(&args),
        Command::Up(args) => up::run(&args),
        Command::Segment(args) => segment::run(&args),
        Command::Match(args) => match_frames::run(&args),
        Command::Bench(BenchCommand::Solver(args)) => bench::solver(&args),
        Command::Bench(BenchCommand::Query(args)) => bench_query::query(&args),
        Command::Bench(BenchCommand::Remote(args)) => bench_remote::remote(&args),
        Command::Bench(BenchCommand::Plot(args)) => bench_plot::plot(&args),
        Command::Bench(BenchCommand::Perception(args)) => bench_perception::perception(&args),
        Command::Bench(BenchCommand::Segment(args)) => bench_segment::segment(&args),
        Command::Bench(BenchCommand::Ros2(args)) => bench_ros2::ros2(&args),
        Command::Bench(BenchCommand::Client(args)) => bench_client::run(&args),
        Command::Bench(BenchCommand::EchoServer(args)) => bench_query::echo_server(&args),
        Command::WireLayout(args) => wire_layout::run(&args),
    }
}
