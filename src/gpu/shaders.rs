//! The WGSL sources, each assembled with the declarations that
//! gpu/bindings/ generates. WGSL has no includes, so the trace kernel is
//! the generated contract followed by its files, in dependency order, and the
//! present pass is its generated bindings followed by shaders/present.wgsl.
//! The tests here read the assembled shaders with naga and hold them to the
//! contract.

use super::bindings::{self, SceneChunks};

/// Files of the trace kernel, in the order they are concatenated (after the
/// declarations generated from [`bindings`]).
pub const TRACE_PARTS: [(&str, &str); 27] = [
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
    (
        WALK_RECORD_OFF,
        include_str!("../../shaders/walk_record_off.wgsl"),
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
    ("texture.wgsl", include_str!("../../shaders/texture.wgsl")),
    ("surface.wgsl", include_str!("../../shaders/surface.wgsl")),
    ("alpha.wgsl", include_str!("../../shaders/alpha.wgsl")),
    ("glass.wgsl", include_str!("../../shaders/glass.wgsl")),
    (
        "environment.wgsl",
        include_str!("../../shaders/environment.wgsl"),
    ),
    ("random.wgsl", include_str!("../../shaders/random.wgsl")),
    ("bsdf.wgsl", include_str!("../../shaders/bsdf.wgsl")),
    (
        "bsdf_microfacet.wgsl",
        include_str!("../../shaders/bsdf_microfacet.wgsl"),
    ),
    (
        "bsdf_diffuse.wgsl",
        include_str!("../../shaders/bsdf_diffuse.wgsl"),
    ),
    (
        "bsdf_metal_rough.wgsl",
        include_str!("../../shaders/bsdf_metal_rough.wgsl"),
    ),
    (
        "bsdf_dielectric.wgsl",
        include_str!("../../shaders/bsdf_dielectric.wgsl"),
    ),
    (
        "bsdf_rough_dielectric.wgsl",
        include_str!("../../shaders/bsdf_rough_dielectric.wgsl"),
    ),
    ("emitters.wgsl", include_str!("../../shaders/emitters.wgsl")),
    ("path.wgsl", include_str!("../../shaders/path.wgsl")),
    ("trace.wgsl", include_str!("../../shaders/trace.wgsl")),
    ("query.wgsl", include_str!("../../shaders/query.wgsl")),
];

/// The render kernel's walk recorder, which records nothing; the inspect
/// kernel holds [`WALK_RECORD`] in its place.
const WALK_RECORD_OFF: &str = "walk_record_off.wgsl";
/// The inspect kernel's walk recorder and its entry point, `inspect_pixel`.
const WALK_RECORD: (&str, &str) = (
    "walk_record.wgsl",
    include_str!("../../shaders/walk_record.wgsl"),
);

/// The window's present pass (fullscreen triangle over the accumulation
/// buffers), a module of its own, without its generated bindings.
const PRESENT_FILE: &str = include_str!("../../shaders/present.wgsl");

/// The window's line overlay (world-space segments over the image), a
/// module of its own, without its generated binding.
const OVERLAY_FILE: &str = include_str!("../../shaders/overlay.wgsl");

/// Shader files compiled as modules of their own (not part of the trace
/// kernel), validated by the same tests.
pub const STANDALONE_SHADERS: [(&str, &str); 2] = [
    ("present.wgsl", PRESENT_FILE),
    ("overlay.wgsl", OVERLAY_FILE),
];

/// The kernel holding `entry` as naga reads it, with its validation: the
/// inspect kernel for `inspect_pixel`, else the trace kernel, with `chunks`
/// bindings per split array and each of `omitted` a private placeholder
/// ([`trace_source_without`]; none for the full kernel).
/// [`specialised_module`] makes each variant's module of it.
pub fn kernel_ir(
    entry: bindings::EntryPoint,
    chunks: SceneChunks,
    omitted: &[bindings::Binding],
) -> Result<(naga::Module, naga::valid::ModuleInfo), String> {
    let source = match entry == bindings::INSPECT_PIXEL {
        true => inspect_source_without(chunks, omitted),
        false => trace_source_without(chunks, omitted),
    };
    let module = naga::front::wgsl::parse_str(&source).map_err(|e| e.emit_to_string(&source))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(&source))?;
    Ok((module, info))
}

/// The module of `kernel` ([`kernel_ir`]) for the entry point `entry`,
/// specialised for `constants` (its overrides' values; with
/// `fold_branches`, gpu/specialise.rs folds away the code they rule out),
/// as a shader module on `device`.
///
/// naga's bounds checks stay on: buffer indices come from the scene's
/// buffers, and a wrong one must not read outside them. Its forced loop
/// bounds (a counter added to every loop, so that a loop the compiler cannot
/// prove finite cannot hang the GPU) are off, because every loop of the
/// kernel ends by construction: k-d restarts (and the short stack's leaves,
/// which it may leave inside its descent loop) are capped at `node_count +
/// 1`; each descent step moves to a higher node index (children follow their
/// parent in the flat layout, `flat_layout_is_what_the_kernel_assumes` in
/// crates/kdray-core/tests/kdtree_props/), and an index past the end is clamped to the last
/// node, a leaf; leaf, brute-force, light, sample and chunk (chunks.wgsl)
/// loops run over counts;
/// the reflection loop over `max_depth`. The counters cost 6-10% of the
/// frame on lavapipe (docs/benchmarks.md).
pub fn specialised_module(
    device: &wgpu::Device,
    kernel: &(naga::Module, naga::valid::ModuleInfo),
    entry: &str,
    constants: &[(&str, f64)],
    fold_branches: bool,
) -> Result<wgpu::ShaderModule, String> {
    let module =
        super::specialise::specialise(&kernel.0, &kernel.1, entry, constants, fold_branches)?;
    let desc = wgpu::ShaderModuleDescriptor {
        label: Some(entry),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
    };
    let checks = wgpu::ShaderRuntimeChecks {
        force_loop_bounding: false,
        ..wgpu::ShaderRuntimeChecks::checked()
    };
    // SAFETY: only the loop bounds are off, and every loop of the kernel
    // ends on its own (above).
    Ok(unsafe { device.create_shader_module_trusted(desc, checks) })
}

/// `source` as a module with naga's bounds checks on and its forced loop
/// bounds off. The caller's loops must each end on their own: turning a
/// runtime check off makes what it guarded undefined behaviour.
pub fn module_without_loop_bounds(
    device: &wgpu::Device,
    label: &str,
    source: &str,
) -> wgpu::ShaderModule {
    let desc = wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    };
    let checks = wgpu::ShaderRuntimeChecks {
        force_loop_bounding: false,
        ..wgpu::ShaderRuntimeChecks::checked()
    };
    // SAFETY: only the loop bounds are off, and the caller's loops end on
    // their own (this function's contract).
    unsafe { device.create_shader_module_trusted(desc, checks) }
}

/// The whole trace kernel as one WGSL module, with `chunks` bindings per
/// split array: the generated contract, then the files.
pub fn trace_source(chunks: SceneChunks) -> String {
    trace_source_without(chunks, &[])
}

/// [`trace_source`] with each of `omitted` (of
/// [`bindings::OPTIONAL_BINDINGS`]) a private placeholder, not a binding
/// ([`bindings::wgsl_contract_without`]): the kernel for frames that never
/// read them, on an adapter with fewer storage buffers per stage.
pub fn trace_source_without(chunks: SceneChunks, omitted: &[bindings::Binding]) -> String {
    let mut source = format!(
        "// ---- bindings/mod.rs\n{}\n",
        bindings::wgsl_contract_without(chunks, omitted)
    );
    for (name, text) in TRACE_PARTS {
        source += &format!("// ---- {name}\n{text}\n");
    }
    source
}

/// The inspect kernel: [`trace_source_without`] with the walk recorder of
/// shaders/walk_record.wgsl, its log binding and its entry point.
pub fn inspect_source_without(chunks: SceneChunks, omitted: &[bindings::Binding]) -> String {
    let mut source = format!(
        "// ---- bindings/mod.rs\n{}\n",
        bindings::wgsl_contract_of(&bindings::INSPECT_ENTRY_POINTS, chunks, omitted)
    );
    for (name, text) in TRACE_PARTS {
        let (name, text) = match name == WALK_RECORD_OFF {
            true => WALK_RECORD,
            false => (name, text),
        };
        source += &format!("// ---- {name}\n{text}\n");
    }
    source
}

/// The present pass: its generated bindings, then shaders/present.wgsl.
pub fn present_source() -> String {
    format!(
        "// ---- bindings/mod.rs\n{}\n// ---- present.wgsl\n{PRESENT_FILE}\n",
        bindings::wgsl_present_contract()
    )
}

/// The present pass as a shader module on `device`.
pub fn present_module(device: &wgpu::Device) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("present"),
        source: wgpu::ShaderSource::Wgsl(present_source().into()),
    })
}

/// The line overlay: its generated binding, then shaders/overlay.wgsl.
pub fn overlay_source() -> String {
    format!(
        "// ---- bindings/mod.rs\n{}\n// ---- overlay.wgsl\n{OVERLAY_FILE}\n",
        bindings::wgsl_overlay_contract()
    )
}

/// The line overlay as a shader module on `device`.
pub fn overlay_module(device: &wgpu::Device) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("overlay"),
        source: wgpu::ShaderSource::Wgsl(overlay_source().into()),
    })
}

#[cfg(test)]
pub(crate) use tests::parse_and_validate;

#[cfg(test)]
mod tests {
    use super::*;
    use bindings::{
        Access, Binding, SharedValue, ENTRY_POINTS, MAX_CHUNKS, PRESENT_BINDINGS, SHARED_CONSTANTS,
        SPLIT_ARRAY_COUNT, UNSPLIT,
    };
    use naga::valid::{Capabilities, ValidationFlags, Validator};

    pub(crate) fn parse_and_validate(source: &str) -> (naga::Module, naga::valid::ModuleInfo) {
        let module = naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        let info = Validator::new(ValidationFlags::all(), Capabilities::empty())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        (module, info)
    }

    /// The kernel validates, and each entry point of the contract is in it
    /// with the contract's workgroup size.
    #[test]
    fn trace_kernel_parses_and_validates() {
        let (module, _) = parse_and_validate(&trace_source([MAX_CHUNKS; SPLIT_ARRAY_COUNT]));
        for contract in ENTRY_POINTS {
            let entry = module
                .entry_points
                .iter()
                .find(|e| e.name == contract.name)
                .unwrap_or_else(|| panic!("the kernel lacks {}", contract.name));
            assert_eq!(
                entry.workgroup_size, contract.workgroup,
                "{}",
                contract.name
            );
        }
        assert_eq!(module.entry_points.len(), ENTRY_POINTS.len());
    }

    /// Each entry point copies the frame's parameters into the private
    /// `params` before anything else (shaders/frame_params.wgsl): read
    /// after a branch, it would still be right, but every read of a
    /// uniform there costs llvmpipe a load per lane.
    #[test]
    fn every_entry_point_reads_the_frame_params_first() {
        let chunks = [MAX_CHUNKS; SPLIT_ARRAY_COUNT];
        let (module, _) = parse_and_validate(&trace_source(chunks));
        let (inspect, _) = parse_and_validate(&inspect_source_without(chunks, &[]));
        assert!(module.entry_points.len() >= 3);
        let entries = module.entry_points.iter().map(|e| (&module, e));
        for (module, entry) in entries.chain(inspect.entry_points.iter().map(|e| (&inspect, e))) {
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

    /// The inspect kernel validates with the inspect entry points at their
    /// workgroup sizes, binds its log as the contract says, and holds every
    /// function of the trace kernel; the trace kernel declares no log.
    #[test]
    fn inspect_kernel_is_the_trace_kernel_with_its_recorder_and_log() {
        let chunks = [MAX_CHUNKS; SPLIT_ARRAY_COUNT];
        let (module, _) = parse_and_validate(&inspect_source_without(chunks, &[]));
        for contract in bindings::INSPECT_ENTRY_POINTS {
            let entry = module
                .entry_points
                .iter()
                .find(|e| e.name == contract.name)
                .unwrap_or_else(|| panic!("the inspect kernel lacks {}", contract.name));
            assert_eq!(
                entry.workgroup_size, contract.workgroup,
                "{}",
                contract.name
            );
        }
        assert_eq!(
            module.entry_points.len(),
            bindings::INSPECT_ENTRY_POINTS.len()
        );
        let mut table = bindings::all(chunks);
        table.push(bindings::INSPECT_LOG);
        globals_are(&module, &table);
        constants_equal_the_hosts(&module, &SHARED_CONSTANTS);
        let render = kernel(chunks);
        assert!(render
            .global_variables
            .iter()
            .all(|(_, g)| g.name.as_deref() != Some(bindings::INSPECT_LOG.name)));
        let names = |m: &naga::Module| -> Vec<String> {
            m.functions
                .iter()
                .filter_map(|(_, f)| f.name.clone())
                .collect()
        };
        let inspect_functions = names(&module);
        for name in names(&render) {
            assert!(
                inspect_functions.contains(&name),
                "the inspect kernel lacks {name}"
            );
        }
    }

    /// Every .wgsl file in shaders/ is part of a validated module.
    #[test]
    fn every_shader_file_is_validated() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        let mut validated: Vec<&str> = TRACE_PARTS.iter().map(|(name, _)| *name).collect();
        validated.extend(STANDALONE_SHADERS.iter().map(|(name, _)| *name));
        validated.push(WALK_RECORD.0);
        parse_and_validate(&present_source());
        parse_and_validate(&inspect_source_without(
            [MAX_CHUNKS; SPLIT_ARRAY_COUNT],
            &[],
        ));
        parse_and_validate(&overlay_source());
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

    fn kernel(chunks: SceneChunks) -> naga::Module {
        parse_and_validate(&trace_source(chunks)).0
    }

    /// Each global of `module` with a binding is one of `table`, at its
    /// number and with its access, and each of `table` is declared.
    fn globals_are(module: &naga::Module, table: &[Binding]) {
        let mut seen = Vec::new();
        for (_, global) in module.global_variables.iter() {
            let Some(res) = &global.binding else { continue };
            let name = global.name.as_deref().unwrap_or("");
            let b = table
                .iter()
                .find(|b| b.name == name)
                .unwrap_or_else(|| panic!("the shader binds `{name}`, which gpu/bindings/ lacks"));
            assert_eq!((res.group, res.binding), (0, b.index), "binding of {name}");
            let access = match global.space {
                naga::AddressSpace::Uniform => Access::Uniform,
                naga::AddressSpace::Storage { access }
                    if access.contains(naga::StorageAccess::STORE) =>
                {
                    Access::StorageReadWrite
                }
                naga::AddressSpace::Storage { .. } => Access::StorageRead,
                other => panic!("{name} is in {other:?}"),
            };
            assert_eq!(access, b.access, "access of {name}");
            seen.push(name.to_string());
        }
        for b in table {
            assert!(
                seen.iter().any(|s| s == b.name),
                "{} is not declared",
                b.name
            );
        }
        let mut indices: Vec<u32> = table.iter().map(|b| b.index).collect();
        indices.sort_unstable();
        indices.dedup();
        assert_eq!(indices.len(), table.len(), "two bindings share a number");
    }

    /// Each global of the kernel is a binding of the contract, at its
    /// number and with its access, and each binding of the contract is
    /// declared, for every number of chunks.
    #[test]
    fn kernel_bindings_are_the_contract() {
        for chunks in [UNSPLIT, [2, 3, 1, 8, 1, 2], [MAX_CHUNKS; SPLIT_ARRAY_COUNT]] {
            globals_are(&kernel(chunks), &bindings::all(chunks));
        }
    }

    /// The same for the present pass and its bindings.
    #[test]
    fn present_bindings_are_the_contract() {
        globals_are(&parse_and_validate(&present_source()).0, &PRESENT_BINDINGS);
    }

    /// The same for the window's line overlay.
    #[test]
    fn overlay_bindings_are_the_contract() {
        globals_are(
            &parse_and_validate(&overlay_source()).0,
            &bindings::OVERLAY_BINDINGS,
        );
    }

    /// Each shared constant, as naga evaluates the kernel's declaration, has
    /// exactly the host's value (bit for bit for floats).
    #[test]
    fn kernel_constants_equal_the_hosts() {
        constants_equal_the_hosts(&kernel([MAX_CHUNKS; SPLIT_ARRAY_COUNT]), &SHARED_CONSTANTS);
    }

    #[test]
    fn present_constants_equal_the_hosts() {
        let (module, _) = parse_and_validate(&present_source());
        constants_equal_the_hosts(&module, &crate::gpu::bindings::PRESENT_CONSTANTS);
    }

    fn constants_equal_the_hosts(module: &naga::Module, constants: &[(&str, SharedValue)]) {
        for &(name, value) in constants {
            let (_, constant) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("the kernel lacks const {name}"));
            let naga::Expression::Literal(literal) = module.global_expressions[constant.init]
            else {
                panic!("{name} is not a literal");
            };
            match (value, literal) {
                (SharedValue::U32(host), naga::Literal::U32(kernel)) => {
                    assert_eq!(host, kernel, "{name}")
                }
                (SharedValue::F32(host), naga::Literal::F32(kernel)) => {
                    assert_eq!(host.to_bits(), kernel.to_bits(), "{name}")
                }
                (host, kernel) => panic!("{name}: host {host:?}, kernel {kernel:?}"),
            }
        }
    }

    /// With any of the optional bindings left out, the kernel still
    /// validates, and the text the page swaps (each optional binding's bound
    /// declaration for its placeholder) is in the full kernel exactly once,
    /// so that swapping it there gives the kernel generated without it.
    #[test]
    fn kernels_without_optional_bindings_validate_and_match_the_swap() {
        use bindings::{declaration, OPTIONAL_BINDINGS};
        let full = trace_source(UNSPLIT);
        let optional: Vec<Binding> = OPTIONAL_BINDINGS.iter().map(|(b, _)| *b).collect();
        // Each alone at either end, some mixes, and all of them.
        let last = 1u32 << (optional.len() - 1);
        for mask in [
            0u32,
            0b1,
            0b10,
            0b100,
            0b11000,
            0b1100000,
            0b10000000,
            0b10111001,
            last,
            (last << 1) - 1,
        ] {
            let omitted: Vec<Binding> = optional
                .iter()
                .enumerate()
                .filter(|(i, _)| mask & (1 << i) != 0)
                .map(|(_, b)| *b)
                .collect();
            let generated = trace_source_without(UNSPLIT, &omitted);
            let (module, _) = parse_and_validate(&generated);
            let mut swapped = full.clone();
            for b in &omitted {
                let bound = declaration(b, true);
                assert_eq!(swapped.matches(&bound).count(), 1, "{}", b.name);
                swapped = swapped.replacen(&bound, &declaration(b, false), 1);
            }
            assert_eq!(swapped, generated, "omitting {mask:#b}");
            let bound: Vec<&str> = module
                .global_variables
                .iter()
                .filter(|(_, g)| g.binding.is_some())
                .filter_map(|(_, g)| g.name.as_deref())
                .collect();
            for b in &omitted {
                assert!(!bound.contains(&b.name), "{} is still bound", b.name);
            }
        }
    }

    /// No shader file declares a binding or a shared constant by hand.
    #[test]
    fn shader_files_leave_the_contract_to_the_generator() {
        for (file, text) in TRACE_PARTS.into_iter().chain(STANDALONE_SHADERS) {
            for line in text.lines() {
                let code = line.split("//").next().unwrap_or("");
                assert!(
                    !code.contains("@binding("),
                    "{file} declares a binding: {line}"
                );
                for (name, _) in SHARED_CONSTANTS.iter().chain(&bindings::PRESENT_CONSTANTS) {
                    assert!(
                        !code.trim_start().starts_with(&format!("const {name}:")),
                        "{file} declares {name}: {line}"
                    );
                }
            }
        }
    }
}
