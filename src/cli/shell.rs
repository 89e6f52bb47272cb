//! `footslam completions SHELL` and `footslam man`: shell completions and manual pages,
//! generated from the command line's own definition (clap), so they never drift from it.

use anyhow::{Context, Result};
use clap::CommandFactory;
use std::path::PathBuf;

/// Arguments of `footslam completions`.
#[derive(Debug, clap::Args)]
pub struct CompletionArgs {
    /// The shell: bash, zsh, fish, elvish or powershell. Install, e.g. for bash:
    /// `footslam completions bash > ~/.local/share/bash-completion/completions/footslam`.
    #[arg(value_enum)]
    shell: clap_complete::Shell,
}

/// Arguments of `footslam man`.
#[derive(Debug, clap::Args)]
pub struct ManArgs {
    /// Folder for the pages: `footslam.1` and one `footslam-COMMAND.1` per command (e.g.
    /// `--out ~/.local/share/man/man1`, then `man footslam-learn`).
    #[arg(short = 'o', long, value_name = "DIR", default_value = "man")]
    out: PathBuf,
}

/// Prints the completion script on stdout.
pub fn completions(args: &CompletionArgs) -> Result<()> {
    let mut cmd = super::Cli::command();
    clap_complete::generate(args.shell, &mut cmd, "footslam", &mut std::io::stdout());
    Ok(())
}

/// Writes the manual pages into `--out`.
pub fn man(args: &ManArgs) -> Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating --out {}", args.out.display()))?;
    let cmd = super::Cli::command();
    clap_mangen::generate_to(cmd, &args.out)
        .with_context(|| format!("writing the manual pages into {}", args.out.display()))?;
    info!("wrote the manual pages into {}", args.out.display());
    Ok(())
}
