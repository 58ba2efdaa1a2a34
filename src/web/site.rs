//! The site's files and how they are written: the page (web/, compiled in),
//! the kernel and the present pass exactly as the native host assembles
//! them (`gpu::shaders`), the contract and the bundle, and the denoiser's
//! kernels and weights (`super::denoise`). The folder must be
//! new, empty or a site written before (it holds [`SITE_MARKER`]): a user's
//! folder is never clobbered. Each file is written atomically.

use std::path::Path;

use super::denoise::{self, SiteDenoiser};
use super::{bundle, contract};
use crate::error::{Error, Result};
use crate::gpu::bindings::UNSPLIT;
use crate::gpu::{Accel, PreparedScene};

/// The file that makes a folder a kdray site: the contract.
pub const SITE_MARKER: &str = "contract.json";

/// The page's own files (web/), by name.
pub const PAGE_FILES: [(&str, &str); 9] = [
    ("index.html", include_str!("../../web/index.html")),
    ("kdray.js", include_str!("../../web/kdray.js")),
    ("bundle.js", include_str!("../../web/bundle.js")),
    ("tracer.js", include_str!("../../web/tracer.js")),
    ("controls.js", include_str!("../../web/controls.js")),
    ("heatmap.js", include_str!("../../web/heatmap.js")),
    ("inspect.js", include_str!("../../web/inspect.js")),
    ("overlay.js", include_str!("../../web/overlay.js")),
    ("denoise.js", include_str!("../../web/denoise.js")),
];

/// Loads the scene at `scene_path` (errors as `render`'s), builds its k-d
/// tree and writes the site into `dir`.
pub fn export_site(scene_path: &Path, dir: &Path) -> Result<()> {
    check_site_dir(dir)?;
    let scene = crate::scene::load_scene(scene_path)?;
    let name = scene_path
        .file_name()
        .map_or("scene".into(), |n| n.to_string_lossy().into_owned());
    let prepared = PreparedScene::new(scene, Accel::Kdtree);
    let bundle = bundle::encode(&prepared, &name);
    let denoiser = SiteDenoiser::new()?;
    let mut contract = contract::contract_json();
    contract["denoise"] = denoiser.contract();
    let contract = serde_json::to_vec_pretty(&contract)?;
    std::fs::create_dir_all(dir).map_err(|e| Error::File {
        path: dir.to_path_buf(),
        what: "cannot create the site's folder",
        source: e,
    })?;
    let kernel = crate::gpu::shaders::trace_source(UNSPLIT);
    let present = crate::gpu::shaders::present_source();
    let inspect = crate::gpu::shaders::inspect_source_without(UNSPLIT, &[]);
    let mut files: Vec<(&str, &[u8])> = PAGE_FILES
        .iter()
        .map(|(name, text)| (*name, text.as_bytes()))
        .collect();
    files.extend([
        (contract::KERNEL_FILE, kernel.as_bytes()),
        (contract::PRESENT_FILE, present.as_bytes()),
        (contract::INSPECT_FILE, inspect.as_bytes()),
        (contract::BUNDLE_FILE, &bundle[..]),
        (denoise::WEIGHTS_FILE, &denoiser.layout.bytes[..]),
    ]);
    for (_, file, source) in denoise::SHADER_FILES {
        files.push((file, source.as_bytes()));
    }
    // The marker last: a site cut short is still refused... unless written
    // before, which is a site anyway.
    files.push((SITE_MARKER, &contract));
    for (name, bytes) in files {
        crate::output::write_file_atomic(&dir.join(name), bytes)?;
    }
    Ok(())
}

/// Refuses (as a usage error, exit 2) a `dir` that exists and is neither
/// an empty folder nor a kdray site.
fn check_site_dir(dir: &Path) -> Result<()> {
    let refuse = |why: &str| {
        Err(Error::Usage(format!(
            "{} {why}; give a new folder, an empty one or a kdray site (one with {SITE_MARKER})",
            dir.display()
        )))
    };
    match std::fs::symlink_metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::File {
            path: dir.to_path_buf(),
            what: "cannot read",
            source: e,
        }),
        Ok(meta) if !meta.is_dir() => refuse("exists and is not a folder"),
        Ok(_) => {
            let mut entries = std::fs::read_dir(dir).map_err(|e| Error::File {
                path: dir.to_path_buf(),
                what: "cannot read",
                source: e,
            })?;
            if entries.next().is_none() || dir.join(SITE_MARKER).is_file() {
                Ok(())
            } else {
                refuse("exists and is not a kdray site")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every file in web/ is part of the site.
    #[test]
    fn every_page_file_is_exported() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("web");
        for entry in std::fs::read_dir(dir).unwrap() {
            let name = entry.unwrap().file_name().into_string().unwrap();
            assert!(
                PAGE_FILES.iter().any(|(n, _)| *n == name),
                "web/{name} is not exported"
            );
        }
    }
}
