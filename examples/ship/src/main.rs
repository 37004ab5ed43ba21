//! `ship replay DIR [--out OUT] [--json] [--smooth]`: the ship's replay program.

fn main() -> std::process::ExitCode {
    nav_replay::program::replay_main::<ship::Ship, { ship::N }>()
}
