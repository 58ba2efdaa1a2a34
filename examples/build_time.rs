//! Times the k-d tree build of a scene file, apart from loading it, in
//! wall and CPU time (CPU time holds up better on a shared machine):
//! `cargo run --release --example build_time -- SCENE [THREADS] [sah|binned|median|exact]`,
//! where `exact` is the default build with every event a candidate at every
//! scene size (`BuildParams::bin_past_objects` unbounded).
//! The digest it prints changes when the tree does, so a faster build can
//! show that it builds the same tree. `EXACT_BELOW=N` and
//! `TRAVERSAL_COST=C` override those build parameters, for experiments.
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: build_time SCENE [THREADS]")?;
    let threads: usize = args.next().map_or(Ok(2), |t| t.parse())?;
    let name = args.next().unwrap_or_else(|| "sah".into());
    let (strategy, bin_past_objects) = match name.as_str() {
        "exact" => (kdray::kdtree::BuildStrategy::Sah, usize::MAX),
        other => match kdray::choice::Choice::from_name(other) {
            Some(strategy) => (strategy, kdray::kdtree::BINNED_PAST_OBJECTS),
            None => return Err(format!("unknown build {other:?}").into()),
        },
    };
    let t = Instant::now();
    let scene = kdray::scene::load_scene(std::path::Path::new(&path))?;
    let prims = kdray::geometry::Primitives::from_scene(&scene);
    let load_s = t.elapsed().as_secs_f64();
    let params = kdray::kdtree::BuildParams {
        strategy,
        bin_past_objects,
        ..kdray::kdtree::BuildParams::for_primitives(&prims)
    };
    let params = match std::env::var("EXACT_BELOW") {
        Ok(v) => kdray::kdtree::BuildParams {
            exact_below: v.parse()?,
            ..params
        },
        Err(_) => params,
    };
    let params = match std::env::var("TRAVERSAL_COST") {
        Ok(v) => kdray::kdtree::BuildParams {
            traversal_cost: v.parse()?,
            ..params
        },
        Err(_) => params,
    };
    let (t, cpu) = (Instant::now(), cpu_seconds());
    let tree = kdray::kdtree::build_primitives(&prims, params, threads);
    let build_s = t.elapsed().as_secs_f64();
    let build_cpu_s = cpu_seconds() - cpu;
    let stats = tree.stats();
    println!(
        "{path}: {} objects, load {load_s:.3} s, {} build on {threads} threads {build_s:.3} s ({build_cpu_s:.2} s of CPU), {} nodes, {} references, SAH cost {:.1}, digest {:016x}",
        prims.len(),
        name,
        stats.nodes,
        tree.leaf_objects.len(),
        tree.sah_cost(&params),
        digest(&tree)
    );
    Ok(())
}

/// FNV-1a over the flat nodes and leaf lists: equal digests mean a faster
/// build made the same tree.
fn digest(tree: &kdray::kdtree::KdTree) -> u64 {
    let words = tree
        .nodes
        .iter()
        .flat_map(|n| [n.kind, n.split.to_bits(), n.index, n.count])
        .chain(tree.leaf_objects.iter().copied());
    words.fold(0xcbf2_9ce4_8422_2325, |h, w| {
        (h ^ w as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// User + system CPU time of this process so far, from /proc (Linux; 0
/// elsewhere): unlike wall time, it does not grow when other processes
/// share the cores.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name, which is in parentheses.
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or(vec![], |(_, rest)| rest.split_whitespace().collect());
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    // utime and stime are fields 14 and 15 of the line, 12 and 13 here; the
    // clock tick is 1/100 s on Linux.
    (ticks(11) + ticks(12)) / 100.0
}
