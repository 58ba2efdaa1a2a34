//! `kdray bench` and `kdray generate` on the command line: the flags mapped
//! onto the library's options, the library's bench or generator run, and
//! what it did printed (the summary on stdout, notes on stderr).

use kdray::bench::generate::{is_big_toml, write_random_scene};
use kdray::bench::summary::markdown_summary;
use kdray::bench::{replot, run_bench, BenchOutcome};
use kdray::gpu::GpuContext;
use kdray::Result;

use crate::args::{BenchArgs, GenerateArgs};

/// `kdray bench`: measures (or, with `--replot`, rewrites the outputs of an
/// earlier run), writes the files, prints the summary on stdout.
pub fn bench(args: BenchArgs) -> Result<()> {
    let outcome = match &args.replot {
        Some(dir) => replot(dir)?,
        None => {
            let command = std::iter::once("kdray".to_string())
                .chain(std::env::args().skip(1))
                .collect::<Vec<_>>()
                .join(" ");
            let config = args.config(command).validated()?;
            let ctx = GpuContext::new()?;
            run_bench(&ctx, &config)?
        }
    };
    print_outcome(&outcome);
    Ok(())
}

fn print_outcome(outcome: &BenchOutcome) {
    println!("{}", markdown_summary(&outcome.report));
    println!("Files written:");
    for f in &outcome.files {
        println!("  {}", f.display());
    }
}

/// `kdray generate`: writes one random scene as a scene file.
pub fn generate(args: GenerateArgs) -> Result<()> {
    let spec = args.spec();
    let scene = write_random_scene(&spec, &args.output)?;
    eprintln!(
        "kdray: wrote {} ({} spheres, {} triangles)",
        args.output.display(),
        scene.spheres.len(),
        scene.triangles.len()
    );
    if is_big_toml(&args.output, spec.count) {
        eprintln!(
            "kdray: note: a TOML scene this big loads slowly and needs about 30 bytes of memory \
             per byte of file; a name ending in .json writes JSON, which loads in one pass"
        );
    }
    Ok(())
}
