//! The inspect kernel: the trace kernel with shaders/walk_record.wgsl in
//! place of walk_record_off.wgsl, whose entry point `inspect_pixel` traces
//! one pixel's first sample as the renderer does and logs every ray it
//! traces and every step of the walk that searches it. [`WalkRecorder`]
//! runs it; [`decode`] reads its log back into rays and
//! [`WalkEvent`]s, the steps the CPU walks report to their observers.
//!
//! The log is words: word [`codes::WORDS_USED`] holds how many the kernel
//! meant to write, then records from [`codes::HEADER_WORDS`] on, each a tag
//! and its fields (floats as their bits), as walk_record.wgsl writes them.
//! A shadow ray's record names the light it aims at ([`RecordedLight`]).

use super::bindings::walk_codes as codes;
use super::bindings::{self, INSPECT_PIXEL};
use super::context::buffer_holding;
use super::{FrameParams, GpuContext, KernelVariant, SceneBuffers, TracePipelines};
use crate::error::{Error, Result};
use crate::geometry::Ray;
use crate::kdtree::traverse::WalkCost;
use crate::kdtree::WalkEvent;
use glam::Vec3;
use kdray_core::reference::RayKind;

/// One ray the kernel traced, with its walk as it ran.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedRay {
    pub kind: RayKind,
    /// An any-hit query (a shadow ray's) rather than nearest hit.
    pub any: bool,
    pub ray: Ray,
    /// How far the query looked (`T_INFINITY`: no limit).
    pub t_limit: f32,
    /// The walk's steps (none for brute force).
    pub walk: Vec<WalkEvent>,
    pub hit: Option<RecordedHit>,
    /// The walk's work, as the kernel counts it for the heatmap.
    pub cost: WalkCost,
    /// A shadow ray's light: what it aims at and with what probability.
    pub light: Option<RecordedLight>,
}

/// The light a shadow ray aims at, as the kernel logged it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordedLight {
    /// Its entry in the lights buffer: the scene's lights first (a scene
    /// light's entry is its index in `[[lights]]`), then the emitters,
    /// then the sky.
    pub entry: u32,
    /// `GpuLight::kind` (`LIGHT_POINT`, ...), or [`codes::LIGHT_SKY`].
    pub kind: u32,
    /// An emitter's object, by scene id; else `NO_OBJECT`.
    pub object: u32,
    /// The probability the light was picked with (Whitted: 1).
    pub pick: f32,
    /// The solid-angle density of the ray's direction, the pick included;
    /// 0 for a delta light (point, spot, directional) and in Whitted.
    pub density: f32,
}

/// What a ray's query returned, as the kernel saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordedHit {
    /// The scene's id of the object (`Primitives::from_scene`'s numbering).
    pub object: u32,
    pub t: f32,
    pub point: Vec3,
    /// Unit geometric normal, facing the ray.
    pub normal: Vec3,
}

/// Everything one `inspect_pixel` dispatch logged.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkLog {
    pub rays: Vec<RecordedRay>,
    /// The sample's colour, unclamped (Whitted) or its radiance (path).
    pub sample: [f32; 3],
}

/// Reads a log: its rays and the sample's colour. A log the kernel had no
/// room to finish, or one that does not parse, is an error.
pub fn decode(words: &[u32]) -> Result<WalkLog> {
    let used = words.get(codes::WORDS_USED as usize).copied().unwrap_or(0) as usize;
    if used > words.len() {
        return Err(Error::Gpu(format!(
            "the inspect log needs {used} words but has room for {}",
            words.len()
        )));
    }
    let mut reader = Reader {
        words: &words[..used],
        at: codes::HEADER_WORDS as usize,
    };
    let mut rays: Vec<RecordedRay> = Vec::new();
    loop {
        let tag = reader.word()?;
        if tag == codes::SAMPLE {
            let sample = reader.vec3()?.to_array();
            return Ok(WalkLog { rays, sample });
        }
        if tag == codes::RAY {
            rays.push(reader.ray()?);
            continue;
        }
        let ray = rays
            .last_mut()
            .ok_or_else(|| malformed(reader.at, "a walk step before any ray"))?;
        if tag == codes::HIT {
            (ray.hit, ray.cost) = reader.hit()?;
        } else {
            ray.walk.push(reader.event(tag)?);
        }
    }
}

fn malformed(at: usize, what: &str) -> Error {
    Error::Gpu(format!("the inspect log is malformed at word {at}: {what}"))
}

/// Reads fields from the log in order.
struct Reader<'a> {
    words: &'a [u32],
    at: usize,
}

impl Reader<'_> {
    fn word(&mut self) -> Result<u32> {
        let w = self
            .words
            .get(self.at)
            .copied()
            .ok_or_else(|| malformed(self.at, "it ends inside a record"))?;
        self.at += 1;
        Ok(w)
    }

    fn index(&mut self) -> Result<usize> {
        Ok(self.word()? as usize)
    }

    fn float(&mut self) -> Result<f32> {
        Ok(f32::from_bits(self.word()?))
    }

    fn flag(&mut self) -> Result<bool> {
        Ok(self.word()? != 0)
    }

    fn vec3(&mut self) -> Result<Vec3> {
        Ok(Vec3::new(self.float()?, self.float()?, self.float()?))
    }

    fn ray(&mut self) -> Result<RecordedRay> {
        let kind = match self.word()? {
            codes::RAY_PRIMARY => RayKind::Primary,
            codes::RAY_SHADOW => RayKind::Shadow,
            codes::RAY_REFLECTED => RayKind::Reflected,
            codes::RAY_REFRACTED => RayKind::Refracted,
            codes::RAY_BOUNCE => RayKind::Bounce,
            other => return Err(malformed(self.at, &format!("ray kind {other}"))),
        };
        let any = self.flag()?;
        let ray = Ray {
            origin: self.vec3()?,
            dir: self.vec3()?,
        };
        let t_limit = self.float()?;
        let light = RecordedLight {
            entry: self.word()?,
            kind: self.word()?,
            object: self.word()?,
            pick: self.float()?,
            density: self.float()?,
        };
        let light = (light.entry != bindings::NO_OBJECT).then_some(light);
        if light.is_some() != (kind == RayKind::Shadow) {
            return Err(malformed(
                self.at,
                "a light on a ray that is not a shadow ray, or none on one",
            ));
        }
        Ok(RecordedRay {
            kind,
            any,
            ray,
            t_limit,
            walk: Vec::new(),
            hit: None,
            cost: WalkCost::default(),
            light,
        })
    }

    fn hit(&mut self) -> Result<(Option<RecordedHit>, WalkCost)> {
        let object = self.word()?;
        let (t, point, normal) = (self.float()?, self.vec3()?, self.vec3()?);
        let cost = WalkCost {
            nodes_visited: self.word()?,
            leaves_visited: self.word()?,
            objects_tested: self.word()?,
        };
        let hit = (object != bindings::NO_OBJECT).then_some(RecordedHit {
            object,
            t,
            point,
            normal,
        });
        Ok((hit, cost))
    }

    fn event(&mut self, tag: u32) -> Result<WalkEvent> {
        Ok(match tag {
            codes::SEGMENT => WalkEvent::Segment {
                t_min: self.float()?,
                t_far: self.float()?,
            },
            codes::NODE => WalkEvent::Node {
                node: self.index()?,
                t_min: self.float()?,
                t_max: self.float()?,
                near: self.index()?,
                far: self.index()?,
                t_split: self.float()?,
                crosses: self.flag()?,
            },
            codes::LEAF => WalkEvent::Leaf {
                node: self.index()?,
                t_min: self.float()?,
                t_max: self.float()?,
            },
            codes::SKIPPED => WalkEvent::SkippedLeaf {
                node: self.index()?,
            },
            codes::TESTED => {
                let object = self.word()?;
                let met = self.flag()?;
                let t = self.float()?;
                WalkEvent::Tested {
                    object,
                    t: met.then_some(t),
                }
            }
            codes::PUSH => WalkEvent::Push {
                node: self.index()?,
                t_max: self.float()?,
            },
            codes::POP => WalkEvent::Pop {
                node: self.index()?,
                t_max: self.float()?,
            },
            codes::RESTART => WalkEvent::Restart {
                node: self.index()?,
                t_min: self.float()?,
            },
            codes::ROPE => WalkEvent::Rope {
                face: self.index()?,
                node: self.index()?,
                t_min: self.float()?,
            },
            other => return Err(malformed(self.at - 1, &format!("tag {other}"))),
        })
    }
}

/// The inspect kernel's pipelines, made once and reused for every pixel.
pub struct WalkRecorder {
    pipelines: std::sync::Arc<TracePipelines>,
}

/// Words the log starts with room for: most pixels' rays fit; a pixel
/// that needs more is traced again with the room it asked for.
pub const FIRST_LOG_WORDS: u64 = 1 << 18;

impl WalkRecorder {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(WalkRecorder {
            pipelines: ctx.trace_pipelines(INSPECT_PIXEL)?,
        })
    }

    /// Traces sample 0 of `pixel` (column, row) of the frame `params`
    /// describes (its camera, settings and walk) through `scene`, with the
    /// pipeline the renderer would specialise for that frame (counting the
    /// walks' work), and returns its log.
    pub fn record(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: &FrameParams,
        pixel: (u32, u32),
    ) -> Result<WalkLog> {
        let params = FrameParams {
            tile_origin: [pixel.0, pixel.1],
            tile_size: [1, 1],
            sample_index: 0,
            sample_count: 1,
            ..*params
        };
        let variant = KernelVariant {
            radiance_output: false,
            ..KernelVariant::for_frame(scene, &params, true)
        };
        let pipeline = self.pipelines.get(ctx, variant)?;
        let limit = ctx.device.limits().max_storage_buffer_binding_size / 4;
        let mut room = FIRST_LOG_WORDS.min(limit);
        loop {
            let words = self.dispatch(ctx, scene, &params, &pipeline, room)?;
            let used = words[codes::WORDS_USED as usize] as u64;
            if used <= room || room >= limit {
                return decode(&words);
            }
            room = used.min(limit);
        }
    }

    /// One dispatch with a log of `room` words; the words read back.
    fn dispatch(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: &FrameParams,
        pipeline: &super::TracePipeline,
        room: u64,
    ) -> Result<Vec<u32>> {
        let bytes = room * 4;
        let (bind_group, log, readback) = ctx.checked("allocating the inspect log", |device| {
            let uniform = buffer_holding(
                device,
                "inspect params",
                bytemuck::bytes_of(params),
                wgpu::BufferUsages::UNIFORM,
            );
            let log = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("inspect log"),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("inspect log readback"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let group = self.pipelines.bind_group(device, &uniform, scene, &[&log]);
            (group, log, readback)
        })?;
        let bind_group = bind_group.for_pipeline(ctx, pipeline)?;
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("inspect_pixel"),
            });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("inspect_pixel"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&pipeline.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&log, 0, &readback, 0, bytes);
        ctx.queue.submit([encoder.finish()]);
        let read = ctx.read_buffer(&readback, bytes)?;
        Ok(bytemuck::cast_slice(&read).to_vec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(x: f32) -> u32 {
        x.to_bits()
    }

    /// A log as walk_record.wgsl writes it reads back into its ray, steps,
    /// hit and sample; one cut short or with an unknown tag is an error.
    #[test]
    fn logs_decode_into_rays_steps_and_hits() {
        let mut words = vec![0u32, 0];
        words.extend([codes::RAY, codes::RAY_SHADOW, 1]);
        words.extend([f(0.0), f(1.0), f(2.0), f(0.0), f(0.0), f(1.0), f(5.0)]);
        words.extend([6, codes::LIGHT_SKY, bindings::NO_OBJECT, f(0.25), f(0.5)]);
        words.extend([codes::SEGMENT, f(0.5), f(4.0)]);
        words.extend([codes::NODE, 0, f(0.5), f(4.0), 1, 7, f(2.0), 1]);
        words.extend([codes::LEAF, 1, f(0.5), f(2.0)]);
        words.extend([codes::TESTED, 3, 1, f(1.5)]);
        words.extend([codes::TESTED, 4, 0, f(-1.0)]);
        words.extend([codes::HIT, 3, f(1.5)]);
        words.extend([f(0.0), f(1.0), f(3.5), f(0.0), f(0.0), f(-1.0), 2, 1, 2]);
        words.extend([codes::SAMPLE, f(0.25), f(0.5), f(1.0)]);
        words[0] = words.len() as u32;
        let log = decode(&words).unwrap();
        assert_eq!(log.sample, [0.25, 0.5, 1.0]);
        assert_eq!(log.rays.len(), 1);
        let ray = &log.rays[0];
        assert_eq!(
            (ray.kind, ray.any, ray.t_limit),
            (RayKind::Shadow, true, 5.0)
        );
        assert_eq!(ray.ray.dir, Vec3::Z);
        assert_eq!(
            ray.light,
            Some(RecordedLight {
                entry: 6,
                kind: codes::LIGHT_SKY,
                object: bindings::NO_OBJECT,
                pick: 0.25,
                density: 0.5
            })
        );
        assert_eq!(
            ray.walk,
            vec![
                WalkEvent::Segment {
                    t_min: 0.5,
                    t_far: 4.0
                },
                WalkEvent::Node {
                    node: 0,
                    t_min: 0.5,
                    t_max: 4.0,
                    near: 1,
                    far: 7,
                    t_split: 2.0,
                    crosses: true
                },
                WalkEvent::Leaf {
                    node: 1,
                    t_min: 0.5,
                    t_max: 2.0
                },
                WalkEvent::Tested {
                    object: 3,
                    t: Some(1.5)
                },
                WalkEvent::Tested { object: 4, t: None },
            ]
        );
        let hit = ray.hit.unwrap();
        assert_eq!((hit.object, hit.t, hit.normal), (3, 1.5, -Vec3::Z));
        assert_eq!(
            (
                ray.cost.nodes_visited,
                ray.cost.leaves_visited,
                ray.cost.objects_tested
            ),
            (2, 1, 2)
        );

        let mut short = words.clone();
        short.truncate(words.len() - 2);
        short[0] = short.len() as u32 + 2;
        assert!(decode(&short).unwrap_err().to_string().contains("room"));
        let mut cut = words.clone();
        cut[0] = 20;
        assert!(decode(&cut)
            .unwrap_err()
            .to_string()
            .contains("ends inside"));
        let mut odd = words.clone();
        odd[17] = 99; // the SEGMENT record's tag
        assert!(decode(&odd).unwrap_err().to_string().contains("tag 99"));
        let mut unlit = words.clone();
        unlit[12] = bindings::NO_OBJECT; // the shadow ray's light entry
        assert!(decode(&unlit)
            .unwrap_err()
            .to_string()
            .contains("shadow ray"));
    }
}
