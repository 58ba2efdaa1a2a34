//! Every BSDF lobe of the kernel (shaders/bsdf_*.wgsl) against its CPU
//! counterpart (crates/kdray-core/src/bsdf/): a small entry point, added to
//! the trace kernel for this test, runs each lobe's eval, pdf and sample
//! (with given random numbers) on a batch of random inputs, and each answer
//! equals the CPU lobe's within f32 tolerance; and the kernel's own samples
//! pass the chi-square test of the CPU lobes' tests.

use crate::common;

use glam::Vec3;
use kdray::gpu::bindings::UNSPLIT;
use kdray::gpu::shaders::trace_source;
use kdray::layout::{GpuMaterial, MODEL_LAMBERTIAN, MODEL_METAL_ROUGH};
use kdray_core::bsdf::check::{chi_square_of, chi_square_z, material, views};
use kdray_core::bsdf::{LobeSample, Site, LOBES};
use wgpu::util::DeviceExt;

/// Inputs per case (vec4s): shading normal and inside, geometric normal
/// and lobe, v, l, u; outputs: eval (value, pdf), pdf, sample (dir, pdf),
/// sample (weight, refracted).
const INPUTS: usize = 5;
const OUTPUTS: usize = 4;

/// The entry point: one case an invocation, each lobe's functions called
/// by the names of the interface (shaders/bsdf.wgsl).
fn check_entry() -> String {
    let mut arms = String::new();
    for (i, lobe) in LOBES.iter().enumerate() {
        let n = lobe.name();
        arms += &format!(
            "        case {i}u: {{ e = {n}_eval(m, s, inside, v, l); p = {n}_pdf(m, s, inside, v, l); smp = {n}_sample(m, s, inside, v, u); }}\n"
        );
    }
    format!(
        r#"
@group(0) @binding(250) var<storage, read> lobe_materials: array<Material>;
@group(0) @binding(251) var<storage, read> lobe_inputs: array<vec4<f32>>;
@group(0) @binding(252) var<storage, read_write> lobe_outputs: array<vec4<f32>>;

@compute @workgroup_size(64)
fn lobe_check(@builtin(global_invocation_id) id: vec3<u32>) {{
    let i = id.x;
    if (i >= arrayLength(&lobe_materials)) {{
        return;
    }}
    let m = lobe_materials[i];
    let a = lobe_inputs[{INPUTS}u * i];
    let b = lobe_inputs[{INPUTS}u * i + 1u];
    let s = Surface(b.xyz, a.xyz, vec3<f32>(0.0));
    let inside = a.w != 0.0;
    let v = lobe_inputs[{INPUTS}u * i + 2u].xyz;
    let l = lobe_inputs[{INPUTS}u * i + 3u].xyz;
    let u = lobe_inputs[{INPUTS}u * i + 4u].xyz;
    var e = LobeEval(vec3<f32>(0.0), 0.0);
    var p = 0.0;
    var smp = LobeSample(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, false);
    switch u32(b.w) {{
{arms}        default: {{}}
    }}
    lobe_outputs[{OUTPUTS}u * i] = vec4<f32>(e.value, e.pdf);
    lobe_outputs[{OUTPUTS}u * i + 1u] = vec4<f32>(p, 0.0, 0.0, 0.0);
    lobe_outputs[{OUTPUTS}u * i + 2u] = vec4<f32>(smp.dir, smp.pdf);
    lobe_outputs[{OUTPUTS}u * i + 3u] = vec4<f32>(smp.weight, select(0.0, 1.0, smp.refracted));
}}
"#
    )
}

struct Case {
    lobe: usize,
    m: GpuMaterial,
    site: Site,
    v: Vec3,
    l: Vec3,
    u: Vec3,
}

/// A deterministic uniform generator (xorshift).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn unit(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.next();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * self.next();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

fn random_case(lobe: usize, rng: &mut Rng) -> Case {
    let mut m: GpuMaterial = bytemuck::Zeroable::zeroed();
    m.diffuse = [rng.next(), rng.next(), rng.next()];
    m.model = if LOBES[lobe].name() == "metal_rough" {
        MODEL_METAL_ROUGH
    } else {
        MODEL_LAMBERTIAN
    };
    m.metallic = rng.next();
    m.roughness = 0.2 + 0.8 * rng.next();
    m.transmission = 1.0;
    m.transmission_roughness = 0.2 + 0.8 * rng.next();
    m.ior = 1.1 + rng.next();
    m.thin_walled = u32::from(rng.next() < 0.3);
    let shading = rng.unit();
    // The geometric normal near the shading one, on its side.
    let geometric = (shading + 0.2 * rng.unit()).normalize();
    let mut v = rng.unit();
    if v.dot(shading) < 0.0 {
        v = -v;
    }
    Case {
        lobe,
        m,
        site: Site {
            shading,
            geometric,
            inside: rng.next() < 0.5,
        },
        v,
        l: rng.unit(),
        u: Vec3::new(rng.next(), rng.next(), rng.next()),
    }
}

/// Runs the cases' lobes on the GPU: per case, the four output vec4s.
fn run_on_gpu(cases: &[Case]) -> Vec<[f32; 4]> {
    let ctx = common::gpu();
    let device = &ctx.device;
    let source = trace_source(UNSPLIT) + &check_entry();
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("lobe check"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("lobe check"),
        layout: None,
        module: &module,
        entry_point: Some("lobe_check"),
        compilation_options: Default::default(),
        cache: None,
    });
    let materials: Vec<GpuMaterial> = cases.iter().map(|c| c.m).collect();
    let mut inputs: Vec<[f32; 4]> = Vec::new();
    for c in cases {
        let s = c.site;
        inputs.push([
            s.shading.x,
            s.shading.y,
            s.shading.z,
            f32::from(u8::from(s.inside)),
        ]);
        inputs.push([s.geometric.x, s.geometric.y, s.geometric.z, c.lobe as f32]);
        inputs.push([c.v.x, c.v.y, c.v.z, 0.0]);
        inputs.push([c.l.x, c.l.y, c.l.z, 0.0]);
        inputs.push([c.u.x, c.u.y, c.u.z, 0.0]);
    }
    let storage = |label, bytes: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let material_buffer = storage("materials", bytemuck::cast_slice(&materials));
    let input_buffer = storage("inputs", bytemuck::cast_slice(&inputs));
    let size = (cases.len() * OUTPUTS * 16) as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("outputs"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("lobe check"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 250,
                resource: material_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 251,
                resource: input_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 252,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups((cases.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, size);
    ctx.queue.submit([encoder.finish()]);
    let slice = readback.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    receiver.recv().unwrap().unwrap();
    let words: Vec<[f32; 4]> = bytemuck::cast_slice(&slice.get_mapped_range().unwrap()).to_vec();
    words
}

/// Whether two values agree within f32 tolerance (relative to the larger).
fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 2e-3 * a.abs().max(b.abs()) + 1e-5
}

fn close3(a: Vec3, b: Vec3) -> bool {
    (0..3).all(|i| close(a[i], b[i]))
}

/// The kernel's lobes equal the CPU's on random materials, normals,
/// directions and random numbers: the value and density of eval, pdf,
/// and the sampled direction, weight, density and side. A sample whose
/// choice turns on a difference in the last bits (a random number within
/// rounding of the Fresnel reflectance, a direction grazing the surface)
/// may go the other way: at most one case in a hundred.
#[test]
fn every_gpu_lobe_equals_its_cpu_counterpart() {
    const PER_LOBE: usize = 512;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let cases: Vec<Case> = (0..LOBES.len())
        .flat_map(|lobe| (0..PER_LOBE).map(move |k| (lobe, k)))
        .map(|(lobe, _)| random_case(lobe, &mut rng))
        .collect();
    let out = run_on_gpu(&cases);
    let mut report = Vec::new();
    for (lobe_index, lobe) in LOBES.iter().enumerate() {
        let mut mismatched = Vec::new();
        let mut nonzero = 0;
        for (k, c) in cases
            .iter()
            .enumerate()
            .filter(|(_, c)| c.lobe == lobe_index)
        {
            let [e, p, d, w] = [
                out[OUTPUTS * k],
                out[OUTPUTS * k + 1],
                out[OUTPUTS * k + 2],
                out[OUTPUTS * k + 3],
            ];
            let cpu_eval = lobe.eval(&c.m, &c.site, c.v, c.l);
            let cpu_pdf = lobe.pdf(&c.m, &c.site, c.v, c.l);
            let cpu_sample = lobe.sample(&c.m, &c.site, c.v, c.u);
            let gpu_value = Vec3::new(e[0], e[1], e[2]);
            let gpu_weight = Vec3::new(w[0], w[1], w[2]);
            let ok = close3(gpu_value, cpu_eval.value)
                && close(e[3], cpu_eval.pdf)
                && close(p[0], cpu_pdf)
                && close(d[3], cpu_sample.pdf)
                && close3(gpu_weight, cpu_sample.weight)
                && (cpu_sample.weight == Vec3::ZERO
                    || (Vec3::new(d[0], d[1], d[2]) - cpu_sample.dir).length() < 1e-3)
                && (w[3] != 0.0) == cpu_sample.refracted;
            nonzero += usize::from(cpu_eval.pdf > 0.0 || cpu_sample.weight != Vec3::ZERO);
            if !ok {
                mismatched.push(format!(
                    "case {k}: gpu eval {e:?} pdf {} sample {d:?} {w:?}; cpu {cpu_eval:?} {cpu_pdf} {cpu_sample:?}",
                    p[0]
                ));
            }
        }
        assert!(
            nonzero > PER_LOBE / 4 || lobe.is_delta(),
            "{}: only {nonzero} cases with a value",
            lobe.name()
        );
        if mismatched.len() > PER_LOBE / 100 {
            report.push(format!(
                "{}: {} of {PER_LOBE} cases differ:\n{}",
                lobe.name(),
                mismatched.len(),
                mismatched[..mismatched.len().min(5)].join("\n")
            ));
        }
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
}

/// The kernel's own sampling, not only the CPU's, has the density its pdf
/// states: 100,000 of the kernel's samples for each lobe with a density
/// (Lambert, metal/rough, frosted glass around a volume and thin-walled),
/// from two views, pass the chi-square test the CPU lobes' tests run
/// (crates/kdray-core/src/bsdf/check.rs).
#[test]
fn the_kernels_own_samples_pass_the_chi_square_test() {
    const N: usize = 100_000;
    let lobe = |name: &str| LOBES.iter().position(|l| l.name() == name).unwrap();
    let frosted = |thin: u32| {
        material(|m| {
            m.transmission = 1.0;
            m.thin_walled = thin;
        })
    };
    let metal = material(|m| {
        m.model = MODEL_METAL_ROUGH;
        m.metallic = 0.5;
        m.diffuse = [0.9, 0.7, 0.3];
    });
    let mut configs = Vec::new();
    for view in [views()[1], views()[5]] {
        configs.push((lobe("diffuse"), material(|_| {}), view));
        configs.push((lobe("metal_rough"), metal, view));
        configs.push((lobe("rough_dielectric"), frosted(0), view));
        configs.push((lobe("rough_dielectric"), frosted(1), view));
    }
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut cases = Vec::new();
    for &(lobe, m, (site, v)) in &configs {
        for _ in 0..N {
            let u = Vec3::new(rng.next(), rng.next(), rng.next());
            cases.push(Case {
                lobe,
                m,
                site,
                v,
                l: v,
                u,
            });
        }
    }
    let out = run_on_gpu(&cases);
    for (k, &(lobe, m, view)) in configs.iter().enumerate() {
        let samples: Vec<LobeSample> = (k * N..(k + 1) * N)
            .map(|i| {
                let (d, w) = (out[OUTPUTS * i + 2], out[OUTPUTS * i + 3]);
                LobeSample {
                    dir: Vec3::new(d[0], d[1], d[2]),
                    weight: Vec3::new(w[0], w[1], w[2]),
                    pdf: d[3],
                    refracted: w[3] != 0.0,
                }
            })
            .collect();
        let (statistic, dof) = chi_square_of(LOBES[lobe], &m, view, &samples);
        let z = chi_square_z(statistic, dof);
        assert!(
            z < 4.0,
            "{} (thin {}): the kernel's samples give chi-square {statistic} with {dof} degrees of freedom (z = {z})",
            LOBES[lobe].name(),
            m.thin_walled
        );
    }
}
