//! `navsim`: simulation, Monte Carlo evaluation and log replay (see `models::cli`).

fn main() -> std::process::ExitCode {
    models::cli::main()
}
