//! What one trace pipeline is specialised for: the scene's layout and kinds
//! of object, material (glass or none, textured or not) and light, the
//! accel and the k-d walk, and whether the frame counts the walks' work,
//! set as the kernel's pipeline-overridable constants (shaders/variant.wgsl)
//! and folded on the host (gpu/specialise.rs), so that each pipeline holds
//! only the code its frames can reach.
//!
//! Why: llvmpipe (lavapipe, Mesa 22.3) runs a branch of an 8-lane SIMD group
//! by masking its lanes, not by jumping over it, so every instruction
//! outside a loop runs for every group whatever the condition, and every
//! loop body runs at least once. A kernel that chose its walk from the
//! frame's uniforms ran all four walks (and the sphere and the triangle test
//! for every object) on every ray. Measured on the bunny at 1920 x 1080,
//! primary + shadow: from 1,403 - 1,557 ms to about 800 ms a frame, the
//! same image.
//!
//! The general variant ([`KernelVariant::GENERAL`]) reads every choice from
//! the frame's uniforms at run time; the ray-query kernel uses it, so the
//! tests hold both forms of the kernel to the CPU.
//!
//! A variant also says which of the kernel's optional bindings its frames
//! never read ([`KernelVariant::unread_bindings`]): on an adapter with too
//! few storage buffers per stage for every binding, its pipeline declares
//! those as private placeholders (gpu/trace_pipelines.rs).

pub use super::bindings::FROM_PARAMS;
use super::bindings::{Binding, Need, OPTIONAL_BINDINGS};
use super::frame_params::{accel_value, traversal_value};
use super::{Accel, SceneArrays, SceneBuffers};
use crate::gpu::FrameParams;
use crate::kdtree::Traversal;

/// The walk a pipeline is made for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Walk {
    /// `FrameParams::accel` and `traversal` decide per frame.
    FromParams,
    /// The seed's loop over every object.
    Brute,
    /// A k-d walk.
    Kdtree(Traversal),
}

/// The choices baked into one trace pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct KernelVariant {
    /// Whether the scene's split arrays may lie in several bindings (the
    /// chunk selection of shaders/chunks.wgsl); without it, an index past
    /// the first binding reads the wrong (bounds-checked) element.
    pub split_scene: bool,
    pub walk: Walk,
    /// Whether the scene may hold spheres, and triangles. A scene with
    /// neither may have either.
    pub spheres: bool,
    pub triangles: bool,
    /// Whether a triangle may have vertex normals (smooth shading).
    pub smooth_triangles: bool,
    /// Whether a material may transmit: the path with refraction, a stack
    /// of pending rays and shadow rays through glass (shaders/glass.wgsl).
    /// Without it the kernel is the opaque one, instruction for instruction.
    pub glass: bool,
    /// Whether a triangle may be textured: the base-colour texture sampled
    /// at its hits (shaders/texture.wgsl). Without it the material is read
    /// as it was before textures, instruction for instruction.
    pub textures: bool,
    /// Whether a material may have an alpha mode: the walks' object test
    /// then reads its alpha (shaders/alpha.wgsl). Without it the test is
    /// the geometric one, instruction for instruction.
    pub alpha_test: bool,
    /// Whether a scene light may be a spot or directional light; without,
    /// every one is a point light to both integrators (shaders/shade.wgsl,
    /// shaders/emitters.wgsl).
    pub spot_or_directional_lights: bool,
    /// Whether the walks count their work (nodes, leaves, objects) for the
    /// frame's cost buffer. Without, the counters are compiled out.
    pub count_costs: bool,
    /// `INTEGRATOR_WHITTED`, `INTEGRATOR_PATH` (shaders/path.wgsl), or
    /// [`FROM_PARAMS`]: the frame's `integrator`.
    pub integrator: u32,
    /// Whether `render_tile` writes radiance sums as floats (path frames,
    /// EXR output) instead of 8-bit colour.
    pub radiance_output: bool,
    /// Whether `render_tile`'s radiance output also carries each pixel's
    /// feature sums (albedo and normal) for the denoiser. Without it the
    /// path is the plain one, instruction for instruction.
    pub feature_output: bool,
}

impl KernelVariant {
    /// Every choice made at run time: any scene, any frame.
    pub const GENERAL: KernelVariant = KernelVariant {
        split_scene: true,
        walk: Walk::FromParams,
        spheres: true,
        triangles: true,
        smooth_triangles: true,
        glass: true,
        textures: true,
        alpha_test: true,
        spot_or_directional_lights: true,
        count_costs: true,
        integrator: FROM_PARAMS,
        radiance_output: false,
        feature_output: false,
    };

    /// The variant for frames of `scene` with `params`' accel and walk,
    /// counting the walks' work if `count_costs`.
    pub fn for_frame(
        scene: &SceneBuffers,
        params: &FrameParams,
        count_costs: bool,
    ) -> KernelVariant {
        KernelVariant {
            count_costs,
            integrator: params.integrator,
            radiance_output: params.integrator == crate::layout::INTEGRATOR_PATH,
            feature_output: false,
            ..Self::for_scene(scene).with_walk_of(params)
        }
    }

    /// The variant for `scene`, its walk left to the frame's uniforms,
    /// counting the walks' work ([`Self::for_arrays`] of its arrays).
    pub fn for_scene(scene: &SceneBuffers) -> KernelVariant {
        scene.variant
    }

    /// The variant for a scene of `arrays`, whose split arrays lie in
    /// several bindings if `split_scene`, its walk left to the frame's
    /// uniforms, counting the walks' work. The host's scene buffers and the
    /// page's bundle (`web::bundle`) both take theirs from here.
    pub fn for_arrays(arrays: &SceneArrays, split_scene: bool) -> KernelVariant {
        let spheres = !arrays.spheres.is_empty();
        let triangles = arrays.objects.len() > arrays.spheres.len();
        KernelVariant {
            split_scene,
            walk: Walk::FromParams,
            spheres: spheres || !triangles,
            triangles: triangles || !spheres,
            smooth_triangles: !arrays.triangle_normals.is_empty(),
            glass: arrays.glass(),
            textures: !arrays.textures.is_empty(),
            alpha_test: arrays.alpha_test(),
            spot_or_directional_lights: arrays.spot_or_directional_lights(),
            count_costs: true,
            integrator: crate::layout::INTEGRATOR_WHITTED,
            radiance_output: false,
            feature_output: false,
        }
    }

    /// The same variant with `params`' accel and walk.
    pub fn with_walk_of(self, params: &FrameParams) -> KernelVariant {
        let walk = if params.accel == accel_value(Accel::Brute) {
            Walk::Brute
        } else {
            Traversal::ALL
                .into_iter()
                .find(|&t| traversal_value(t) == params.traversal)
                .map_or(Walk::FromParams, Walk::Kdtree)
        };
        KernelVariant { walk, ..self }
    }

    /// Whether this variant's frames may read the bindings that `need`
    /// names (shaders/variant.wgsl compiles the other reads out).
    pub fn reads(&self, need: Need) -> bool {
        match need {
            Need::Spheres => self.spheres,
            Need::Triangles => self.triangles,
            Need::SmoothTriangles => self.smooth_triangles,
            Need::KdWalk => self.walk != Walk::Brute,
            Need::RopeWalk => {
                matches!(self.walk, Walk::FromParams | Walk::Kdtree(Traversal::Ropes))
            }
            Need::Costs => self.count_costs,
            Need::Textures => self.textures,
        }
    }

    /// The optional bindings ([`OPTIONAL_BINDINGS`]) this variant's frames
    /// never read, in the table's order.
    pub fn unread_bindings(&self) -> Vec<Binding> {
        OPTIONAL_BINDINGS
            .iter()
            .filter(|(_, need)| !self.reads(*need))
            .map(|(b, _)| *b)
            .collect()
    }

    /// The pipeline constants that make this variant, by WGSL name
    /// (shaders/variant.wgsl declares each of [`OVERRIDES`]).
    pub fn constants(&self) -> [(&'static str, f64); 14] {
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        let (accel, traversal) = match self.walk {
            Walk::FromParams => (FROM_PARAMS, FROM_PARAMS),
            // The brute-force loop reads no tree: any walk will do.
            Walk::Brute => (
                accel_value(Accel::Brute),
                traversal_value(Traversal::Restart),
            ),
            Walk::Kdtree(t) => (accel_value(Accel::Kdtree), traversal_value(t)),
        };
        [
            ("SPLIT_SCENE", flag(self.split_scene)),
            ("ACCEL", accel as f64),
            ("TRAVERSAL", traversal as f64),
            ("SPHERES", flag(self.spheres)),
            ("TRIANGLES", flag(self.triangles)),
            ("SMOOTH_TRIANGLES", flag(self.smooth_triangles)),
            ("GLASS", flag(self.glass)),
            ("TEXTURES", flag(self.textures)),
            ("ALPHA_TEST", flag(self.alpha_test)),
            (
                "SPOT_OR_DIRECTIONAL_LIGHTS",
                flag(self.spot_or_directional_lights),
            ),
            ("COUNT_COSTS", flag(self.count_costs)),
            ("INTEGRATOR", self.integrator as f64),
            ("RADIANCE_OUTPUT", flag(self.radiance_output)),
            ("FEATURE_OUTPUT", flag(self.feature_output)),
        ]
    }
}

/// The names of the kernel's pipeline-overridable constants, all of which
/// [`KernelVariant::constants`] sets.
pub const OVERRIDES: [&str; 14] = [
    "SPLIT_SCENE",
    "ACCEL",
    "TRAVERSAL",
    "SPHERES",
    "TRIANGLES",
    "SMOOTH_TRIANGLES",
    "GLASS",
    "TEXTURES",
    "ALPHA_TEST",
    "SPOT_OR_DIRECTIONAL_LIGHTS",
    "COUNT_COSTS",
    "INTEGRATOR",
    "RADIANCE_OUTPUT",
    "FEATURE_OUTPUT",
];

/// The overrides that follow from the scene ([`KernelVariant::for_arrays`]);
/// the others are each pipeline's choices: its walk, whether it counts
/// costs, its integrator and its output.
pub const SCENE_OVERRIDES: [&str; 8] = [
    "SPLIT_SCENE",
    "SPHERES",
    "TRIANGLES",
    "SMOOTH_TRIANGLES",
    "GLASS",
    "TEXTURES",
    "ALPHA_TEST",
    "SPOT_OR_DIRECTIONAL_LIGHTS",
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The general variant reads every optional binding; a brute-force
    /// frame of a flat triangle mesh without costs reads none of the tree's,
    /// the spheres', the normals' or the costs'; only the rope walk reads
    /// the ropes.
    #[test]
    fn unread_bindings_follow_the_variant() {
        use crate::gpu::bindings::{
            KD_NODES, LEAF_OBJECTS, LEAF_ROPES, LEAF_ROPE_INDEX, PIXEL_COSTS, SPHERES, TEXTURES,
            TRIANGLE_NORMALS,
        };
        assert!(KernelVariant::GENERAL.unread_bindings().is_empty());
        let mesh = KernelVariant {
            split_scene: false,
            walk: Walk::Brute,
            spheres: false,
            triangles: true,
            smooth_triangles: false,
            count_costs: false,
            glass: false,
            textures: false,
            alpha_test: false,
            spot_or_directional_lights: false,
            integrator: crate::layout::INTEGRATOR_WHITTED,
            radiance_output: false,
            feature_output: false,
        };
        assert_eq!(
            mesh.unread_bindings(),
            [
                SPHERES,
                TRIANGLE_NORMALS,
                KD_NODES,
                LEAF_OBJECTS,
                LEAF_ROPES,
                LEAF_ROPE_INDEX,
                PIXEL_COSTS,
                TEXTURES
            ]
        );
        for (t, ropes) in [
            (Traversal::Restart, false),
            (Traversal::Ropes, true),
            (Traversal::ShortStack, false),
        ] {
            let unread = KernelVariant {
                walk: Walk::Kdtree(t),
                ..mesh
            }
            .unread_bindings();
            assert!(!unread.contains(&KD_NODES) && !unread.contains(&LEAF_OBJECTS));
            assert_eq!(!unread.contains(&LEAF_ROPES), ropes, "{t:?}");
            assert_eq!(!unread.contains(&LEAF_ROPE_INDEX), ropes, "{t:?}");
        }
    }

    /// Each variant sets every override of the kernel, and no other name:
    /// an override the host forgot would keep its general default, silently.
    #[test]
    fn every_override_of_the_kernel_is_set_by_the_host() {
        let source = crate::gpu::shaders::trace_source(crate::gpu::bindings::UNSPLIT);
        let module = naga::front::wgsl::parse_str(&source).expect("the kernel parses");
        let mut declared: Vec<String> = module
            .overrides
            .iter()
            .filter_map(|(_, o)| o.name.clone())
            .collect();
        declared.sort();
        let mut expected: Vec<String> = OVERRIDES.iter().map(|s| s.to_string()).collect();
        expected.sort();
        assert_eq!(declared, expected);
        let set: Vec<&str> = KernelVariant::GENERAL
            .constants()
            .iter()
            .map(|(name, _)| *name)
            .collect();
        assert_eq!(set, OVERRIDES);
    }

    /// The general variant's values are the kernel's defaults, so a
    /// pipeline made without constants is the general one.
    #[test]
    fn the_general_variant_is_the_kernels_default() {
        let source = crate::gpu::shaders::trace_source(crate::gpu::bindings::UNSPLIT);
        let module = naga::front::wgsl::parse_str(&source).expect("the kernel parses");
        for (name, value) in KernelVariant::GENERAL.constants() {
            let (_, o) = module
                .overrides
                .iter()
                .find(|(_, o)| o.name.as_deref() == Some(name))
                .expect("declared");
            let init = o.init.expect("a default");
            let default = match module.global_expressions[init] {
                naga::Expression::Literal(naga::Literal::Bool(b)) => f64::from(u8::from(b)),
                naga::Expression::Literal(naga::Literal::U32(u)) => u as f64,
                naga::Expression::Constant(c) => {
                    match module.global_expressions[module.constants[c].init] {
                        naga::Expression::Literal(naga::Literal::U32(u)) => u as f64,
                        ref e => panic!("{name}: unexpected default {e:?}"),
                    }
                }
                ref e => panic!("{name}: unexpected default {e:?}"),
            };
            assert_eq!(default, value, "{name}");
        }
    }
}
