//! The WGSL sources. WGSL has no includes, so the trace kernel is the
//! concatenation of its parts, in dependency order.

/// Files of the trace kernel, in the order they are concatenated (after the
/// declarations generated from [`super::bindings`]).
pub const TRACE_PARTS: [(&str, &str); 12] = [
    ("types.wgsl", include_str!("../../shaders/types.wgsl")),
    (
        "frame_params.wgsl",
        include_str!("../../shaders/frame_params.wgsl"),
    ),
    ("variant.wgsl", include_str!("../../shaders/variant.wgsl")),
    ("chunks.wgsl", include_str!("../../shaders/chunks.wgsl")),
    (
        "intersect.wgsl",
        include_str!("../../shaders/intersect.wgsl"),
    ),
    (
        "walk_step.wgsl",
        include_str!("../../shaders/walk_step.wgsl"),
    ),
    ("traverse.wgsl", include_str!("../../shaders/traverse.wgsl")),
    (
        "traverse_ropes.wgsl",
        include_str!("../../shaders/traverse_ropes.wgsl"),
    ),
    (
        "traverse_short_stack.wgsl",
        include_str!("../../shaders/traverse_short_stack.wgsl"),
    ),
    ("shade.wgsl", include_str!("../../shaders/shade.wgsl")),
    ("trace.wgsl", include_str!("../../shaders/trace.wgsl")),
    ("query.wgsl", include_str!("../../shaders/query.wgsl")),
];

/// Entry point that renders a tile to 8-bit colour (all samples of each pixel).
pub const TRACE_ENTRY_POINT: &str = "render_tile";
/// Entry point that adds one stratified sample per pixel to the accumulation
/// buffer (binding 9), for progressive refinement.
pub const ACCUMULATE_ENTRY_POINT: &str = "accumulate_tile";
/// Workgroup size of both entry points (see `@workgroup_size` in trace.wgsl).
pub const TRACE_WORKGROUP: (u32, u32) = (8, 8);
/// Entry point that traces given rays and writes their hits (tests, debugging).
pub const QUERY_ENTRY_POINT: &str = "trace_rays";
/// Its workgroup size (rays per workgroup, see query.wgsl).
pub const QUERY_WORKGROUP: u32 = 64;

/// The interactive window's present pass (fullscreen triangle over the
/// accumulation buffer), a module of its own.
pub const PRESENT_SOURCE: &str = include_str!("../../shaders/present.wgsl");
/// Its entry points.
pub const PRESENT_VERTEX_ENTRY_POINT: &str = "vs_main";
pub const PRESENT_FRAGMENT_ENTRY_POINT: &str = "fs_main";

/// The trace kernel as a shader module on `device`.
///
/// naga's bounds checks stay on: buffer indices come from the scene's
/// buffers, and a wrong one must not read outside them. Its forced loop
/// bounds (a counter added to every loop, so that a loop the compiler cannot
/// prove finite cannot hang the GPU) are off, because every loop of the
/// kernel ends by construction: k-d restarts (and the short stack's leaves,
/// which it may leave inside its descent loop) are capped at `node_count +
/// 1`; each descent step moves to a higher node index (children follow their
/// parent in the flat layout, `flat_layout_is_what_the_kernel_assumes` in
/// tests/kdtree_props/), and an index past the end is clamped to the last
/// node, a leaf; leaf, brute-force, light, sample and chunk (chunks.wgsl)
/// loops run over counts;
/// the reflection loop over `max_depth`. The counters cost 6-10% of the
/// frame on lavapipe (docs/benchmarks.md).
pub fn trace_module(device: &wgpu::Device) -> wgpu::ShaderModule {
    let desc = wgpu::ShaderModuleDescriptor {
        label: Some("trace"),
        source: wgpu::ShaderSource::Wgsl(
            trace_source(super::bindings::scene_chunks(&device.limits())).into(),
        ),
    };
    let checks = wgpu::ShaderRuntimeChecks {
        force_loop_bounding: false,
        ..wgpu::ShaderRuntimeChecks::checked()
    };
    // SAFETY: turning a runtime check off makes what it guarded undefined
    // behaviour. Only the loop bounds are off, and every loop of the kernel
    // terminates on its own (above).
    unsafe { device.create_shader_module_trusted(desc, checks) }
}

/// The whole trace kernel as one WGSL module, with `chunks` bindings per
/// split array: the generated contract, then the files.
pub fn trace_source(chunks: super::bindings::SceneChunks) -> String {
    let mut source = format!(
        "// ---- bindings.rs\n{}\n",
        super::bindings::wgsl_contract(chunks)
    );
    for (name, text) in TRACE_PARTS {
        source += &format!("// ---- {name}\n{text}\n");
    }
    source
}

#[cfg(test)]
pub(crate) use tests::parse_and_validate;

#[cfg(test)]
mod tests {
    use super::*;
    use naga::valid::{Capabilities, ValidationFlags, Validator};

    pub(crate) fn parse_and_validate(source: &str) -> (naga::Module, naga::valid::ModuleInfo) {
        let module = naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        let info = Validator::new(ValidationFlags::all(), Capabilities::empty())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        (module, info)
    }

    #[test]
    fn trace_kernel_parses_and_validates() {
        let (module, _) = parse_and_validate(&trace_source(
            [super::super::bindings::MAX_CHUNKS; super::super::bindings::SPLIT_ARRAY_COUNT],
        ));
        let entry = module
            .entry_points
            .iter()
            .find(|e| e.name == TRACE_ENTRY_POINT)
            .expect("entry point");
        assert_eq!(
            entry.workgroup_size,
            [TRACE_WORKGROUP.0, TRACE_WORKGROUP.1, 1]
        );
        let query = module
            .entry_points
            .iter()
            .find(|e| e.name == QUERY_ENTRY_POINT)
            .expect("query entry point");
        assert_eq!(query.workgroup_size, [QUERY_WORKGROUP, 1, 1]);
    }

    /// Each entry point copies the frame's parameters into the private
    /// `params` before anything else (shaders/frame_params.wgsl): read
    /// after a branch, it would still be right, but every read of a
    /// uniform there costs llvmpipe a load per lane.
    #[test]
    fn every_entry_point_reads_the_frame_params_first() {
        let (module, _) = parse_and_validate(&trace_source(
            [super::super::bindings::MAX_CHUNKS; super::super::bindings::SPLIT_ARRAY_COUNT],
        ));
        assert!(module.entry_points.len() >= 3);
        for entry in &module.entry_points {
            let first = entry
                .function
                .body
                .iter()
                .find(|s| !matches!(s, naga::Statement::Emit(_)));
            let called = match first {
                Some(naga::Statement::Call { function, .. }) => {
                    module.functions[*function].name.as_deref()
                }
                _ => None,
            };
            assert_eq!(called, Some("read_params"), "entry point {}", entry.name);
        }
    }

    /// Every .wgsl file in shaders/ is part of a validated module.
    #[test]
    fn every_shader_file_is_validated() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        let mut validated: Vec<&str> = TRACE_PARTS.iter().map(|(name, _)| *name).collect();
        validated.extend(crate::gpu::STANDALONE_SHADERS.iter().map(|(name, _)| *name));
        for (_, source) in crate::gpu::STANDALONE_SHADERS {
            parse_and_validate(source);
        }
        for entry in std::fs::read_dir(&dir).unwrap() {
            let name = entry.unwrap().file_name().into_string().unwrap();
            if name.ends_with(".wgsl") {
                assert!(
                    validated.contains(&name.as_str()),
                    "{name} is not validated by any test"
                );
            }
        }
    }
}
