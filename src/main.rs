//! The `printwatt` command: a thin clap front end over the `printwatt` library. The CLI is
//! the binary's own module, not part of the library's API.

use clap::Parser;

mod cli;

/// The exit status of a command whose reader closed the pipe: the shell's status of a process
/// ended by SIGPIPE (128 + 13), without a word.
const CLOSED_PIPE_STATUS: i32 = 141;

/// What a `println!` that failed left (its panic message), for the safety net in [`main`].
static STDOUT_PANIC: std::sync::Mutex<Option<String>> = std::sync::Mutex::new(None);

fn main() {
    let cli = cli::Cli::parse();
    // Results go through `cli::out_line`, whose errors take the error path below. A `println!`
    // left anywhere panics when standard output fails: that panic is not a crash to report
    // but the same failure, ended the same way (its stack unwinds, so staging directories and
    // locks are removed as for any error).
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if let Some(rest) = msg.strip_prefix("failed printing to stdout: ") {
            if let Ok(mut g) = STDOUT_PANIC.lock() {
                g.get_or_insert_with(|| rest.to_string());
            }
            return;
        }
        default_hook(info)
    }));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        cli::run(cli).and_then(|()| cli::flush_stdout())
    }));
    let result = match result {
        Ok(r) => r,
        Err(_) => {
            let failed = STDOUT_PANIC.lock().ok().and_then(|g| g.clone());
            match failed {
                Some(m) if m.contains("os error 32") || m.contains("Broken pipe") => {
                    std::process::exit(CLOSED_PIPE_STATUS)
                }
                Some(m) => {
                    eprintln!("error: writing to standard output: {m}");
                    std::process::exit(1)
                }
                // A real bug: the default hook has said where.
                None => std::process::exit(101),
            }
        }
    };
    if let Err(e) = result {
        if let Some(f) = e
            .chain()
            .find_map(|c| c.downcast_ref::<cli::StdoutFailed>())
        {
            if f.closed_pipe() {
                std::process::exit(CLOSED_PIPE_STATUS);
            }
            eprintln!("error: {f}");
            std::process::exit(1);
        }
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
