//! The `printwatt` command: a thin clap front end over the `printwatt` library. The CLI is
//! the binary's own module, not part of the library's API.

use clap::Parser;

mod cli;

fn main() {
    let cli = cli::Cli::parse();
    if let Err(e) = cli::run(cli) {
        eprintln!(
            "error: {}{}",
            printwatt::error::clip(&cli::error_text(&e)),
            hint(&e)
        );
        std::process::exit(1);
    }
}

/// The command-line words for a library error: the library names no flags, the binary does.
fn hint(e: &anyhow::Error) -> &'static str {
    for c in e.chain() {
        match c.downcast_ref::<printwatt::Error>() {
            Some(printwatt::Error::OutputExists { .. }) => {
                return ": pass --force to replace it, or choose another --out"
            }
            Some(printwatt::Error::OutputRefused { .. }) => {
                return " (give another --out DIR; default: the current directory)"
            }
            Some(printwatt::Error::BadRunName { .. }) => {
                return " (--run names a directory inside --results-dir)"
            }
            _ => {}
        }
    }
    ""
}

#[cfg(test)]
mod tests {
    #[test]
    fn an_io_error_says_what_the_system_said_once() {
        let e = anyhow::Error::from(printwatt::Error::io(
            "wall.gcode",
            std::io::Error::from(std::io::ErrorKind::NotFound),
        ))
        .context("loading path wall.gcode");
        let t = super::cli::error_text(&e);
        assert_eq!(t, "loading path wall.gcode: wall.gcode: entity not found");
        // A cause that adds something is kept.
        let e = anyhow::anyhow!("inner").context("outer");
        assert_eq!(super::cli::error_text(&e), "outer: inner");
    }

    #[test]
    fn clap_definition_is_consistent() {
        use clap::CommandFactory;
        super::cli::Cli::command().debug_assert();
    }
}
