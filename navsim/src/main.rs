//! `navsim`: simulation, Monte Carlo evaluation and log replay (see `navsim::cli`).

fn main() -> std::process::ExitCode {
    navsim::cli::main()
}
