//! `phalanx completions`: a shell's completion script.

use super::out;
use crate::error::Error;
use clap_complete::Shell;

/// Print the completion script for a shell
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  phalanx completions bash > ~/.local/share/bash-completion/completions/phalanx\n  phalanx completions zsh > ~/.zfunc/_phalanx\n  phalanx completions fish > ~/.config/fish/completions/phalanx.fish\n  phalanx completions powershell >> $PROFILE"
)]
pub(crate) struct Args {
    /// The shell
    #[arg(value_enum)]
    shell: Shell,
}

/// Writes the script completing `cmd` (the whole command line) to standard output.
pub(crate) fn run(args: &Args, cmd: clap::Command) -> Result<i32, Error> {
    out::print(&script(args.shell, cmd))?;
    Ok(0)
}

/// The completion script of `cmd` for `shell`.
fn script(shell: Shell, mut cmd: clap::Command) -> Vec<u8> {
    let mut script = Vec::new();
    clap_complete::generate(shell, &mut cmd, "phalanx", &mut script);
    script
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::Cli;
    use clap::CommandFactory;

    #[test]
    fn every_shell_completes_every_command_and_an_option() {
        let commands = [
            "stats",
            "check",
            "coverage",
            "report",
            "add",
            "place",
            "audit",
            "synth",
            "snapshot",
            "history",
            "completions",
            "man",
        ];
        for shell in [Shell::Bash, Shell::Zsh, Shell::Fish, Shell::PowerShell] {
            let text = String::from_utf8(script(shell, Cli::command())).unwrap();
            for c in commands {
                assert!(text.contains(c), "{shell}: no '{c}' in the script");
            }
            assert!(text.contains("resamples"), "{shell}: no --resamples");
        }
    }
}
