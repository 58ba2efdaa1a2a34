//! What a dependent load costs on this adapter, by the way the kernel reads
//! memory: a storage buffer, a sampled texture (`textureLoad`) or a uniform
//! buffer, one word or two at a time, each lane on its own chain or all
//! lanes of a row on one, and under which lanes' masks. Each invocation
//! follows a random cycle through `n` words for `steps` steps; the GPU time
//! per step is printed (one load a step, except in the `masked_*` kernels,
//! where a step loads in about half the lanes).
//!
//! ```sh
//! cargo run --release --example load_paths -- [N_LOG2] [STEPS]
//! ```
//! Measured for docs/design.md, "Where the scene's arrays live".

use std::time::Instant;

use kdray::gpu::context::GpuContext;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
/// Texture rows are 4096 texels wide: index i lies at (i & 4095, i >> 12).
const TEX_WIDTH: u32 = 4096;

fn source(steps: u32, mask: u32) -> String {
    format!(
        r#"
@group(0) @binding(0) var<storage, read> words: array<u32>;
@group(0) @binding(1) var<storage, read> pairs: array<vec2<u32>>;
@group(0) @binding(2) var words_tex: texture_2d<u32>;
@group(0) @binding(3) var pairs_tex: texture_2d<u32>;
@group(0) @binding(4) var<uniform> small: array<vec4<u32>, 4096>;
@group(0) @binding(5) var<storage, read_write> out: array<u32>;
@group(0) @binding(6) var<storage, read> quads: array<vec4<u32>>;
@group(0) @binding(7) var quads_tex: texture_2d<u32>;

const STEPS: u32 = {steps}u;
const MASK: u32 = {mask}u;

fn start(gid: vec3<u32>, shared_row: bool) -> u32 {{
    let x = select(gid.x, gid.x & ~7u, shared_row);
    return (x * 7919u + gid.y * 104729u) & MASK;
}}

fn texel(i: u32) -> vec2<u32> {{
    return vec2<u32>(i & 4095u, i >> 12u);
}}

fn done(gid: vec3<u32>, acc: u32) {{
    out[gid.y * {WIDTH}u + gid.x] = acc;
}}

@compute @workgroup_size(8, 8, 1)
fn storage_word(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ i = words[i]; acc += i; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn storage_word_shared_row(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, true);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ i = words[i]; acc += i; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn storage_pair(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ let p = pairs[i]; i = p.x; acc += p.y; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn storage_two_words(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ let a = words[i]; acc += words[i ^ 1u]; i = a; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn texture_word(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ i = textureLoad(words_tex, texel(i), 0).x; acc += i; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn texture_word_shared_row(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, true);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ i = textureLoad(words_tex, texel(i), 0).x; acc += i; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn texture_pair(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ let p = textureLoad(pairs_tex, texel(i), 0); i = p.x; acc += p.y; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn storage_quad(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ let q = quads[i]; i = q.x; acc += q.y + q.z + q.w; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn texture_quad(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ let q = textureLoad(quads_tex, texel(i), 0); i = q.x; acc += q.y + q.z + q.w; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn uniform_word(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false) & 16383u;
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ i = small[i >> 2u][i & 3u] & 16383u; acc += i; }}
    done(gid, acc);
}}

@compute @workgroup_size(8, 8, 1)
fn storage_word_small(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false) & 16383u;
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ i = words[i] & 16383u; acc += i; }}
    done(gid, acc);
}}

// Whether a lane loads at step s: a hash of (s, lane), true for about half
// the lanes of a group, in a pattern that changes every step.
fn coin(s: u32, gid: vec3<u32>) -> bool {{
    var h = s * 747796405u + gid.x * 2891336453u + gid.y * 277803737u;
    h = (h ^ (h >> 16u)) * 2246822519u;
    h = h ^ (h >> 13u);
    return (h & 1u) != 0u;
}}

// The masked kernels' shape with every lane loading at every step: the coin
// is computed and the condition holds anyway (acc never takes that value
// here), so the load sits under a mask that is always full.
@compute @workgroup_size(8, 8, 1)
fn masked_none(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ if (coin(s, gid) || acc != 0xdeadbeefu) {{ i = words[i]; }} acc += i; }}
    done(gid, acc);
}}

// Half the lanes load at each step, a different half every step.
@compute @workgroup_size(8, 8, 1)
fn masked_half(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ if (coin(s, gid)) {{ i = words[i]; }} acc += i; }}
    done(gid, acc);
}}

// Half the lanes load at each step, the same half every step.
@compute @workgroup_size(8, 8, 1)
fn masked_fixed_half(@builtin(global_invocation_id) gid: vec3<u32>) {{
    var i = start(gid, false);
    var acc = 0u;
    for (var s = 0u; s < STEPS; s++) {{ if ((gid.x & 1u) == 0u || acc == 0xdeadbeefu) {{ i = words[i]; }} acc += i; }}
    done(gid, acc);
}}
"#
    )
}

/// A random cyclic permutation of 0..n (Sattolo's algorithm, a fixed LCG).
fn cycle(n: usize) -> Vec<u32> {
    let mut next: Vec<u32> = (0..n as u32).collect();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for i in (1..n).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let j = ((state >> 33) % i as u64) as usize;
        next.swap(i, j);
    }
    next
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let n_log2: u32 = args.get(1).map_or(Ok(20), |s| s.parse())?;
    let steps: u32 = args.get(2).map_or(Ok(500), |s| s.parse())?;
    let n = 1usize << n_log2;
    assert!(n >= TEX_WIDTH as usize * 4, "N_LOG2 must be at least 14");
    let ctx = GpuContext::new()?;
    println!("{}", ctx.adapter_line());
    let limits = ctx.device.limits();
    println!(
        "uniform binding {} bytes, {} uniform buffers a stage; storage binding {} bytes, {} a stage; 2-d textures {} texels a side",
        limits.max_uniform_buffer_binding_size,
        limits.max_uniform_buffers_per_shader_stage,
        limits.max_storage_buffer_binding_size,
        limits.max_storage_buffers_per_shader_stage,
        limits.max_texture_dimension_2d
    );
    let device = &ctx.device;
    let words = cycle(n);
    // The small cycle (uniform buffer and its storage twin): 16,384 words.
    let small: Vec<u32> = cycle(16384);
    let mut words_with_small = words.clone();
    words_with_small[..16384].copy_from_slice(&small);
    let pairs: Vec<u32> = words.iter().flat_map(|&w| [w, w ^ 5]).collect();
    let quads: Vec<u32> = words
        .iter()
        .flat_map(|&w| [w, w ^ 5, w ^ 6, w ^ 7])
        .collect();
    use wgpu::util::DeviceExt;
    let storage = |data: &[u32]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let words_buf = storage(&words);
    let words_small_buf = storage(&words_with_small);
    let pairs_buf = storage(&pairs);
    let quads_buf = storage(&quads);
    let uniform_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&small),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let out_buf = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: (WIDTH * HEIGHT * 4) as u64,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let texture = |format: wgpu::TextureFormat, data: &[u32], texel_words: u32| {
        let rows = (n as u32) / TEX_WIDTH;
        let t = device.create_texture_with_data(
            &ctx.queue,
            &wgpu::TextureDescriptor {
                label: None,
                size: wgpu::Extent3d {
                    width: TEX_WIDTH,
                    height: rows,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(&data[..(rows * TEX_WIDTH * texel_words) as usize]),
        );
        t.create_view(&Default::default())
    };
    let words_tex = texture(wgpu::TextureFormat::R32Uint, &words, 1);
    let pairs_tex = texture(wgpu::TextureFormat::Rg32Uint, &pairs, 2);
    let quads_tex = texture(wgpu::TextureFormat::Rgba32Uint, &quads, 4);
    let desc = wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(source(steps, n as u32 - 1).into()),
    };
    let checks = wgpu::ShaderRuntimeChecks {
        force_loop_bounding: false,
        ..wgpu::ShaderRuntimeChecks::checked()
    };
    // SAFETY: every loop of the module runs over a constant count.
    let module = unsafe { device.create_shader_module_trusted(desc, checks) };
    let tex_entry = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    let buf_entry = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let read = wgpu::BufferBindingType::Storage { read_only: true };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[
            buf_entry(0, read),
            buf_entry(1, read),
            tex_entry(2),
            tex_entry(3),
            buf_entry(4, wgpu::BufferBindingType::Uniform),
            buf_entry(5, wgpu::BufferBindingType::Storage { read_only: false }),
            buf_entry(6, read),
            tex_entry(7),
        ],
    });
    let group_with = |words: &wgpu::Buffer| {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: words.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: pairs_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&words_tex),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&pairs_tex),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: uniform_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: out_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: quads_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: wgpu::BindingResource::TextureView(&quads_tex),
                },
            ],
        })
    };
    let group = group_with(&words_buf);
    let group_small = group_with(&words_small_buf);
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let kernels = [
        "storage_word",
        "storage_word_shared_row",
        "storage_pair",
        "storage_two_words",
        "texture_word",
        "texture_word_shared_row",
        "texture_pair",
        "storage_quad",
        "texture_quad",
        "uniform_word",
        "storage_word_small",
        "masked_none",
        "masked_half",
        "masked_fixed_half",
    ];
    println!(
        "{n} words, {steps} loads per invocation, {WIDTH}x{HEIGHT} invocations; ns per step per invocation, three runs"
    );
    for name in kernels {
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(name),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(name),
            compilation_options: Default::default(),
            cache: None,
        });
        let bind = if name == "storage_word_small" {
            &group_small
        } else {
            &group
        };
        let mut times = Vec::new();
        for run in 0..4 {
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, bind, &[]);
                pass.dispatch_workgroups(WIDTH / 8, HEIGHT / 8, 1);
            }
            let t0 = Instant::now();
            ctx.queue.submit([encoder.finish()]);
            device.poll(wgpu::PollType::wait_indefinitely())?;
            let s = t0.elapsed().as_secs_f64();
            if run > 0 {
                // the first run compiles the kernel
                times.push(s * 1e9 / (WIDTH * HEIGHT * steps) as f64);
            }
        }
        println!(
            "{name:<26} {}",
            times
                .iter()
                .map(|t| format!("{t:.3}"))
                .collect::<Vec<_>>()
                .join("  ")
        );
    }
    Ok(())
}
