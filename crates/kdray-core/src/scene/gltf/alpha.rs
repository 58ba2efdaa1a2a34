//! A glTF material's `alphaMode`, `alphaCutoff` and base-colour alpha, in
//! kdray's terms ([`Alpha`]); a cutoff that is not a number >= 0 is an
//! error naming the material and the key.

use crate::scene::alpha::{Alpha, AlphaMode};
use crate::scene::warning::Warning;

/// The material's alpha: its mode, its cutoff (glTF's default 0.5) and
/// baseColorFactor's alpha, clamped into [0, 1].
pub(super) fn alpha(material: &gltf::Material) -> Alpha {
    let mode = match material.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask,
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    let factor = material.pbr_metallic_roughness().base_color_factor()[3];
    Alpha {
        mode,
        cutoff: material
            .alpha_cutoff()
            .map_or(Alpha::DEFAULT_CUTOFF, f64::from),
        factor: f64::from(factor).clamp(0.0, 1.0),
    }
}

/// Every material's alphaCutoff, as parsed: each a number >= 0 (glTF's
/// minimum), else the first that is not, named.
pub(super) fn check_cutoffs(root: &gltf::json::Root) -> Result<(), String> {
    for (i, m) in root.materials.iter().enumerate() {
        if let Some(c) = m.alpha_cutoff.map(|c| c.0) {
            if !(c >= 0.0 && c.is_finite()) {
                return Err(cutoff_message(i, &c.to_string()));
            }
        }
    }
    Ok(())
}

/// Why the crate could not parse `bytes` where a material's alphaCutoff is
/// not a number (the crate's own message names a line and column only);
/// None where every alphaCutoff is one, or the JSON cannot be read.
pub(super) fn cutoff_type_error(bytes: &[u8]) -> Option<String> {
    let json = match bytes.starts_with(b"glTF") {
        true => gltf::binary::Glb::from_slice(bytes).ok()?.json.into_owned(),
        false => bytes.to_vec(),
    };
    let root: serde_json::Value = serde_json::from_slice(&json).ok()?;
    let materials = root.get("materials")?.as_array()?;
    materials.iter().enumerate().find_map(|(i, m)| {
        let c = m.get("alphaCutoff")?;
        (!c.is_number()).then(|| cutoff_message(i, &c.to_string()))
    })
}

fn cutoff_message(material: usize, value: &str) -> String {
    format!("materials[{material}].alphaCutoff: must be a number >= 0, got {value}")
}

/// The warning for a file with BLEND materials: coverage rather than
/// blending (docs/scene-format.md, "glTF materials").
pub(super) fn blend_warning(path: &std::path::Path) -> Warning {
    Warning::new(
        path,
        None,
        "alphaMode BLEND is approximated: the path tracer lets a ray through with probability 1 - alpha, \
         the Whitted integrator cuts off at alpha 0.5"
            .to_string(),
    )
}
