#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! `vref-perception-feed` as a user meets it: help, refusals with exit code 2, and a
//! clean stop on SIGTERM.

use vref_scene::Side;
use vref_testkit::feed_cli;

const BIN: &str = env!("CARGO_BIN_EXE_vref-perception-feed");

#[test]
fn help_lists_every_flag() {
    feed_cli::help_lists_every_flag(BIN);
}

#[test]
fn bad_sources_and_settings_exit_2_naming_the_problem() {
    feed_cli::bad_sources_and_settings_exit_2_naming_the_problem(BIN);
}

#[test]
fn it_publishes_until_sigterm_then_exits_0() {
    feed_cli::publishes_until_sigterm_then_exits_0(BIN, "pf", "robot_camera", Side::Robot);
}
