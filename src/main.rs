use clap::Parser;

fn main() {
    let cli = printwatt::cli::Cli::parse();
    if let Err(e) = printwatt::cli::run(cli) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
