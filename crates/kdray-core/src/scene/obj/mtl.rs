//! MTL material libraries: `newmtl`, the Phong colours kdray uses
//! (`Ka`, `Kd`, `Ks`, `Ns`), glass (`d`, `Tr`, `Ni`) and the diffuse
//! texture `map_Kd` (decoded here, bilinear and trilinear between its mip
//! levels, repeating unless
//! `-clamp on`; its other options are skipped); every other statement is
//! ignored, and the other texture statements (`map_Ka`, `map_Ks`, `bump`,
//! `disp`, `decal`, `refl`, `norm`, ...) with one warning per file: a model
//! that renders without them should say why. A `map_Kd` image that cannot
//! be read or decoded is a warning naming the file; the material keeps its
//! flat `Kd`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;

use super::tokens::{first_three_numbers, parse_number, rest_of_line, statement_error, statements};
use crate::scene::error::SceneError;
use crate::scene::mesh::MeshMaterial;
use crate::scene::texture::{MinFilter, Texture, TextureFilter, TextureWrap};
use crate::scene::warning::Warning;

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
    // Each map_Kd image decoded once per file (and clamp mode).
    let mut decoded: HashMap<(PathBuf, bool), Option<Arc<Texture>>> = HashMap::new();
    // The material being defined; added to the library when the next one
    // starts or the file ends.
    let mut current: Option<MeshMaterial> = None;
    fn finish(material: Option<MeshMaterial>, library: &mut HashMap<String, MeshMaterial>) {
        if let Some(material) = material {
            library.entry(material.name.clone()).or_insert(material);
        }
    }

    for (line_no, line, keyword, tokens) in statements(text) {
        let err = statement_error(path, line_no, keyword);

        if keyword.eq_ignore_ascii_case("newmtl") {
            let name = rest_of_line(line, keyword);
            if name.is_empty() {
                return Err(err("expected a material name".to_string()));
            }
            finish(current.take(), library);
            current = Some(new_material(name));
            continue;
        }
        if keyword.eq_ignore_ascii_case("map_Kd") {
            let Some(material) = current.as_mut() else {
                return Err(err("comes before any newmtl statement".to_string()));
            };
            let Some((file, clamp)) = map_statement(line, keyword) else {
                return Err(err("expected the name of an image file".to_string()));
            };
            let image = texture_file(path, file);
            material.texture = decoded
                .entry((image.clone(), clamp))
                .or_insert_with(|| {
                    decode_map_kd(file, &image, clamp)
                        .map(Some)
                        .unwrap_or_else(|e| {
                            warnings.push(Warning::new(
                                path,
                                Some(line_no),
                                format!(
                                    "cannot read texture {}: {e}; material '{}' uses its flat Kd",
                                    image.display(),
                                    material.name
                                ),
                            ));
                            None
                        })
                })
                .clone();
            continue;
        }

        let is_colour = ["Ka", "Kd", "Ks", "Ke"]
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
            continue; // illum, ...
        }
        let Some(material) = current.as_mut() else {
            return Err(err("comes before any newmtl statement".to_string()));
        };
        if is_glass {
            read_glass(material, keyword, tokens);
        } else {
            read_colour_or_shininess(material, keyword, tokens).map_err(err)?;
        }
    }
    finish(current.take(), library);
    if let Some((line, keyword)) = first_texture {
        warnings.push(ignored_textures_warning(path, line, &keyword, textures));
    }
    Ok(())
}

/// A material named `name` before any of its statements: black, matte,
/// opaque, untextured.
fn new_material(name: &str) -> MeshMaterial {
    MeshMaterial {
        name: name.to_string(),
        ambient: DVec3::ZERO,
        diffuse: DVec3::ZERO,
        specular: DVec3::ZERO,
        shininess: 0.0,
        reflection: 0.0,
        transmission: 0.0,
        ior: crate::scene::material::Material::DEFAULT_IOR,
        texture: None,
        physical: crate::scene::material::Physical::LAMBERTIAN,
        maps: crate::scene::material::MaterialMaps::NONE,
        alpha: crate::scene::alpha::Alpha::OPAQUE,
    }
}

/// `map_Kd`'s image `file` (found at `image`), decoded with its mip levels:
/// bilinear within a level, trilinear between them, repeating unless
/// `clamp`. The error says why it cannot be read or decoded.
fn decode_map_kd(file: &str, image: &Path, clamp: bool) -> Result<Arc<Texture>, String> {
    let wrap = if clamp {
        TextureWrap::ClampToEdge
    } else {
        TextureWrap::Repeat
    };
    // Only a regular file (`map_Kd /dev/zero` would be read forever).
    let bytes = crate::scene::input_file::read_input_file(image).map_err(|e| e.to_string())?;
    let texture = Texture::decode(
        file,
        &bytes,
        TextureFilter::Bilinear,
        MinFilter::TRILINEAR,
        [wrap; 2],
    )?;
    Ok(Arc::new(texture))
}

/// `d`, `Tr` or `Ni`, read leniently, as before these were read at all:
/// `d -halo v` takes v; anything but one number leaves the statement unread.
fn read_glass<'t>(
    material: &mut MeshMaterial,
    keyword: &str,
    tokens: impl Iterator<Item = &'t str>,
) {
    let words: Vec<&str> = tokens
        .filter(|w| !w.eq_ignore_ascii_case("-halo"))
        .collect();
    if let [word] = words[..] {
        if let Ok(value) = parse_number(word) {
            set_glass(material, keyword, value);
        }
    }
}

/// `Ns x`, or `Ka`/`Kd`/`Ks` as three numbers or one (a grey); the error
/// message (without file and line) for anything else.
fn read_colour_or_shininess<'t>(
    material: &mut MeshMaterial,
    keyword: &str,
    tokens: impl Iterator<Item = &'t str>,
) -> Result<(), String> {
    let (values, count) = first_three_numbers(tokens)?;
    if keyword.eq_ignore_ascii_case("Ns") {
        if count != 1 {
            return Err(format!("expected 1 number, found {count}"));
        }
        if values[0] < 0.0 {
            return Err(format!("shininess must be >= 0, found {}", values[0]));
        }
        material.shininess = values[0];
        return Ok(());
    }
    let colour = match count {
        1 => DVec3::splat(values[0]),
        3 => DVec3::from_array(values),
        _ => {
            return Err(format!(
                "expected 3 numbers (r g b) or 1 (grey), found {count}"
            ))
        }
    };
    match keyword.as_bytes()[1].to_ascii_lowercase() {
        b'a' => material.ambient = colour,
        b'd' => material.diffuse = colour,
        // Emitted radiance: the path tracer's light.
        b'e' => material.physical.emission = colour.max(DVec3::ZERO),
        _ => material.specular = colour,
    }
    Ok(())
}

/// The one warning for a file's texture statements other than `map_Kd`:
/// the first one's line and keyword, and how many more there are.
fn ignored_textures_warning(path: &Path, line: usize, keyword: &str, count: usize) -> Warning {
    let more = match count - 1 {
        0 => String::new(),
        1 => " (and 1 more texture statement)".to_string(),
        n => format!(" (and {n} more texture statements)"),
    };
    Warning::new(
        path,
        Some(line),
        format!("{keyword}{more} ignored: kdray reads no textures but map_Kd; faces use the flat colours Ka, Ks"),
    )
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

/// The image file of a `map_*` statement and whether it asks for
/// `-clamp on`; the options before the file name are skipped (each with
/// its arguments). None where no file name is left.
fn map_statement<'l>(line: &'l str, keyword: &str) -> Option<(&'l str, bool)> {
    let mut rest = rest_of_line(line, keyword);
    let mut clamp = false;
    while let Some(option) = rest.strip_prefix('-') {
        let mut words = option.splitn(2, |c: char| c.is_ascii_whitespace());
        let name = words.next()?.to_ascii_lowercase();
        rest = words.next().unwrap_or("").trim_start();
        // -o, -s and -t take up to three numbers; -mm two; the rest one.
        let arguments = match name.as_str() {
            "o" | "s" | "t" => 3,
            "mm" => 2,
            _ => 1,
        };
        for k in 0..arguments {
            let mut words = rest.splitn(2, |c: char| c.is_ascii_whitespace());
            let word = words.next().unwrap_or("");
            if word.is_empty() || (k > 0 && parse_number(word).is_err()) {
                break;
            }
            if name == "clamp" {
                clamp = word.eq_ignore_ascii_case("on");
            }
            rest = words.next().unwrap_or("").trim_start();
        }
    }
    (!rest.is_empty()).then_some((rest, clamp))
}

/// An MTL statement that names a texture image.
fn is_texture_statement(keyword: &str) -> bool {
    let lower = keyword.to_ascii_lowercase();
    lower.starts_with("map_") || ["bump", "disp", "decal", "refl", "norm"].contains(&lower.as_str())
}

/// Where a `map_Kd` statement's `file` lies: relative to the MTL file's
/// folder (an absolute path as it is). MTL files written on Windows name
/// their images with backslashes (`.\wood.jpg`), which other readers take
/// as separators: where the name as written is no file, the name with `/`
/// for `\` is used.
fn texture_file(mtl: &Path, file: &str) -> std::path::PathBuf {
    let folder = mtl.parent().unwrap_or(Path::new(""));
    let as_written = folder.join(file);
    if as_written.exists() || !file.contains('\\') {
        return as_written;
    }
    let slashed = folder.join(file.replace('\\', "/"));
    if slashed.exists() {
        slashed
    } else {
        as_written
    }
}
