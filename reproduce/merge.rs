//! Merge the output folders of sharded figure runs (the ensemble runner,
//! `granular_automata::ensemble`): copies every per-run file of
//! `SHARD_DIR/<binary>/runs/` into `--out`, checking that runs present twice
//! are byte-identical. Then rerun the figure with `--out` and without
//! `--shard`: it finds every run done and only analyses.
//!
//! `cargo run --release --bin merge -- --out results parts/0 parts/1 parts/2`

use clap::Parser;
use granular_automata::ensemble::merge;
use std::path::PathBuf;

#[derive(Parser)]
#[command(about = "Merge shard output folders (--shard i/n runs) into one --out folder")]
struct Args {
    /// The folder to merge into (the --out of the final, unsharded run).
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// The --out folders of the shards.
    #[arg(required = true)]
    shards: Vec<PathBuf>,
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let r = merge(&a.out, &a.shards)?;
    println!(
        "merged {} shard folders into {}: {} run files copied, {} already present and identical",
        a.shards.len(),
        a.out.display(),
        r.copied,
        r.identical
    );
    Ok(())
}
