//! Which texture coordinates a glTF material's textures read, and
//! `KHR_texture_transform` applied to them. Each texture slot (base colour,
//! metallic-roughness, normal, emissive, occlusion) reads a `TEXCOORD_n`
//! set (its `texCoord`, or the transform's override) with its transform
//! (`offset`, `rotation`, `scale`). A triangle keeps up to two channels of
//! coordinates, each a set with a transform applied once, when the file is
//! read: the first is the base colour texture's choice (else the first
//! map's), the second the first other choice a slot makes. A slot that
//! makes a third choice reads the first channel, and its material gets one
//! warning.

use glam::DVec2;
use serde_json::Value;

const EXTENSION: &str = "KHR_texture_transform";

/// `KHR_texture_transform`'s affine map of texture coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct UvTransform {
    offset: DVec2,
    /// Radians.
    rotation: f64,
    scale: DVec2,
}

impl UvTransform {
    /// The extension's object, with its defaults (offset 0, rotation 0,
    /// scale 1) for missing or malformed members.
    fn parse(value: &Value) -> UvTransform {
        let pair = |key: &str, default: f64| {
            let v = value.get(key).and_then(Value::as_array);
            let at = |i: usize| v.and_then(|v| v.get(i)).and_then(Value::as_f64);
            DVec2::new(at(0).unwrap_or(default), at(1).unwrap_or(default))
        };
        UvTransform {
            offset: pair("offset", 0.0),
            rotation: value.get("rotation").and_then(Value::as_f64).unwrap_or(0.0),
            scale: pair("scale", 1.0),
        }
    }

    /// translation * rotation * scale applied to `uv`, as the extension's
    /// specification writes it (its rotation matrix's columns are
    /// (cos, sin) and (-sin, cos)).
    pub(super) fn apply(&self, uv: DVec2) -> DVec2 {
        let (s, c) = self.rotation.sin_cos();
        let p = uv * self.scale;
        DVec2::new(c * p.x - s * p.y, s * p.x + c * p.y) + self.offset
    }
}

/// The coordinates a material's textures read: a `TEXCOORD_n` set and the
/// transform, if any, to apply to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct UvChoice {
    pub set: u32,
    pub transform: Option<UvTransform>,
    /// The slot they come from, for messages.
    pub slot: &'static str,
}

/// One texture slot's coordinates: its `texCoord`, or the transform's
/// override, and its transform.
fn slot_choice(slot: &'static str, tex_coord: u32, transform: Option<&Value>) -> UvChoice {
    let set = transform
        .and_then(|t| t.get("texCoord"))
        .and_then(Value::as_u64)
        .and_then(|s| u32::try_from(s).ok())
        .unwrap_or(tex_coord);
    UvChoice {
        set,
        transform: transform.map(UvTransform::parse),
        slot,
    }
}

/// The two channels of coordinates a material's textures read.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct UvChannels {
    pub first: UvChoice,
    pub second: Option<UvChoice>,
    /// The slots ([`crate::scene::UV_SLOT_BASE`] and its neighbours) that
    /// read the second channel.
    pub second_slots: u32,
    /// A slot whose choice is neither channel's (it reads the first).
    pub unmatched: Option<&'static str>,
}

/// The channels `material`'s textures read; None without a texture.
pub(super) fn uv_channels(material: &gltf::Material) -> Option<UvChannels> {
    use crate::scene::{
        UV_SLOT_BASE, UV_SLOT_EMISSIVE, UV_SLOT_METAL_ROUGH, UV_SLOT_NORMAL, UV_SLOT_OCCLUSION,
    };
    let pbr = material.pbr_metallic_roughness();
    let info = |slot, i: gltf::texture::Info| {
        slot_choice(slot, i.tex_coord(), i.extension_value(EXTENSION))
    };
    let slots: Vec<(u32, UvChoice)> = [
        pbr.base_color_texture()
            .map(|i| (UV_SLOT_BASE, info("baseColorTexture", i))),
        pbr.metallic_roughness_texture()
            .map(|i| (UV_SLOT_METAL_ROUGH, info("metallicRoughnessTexture", i))),
        material.normal_texture().map(|n| {
            let c = slot_choice("normalTexture", n.tex_coord(), n.extension_value(EXTENSION));
            (UV_SLOT_NORMAL, c)
        }),
        material
            .emissive_texture()
            .map(|i| (UV_SLOT_EMISSIVE, info("emissiveTexture", i))),
        material.occlusion_texture().map(|o| {
            let c = slot_choice(
                "occlusionTexture",
                o.tex_coord(),
                o.extension_value(EXTENSION),
            );
            (UV_SLOT_OCCLUSION, c)
        }),
    ]
    .into_iter()
    .flatten()
    .collect();
    let (_, first) = *slots.first()?;
    let same = |a: &UvChoice, b: &UvChoice| a.set == b.set && a.transform == b.transform;
    let mut channels = UvChannels {
        first,
        second: None,
        second_slots: 0,
        unmatched: None,
    };
    for (bit, choice) in &slots[1..] {
        if same(choice, &first) {
            continue;
        }
        match channels.second {
            None => channels.second = Some(*choice),
            Some(second) if !same(choice, &second) => {
                channels.unmatched.get_or_insert(choice.slot);
                continue;
            }
            Some(_) => {}
        }
        channels.second_slots |= bit;
    }
    Some(channels)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The specification's matrix: scale, then rotate counter-clockwise in
    /// (u, v), then offset; defaults leave coordinates as they are.
    #[test]
    fn the_transform_scales_rotates_then_offsets() {
        let t = UvTransform::parse(&serde_json::json!({
            "offset": [0.5, 0.25], "rotation": std::f64::consts::FRAC_PI_2, "scale": [2.0, 3.0]
        }));
        // (1, 1) -> scaled (2, 3) -> rotated a quarter turn (-3, 2) -> (-2.5, 2.25).
        let p = t.apply(DVec2::new(1.0, 1.0));
        assert!((p - DVec2::new(-2.5, 2.25)).length() < 1e-12, "{p}");
        let identity = UvTransform::parse(&serde_json::json!({}));
        assert_eq!(identity.apply(DVec2::new(0.3, 0.7)), DVec2::new(0.3, 0.7));
    }

    #[test]
    fn a_transform_may_choose_another_coordinate_set() {
        let t = serde_json::json!({"texCoord": 1});
        assert_eq!(slot_choice("baseColorTexture", 0, Some(&t)).set, 1);
        assert_eq!(slot_choice("baseColorTexture", 0, None).set, 0);
    }
}
