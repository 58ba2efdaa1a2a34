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
    if args.wavefront_bound {
        return wavefront_bound(&args);
    }
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

/// `kdray bench --wavefront-bound`: a table on stdout, the figures in
/// OUT/wavefront-bound.json.
fn wavefront_bound(args: &BenchArgs) -> Result<()> {
    let ctx = GpuContext::new()?;
    let mut all = Vec::new();
    println!("| scene | walk | megakernel Mrays/s | queue alone Mrays/s | megakernel / queue |");
    println!("| --- | --- | ---: | ---: | ---: |");
    for path in &args.scenes {
        let mut scene = kdray::scene::load_scene(path)?;
        scene.render.width = args.width.unwrap_or(scene.render.width);
        scene.render.height = args.height.unwrap_or(scene.render.height);
        scene.render.max_depth = args.max_depth.unwrap_or(scene.render.max_depth);
        let figures = kdray::bench::wavefront_bound::measure(&ctx, &scene, args.repeat)?;
        for f in &figures {
            println!(
                "| {} | {} | {:.2} | {:.2} | {:.2} |",
                path.display(),
                f.traversal,
                f.megakernel_mrays_per_s,
                f.queue_mrays_per_s,
                f.ratio
            );
        }
        all.push(serde_json::json!({
            "scene": path,
            "width": scene.render.width,
            "height": scene.render.height,
            "max_depth": scene.render.max_depth,
            "walks": figures,
        }));
    }
    let report = serde_json::json!({
        "command": std::env::args().collect::<Vec<_>>().join(" "),
        "adapter": ctx.info.name,
        "scenes": all,
    });
    std::fs::create_dir_all(&args.out).map_err(|e| kdray::Error::File {
        path: args.out.clone(),
        what: "cannot create the output folder",
        source: e,
    })?;
    let file = args.out.join("wavefront-bound.json");
    kdray::output::write_file_atomic(&file, serde_json::to_string_pretty(&report)?.as_bytes())?;
    eprintln!("kdray: wrote {}", file.display());
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
