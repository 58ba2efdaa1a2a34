//! MTL material libraries: `newmtl`, the Phong colours kdray uses
//! (`Ka`, `Kd`, `Ks`, `Ns`) and glass (`d`, `Tr`, `Ni`); every other
//! statement is ignored, and the
//! texture statements (`map_*`, `bump`, `disp`, `decal`, `refl`, `norm`)
//! with one warning per file: kdray has no textures, and a textured model
//! that renders in flat colours should say why.

use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use super::tokens::{parse_number, rest_of_line, strip_comment};
use crate::scene::mesh::MeshMaterial;
use crate::scene::{SceneError, Warning};

/// Parses an MTL file into `library`. A material already in `library`
/// (defined by an earlier MTL file, or earlier in this one) keeps its first
/// definition. Texture statements add one warning to `warnings`.
pub(super) fn parse_mtl(
    text: &str,
    path: &Path,
    library: &mut HashMap<String, MeshMaterial>,
    warnings: &mut Vec<Warning>,
) -> Result<(), SceneError> {
    // The first texture statement's line and keyword, and how many there are.
    let mut first_texture: Option<(usize, String)> = None;
    let mut textures = 0usize;
    // The material being defined; added to the library when the next one
    // starts or the file ends.
    let mut current: Option<MeshMaterial> = None;
    fn finish(material: Option<MeshMaterial>, library: &mut HashMap<String, MeshMaterial>) {
        if let Some(material) = material {
            library.entry(material.name.clone()).or_insert(material);
        }
    }

    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (number, raw) in text.split('\n').enumerate() {
        let line_no = number + 1;
        let line = strip_comment(raw);
        let mut tokens = line.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        let err = |message: String| {
            SceneError::new(path, Some(line_no), Some(keyword.to_string()), message)
        };

        if keyword.eq_ignore_ascii_case("newmtl") {
            let name = rest_of_line(line, keyword);
            if name.is_empty() {
                return Err(err("expected a material name".to_string()));
            }
            finish(current.take(), library);
            current = Some(MeshMaterial {
                name: name.to_string(),
                ambient: DVec3::ZERO,
                diffuse: DVec3::ZERO,
                specular: DVec3::ZERO,
                shininess: 0.0,
                reflection: 0.0,
                transmission: 0.0,
                ior: crate::scene::Material::DEFAULT_IOR,
            });
            continue;
        }

        let is_colour = ["Ka", "Kd", "Ks"]
            .iter()
            .any(|k| keyword.eq_ignore_ascii_case(k));
        let is_shininess = keyword.eq_ignore_ascii_case("Ns");
        let is_glass = ["d", "Tr", "Ni"]
            .iter()
            .any(|k| keyword.eq_ignore_ascii_case(k));
        if is_texture_statement(keyword) {
            textures += 1;
            first_texture.get_or_insert((line_no, keyword.to_string()));
            continue;
        }
        if !is_colour && !is_shininess && !is_glass {
            continue; // illum, Ke, ...
        }
        let Some(material) = current.as_mut() else {
            return Err(err("comes before any newmtl statement".to_string()));
        };
        if is_glass {
            // Read leniently, as before these were read at all: `d -halo v`
            // takes v; anything but one number leaves the statement unread.
            let words: Vec<&str> = tokens
                .filter(|w| !w.eq_ignore_ascii_case("-halo"))
                .collect();
            if let [word] = words[..] {
                if let Ok(value) = parse_number(word) {
                    set_glass(material, keyword, value);
                }
            }
            continue;
        }

        let mut values = [0.0f64; 3];
        let mut count = 0usize;
        for token in tokens {
            let value = parse_number(token).map_err(err)?;
            if count < 3 {
                values[count] = value;
            }
            count += 1;
        }

        if is_shininess {
            if count != 1 {
                return Err(err(format!("expected 1 number, found {count}")));
            }
            if values[0] < 0.0 {
                return Err(err(format!("shininess must be >= 0, found {}", values[0])));
            }
            material.shininess = values[0];
        } else {
            let colour = match count {
                1 => DVec3::splat(values[0]),
                3 => DVec3::from_array(values),
                _ => {
                    return Err(err(format!(
                        "expected 3 numbers (r g b) or 1 (grey), found {count}"
                    )))
                }
            };
            match keyword.as_bytes()[1].to_ascii_lowercase() {
                b'a' => material.ambient = colour,
                b'd' => material.diffuse = colour,
                _ => material.specular = colour,
            }
        }
    }
    finish(current.take(), library);
    if let Some((line, keyword)) = first_texture {
        let more = match textures - 1 {
            0 => String::new(),
            1 => " (and 1 more texture statement)".to_string(),
            n => format!(" (and {n} more texture statements)"),
        };
        warnings.push(Warning::new(
            path,
            Some(line),
            format!("{keyword}{more} ignored: kdray has no textures; faces use the flat colours Ka, Kd, Ks"),
        ));
    }
    Ok(())
}

/// `d` (dissolve: 1 opaque), `Tr` (1 - d) and `Ni` (index of refraction)
/// in kdray's terms: transmission = 1 - d = Tr, clamped into [0, 1]
/// (exporters write values a little outside); an `Ni` of 0 or less (many
/// exporters write `Ni 0` for opaque materials) leaves the default index.
fn set_glass(material: &mut MeshMaterial, keyword: &str, value: f64) {
    if keyword.eq_ignore_ascii_case("Ni") {
        if value > 0.0 {
            material.ior = value;
        }
    } else if keyword.eq_ignore_ascii_case("d") {
        material.transmission = (1.0 - value).clamp(0.0, 1.0);
    } else {
        material.transmission = value.clamp(0.0, 1.0);
    }
}

/// An MTL statement that names a texture image.
fn is_texture_statement(keyword: &str) -> bool {
    let lower = keyword.to_ascii_lowercase();
    lower.starts_with("map_") || ["bump", "disp", "decal", "refl", "norm"].contains(&lower.as_str())
}
