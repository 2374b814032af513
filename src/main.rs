use clap::Parser;

fn main() {
    let cli = printwatt::cli::Cli::parse();
    if let Err(e) = printwatt::cli::run(cli) {
        eprintln!("error: {}", printwatt::error::clip(&format!("{e:#}")));
        std::process::exit(1);
    }
}
