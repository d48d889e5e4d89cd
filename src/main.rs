//! The `phalanx` command: see `phalanx --help`.

fn main() {
    std::process::exit(phalanx::cli::main());
}
