//! The denoiser's WGSL modules (shaders/denoise/) and their compute
//! pipelines: the 3x3 convolution, max pooling and upsampling, and the
//! tile's packing and unpacking. Made once per [`super::Denoiser`]; each
//! pipeline's bind group layout is the one its entry point implies.

use crate::error::Result;
use crate::gpu::GpuContext;

pub const CONV_WGSL: &str = include_str!("../../shaders/denoise/conv.wgsl");
pub const RESAMPLE_WGSL: &str = include_str!("../../shaders/denoise/resample.wgsl");
pub const PACK_WGSL: &str = include_str!("../../shaders/denoise/pack.wgsl");

/// Every denoise shader file and its entry points (the naga test reads them).
#[cfg(test)]
pub const DENOISE_SHADERS: [(&str, &str, &[&str]); 3] = [
    ("conv.wgsl", CONV_WGSL, &["conv3x3"]),
    ("resample.wgsl", RESAMPLE_WGSL, &["max_pool2", "upsample2"]),
    ("pack.wgsl", PACK_WGSL, &["pack_tile", "unpack_tile"]),
];

/// Output channels of one weights block (gpu_weights.rs).
pub const CONV_GROUP: usize = 8;
/// Output channels one convolution invocation computes (conv.wgsl): two
/// weights blocks.
pub const CONV_OUTPUTS: usize = 2 * CONV_GROUP;
/// Pixels of a row one convolution invocation computes (conv.wgsl).
pub const CONV_PIXELS: u32 = 8;
/// Every entry point's workgroup is 8 x 8 x 1.
pub const WORKGROUP: u32 = 8;

pub struct Kernels {
    pub conv: wgpu::ComputePipeline,
    pub pool: wgpu::ComputePipeline,
    pub upsample: wgpu::ComputePipeline,
    pub pack: wgpu::ComputePipeline,
    pub unpack: wgpu::ComputePipeline,
}

/// `source` as a module without forced loop bounds: every loop of these
/// shaders runs over a count from the parameters (channels, at most 160)
/// or a constant (taps).
fn module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    crate::gpu::shaders::module_without_loop_bounds(device, label, source)
}

fn pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

impl Kernels {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        ctx.checked("creating the denoiser's pipelines", |device| {
            let conv = module(device, "denoise conv", CONV_WGSL);
            let resample = module(device, "denoise resample", RESAMPLE_WGSL);
            let pack = module(device, "denoise pack", PACK_WGSL);
            Kernels {
                conv: pipeline(device, &conv, "conv3x3"),
                pool: pipeline(device, &resample, "max_pool2"),
                upsample: pipeline(device, &resample, "upsample2"),
                pack: pipeline(device, &pack, "pack_tile"),
                unpack: pipeline(device, &pack, "unpack_tile"),
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::shaders::parse_and_validate;

    /// Each denoise shader validates with naga and has its entry points
    /// with an 8 x 8 x 1 workgroup; every file in shaders/denoise/ is one
    /// of them.
    #[test]
    fn denoise_shaders_parse_and_validate() {
        for (name, source, entries) in DENOISE_SHADERS {
            let (module, _) = parse_and_validate(source);
            for entry in entries {
                let found = module
                    .entry_points
                    .iter()
                    .find(|e| e.name == *entry)
                    .unwrap_or_else(|| panic!("{name} has no entry point {entry}"));
                assert_eq!(found.workgroup_size, [WORKGROUP, WORKGROUP, 1], "{entry}");
            }
        }
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders/denoise");
        for entry in std::fs::read_dir(dir).unwrap() {
            let file = entry.unwrap().file_name().into_string().unwrap();
            assert!(
                DENOISE_SHADERS.iter().any(|(name, _, _)| *name == file),
                "{file} is not validated"
            );
        }
    }

    /// The WGSL's PU constants are the core's, digit for digit.
    #[test]
    fn pack_shader_constants_are_the_cores() {
        use kdray_core::denoise::transfer as t;
        let (module, _) = parse_and_validate(PACK_WGSL);
        let expected = [
            ("PU_A", t::PU_A),
            ("PU_B", t::PU_B),
            ("PU_C", t::PU_C),
            ("PU_D", t::PU_D),
            ("PU_E", t::PU_E),
            ("PU_F", t::PU_F),
            ("PU_G", t::PU_G),
            ("PU_Y0", t::PU_Y0),
            ("PU_Y1", t::PU_Y1),
            ("PU_X0", t::PU_X0),
            ("PU_X1", t::PU_X1),
            ("F32_MAX", f32::MAX),
        ];
        for (name, value) in expected {
            let constant = module
                .constants
                .iter()
                .map(|(_, c)| c)
                .find(|c| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no constant {name}"));
            match module.global_expressions[constant.init] {
                naga::Expression::Literal(naga::Literal::F32(v)) => assert_eq!(v, value, "{name}"),
                ref other => panic!("{name} is {other:?}"),
            }
        }
    }
}
