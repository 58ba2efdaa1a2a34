//! Scenes: the validated, world-space description that everything downstream
//! consumes; nothing here knows about the GPU or the k-d tree. This file is
//! the module's face: the types live in `validated_scene` ([`Scene`]),
//! `camera`, `render_settings`, `light`, `material`, `objects` and
//! `triangle_parts`. A scene file goes `input_file` (bytes) -> `load` (TOML or
//! JSON into the `schema`, its library errors worded by `document_errors`
//! with the lines of `source_map`) -> `validate` (every rule, into a
//! `Scene`) -> `mesh_placement` (each `[[meshes]]` entry read through
//! `mesh_file` by `obj` or `gltf` into a `mesh::Mesh`, then placed in the
//! world; each `[shapes.NAME]` loaded once and kept in its own space, and
//! its `[[instances]]` kept as transforms, by `validate_instances`, until
//! `instances` flattens them). `write` turns a `Scene` back into scene file text, and
//! `animation` gives the camera and lights at each frame of an
//! `[animation]`.
//!
//! Units: positions in scene units, angles in degrees in files and radians
//! nowhere in this module (the camera keeps `vfov_degrees`), colours linear.

mod alpha;
mod animation;
mod camera;
mod camera_basis;
mod document_errors;
pub mod environment;
mod error;
mod flatten_instances;
pub mod gltf;
mod input_file;
mod instances;
mod integrator;
mod light;
mod light_kind;
mod light_shape;
mod load;
mod material;
pub mod mesh;
pub mod mesh_file;
mod mesh_placement;
mod model_scene;
mod normals;
pub mod obj;
mod objects;
#[cfg(test)]
mod physical_keys_tests;
mod render_settings;
mod scene_format;
mod schema;
mod source_map;
pub mod tangents;
pub mod texture;
mod triangle_parts;
mod validate;
mod validate_animation;
mod validate_instances;
mod validate_light;
mod validated_scene;
mod warning;
mod write;

pub use alpha::{Alpha, AlphaMode};
pub use animation::{Animation, CameraKey, CameraPath, Frame, FramePath, LightKey, MAX_FRAMES};
pub use camera::Camera;
pub use camera_basis::CameraBasis;
pub use environment::EnvironmentMap;
pub use error::SceneError;
pub use input_file::MAX_INPUT_BYTES;
pub use instances::{transformed_box, Instance, Shape, MAX_FLATTENED_OBJECTS};
pub use integrator::{Integrator, ToneMap};
pub use light::Light;
pub use light_kind::{spot_factor, LightKind};
pub use light_shape::LightShape;
pub use load::{load_scene, load_scene_observed, load_scene_with, parse_scene, parse_scene_with};
pub use material::{
    Material, MaterialMaps, MetalRough, Physical, Volume, UV_SLOT_BASE, UV_SLOT_EMISSIVE,
    UV_SLOT_METAL_ROUGH, UV_SLOT_NORMAL, UV_SLOT_OCCLUSION,
};
pub use model_scene::{model_scene, model_scene_viewed, model_scene_with, ModelCamera};
pub use objects::{Sphere, Triangle};
pub use render_settings::{RenderSettings, ShadowMode};
pub use scene_format::SceneFormat;
pub use texture::{MinFilter, MipMode, Texture, TextureFilter, TextureWrap};
pub use validate::{check_samples, MAX_IMAGE_SIDE};
pub use validated_scene::Scene;
pub use warning::{print_warning, Warning};
pub use write::scene_text;
