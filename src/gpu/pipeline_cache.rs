//! Compiled pipelines kept between processes, where the driver keeps them:
//! a `wgpu::PipelineCache` (Vulkan only) loaded from and saved to a file,
//! so that a second `kdray render` on the same adapter can skip compiling.
//! What a driver puts in it is its own: Mesa 22.3's lavapipe writes only a
//! header (no compiled code), so there a second run compiles again.
//!
//! The file is `DIR/wgpu_pipeline_cache_vulkan_VENDOR_DEVICE`
//! (`wgpu::util::pipeline_cache_key`), DIR being `KDRAY_PIPELINE_CACHE`,
//! else `$XDG_CACHE_HOME/kdray`, else `$HOME/.cache/kdray`;
//! `KDRAY_PIPELINE_CACHE=off` keeps no file. The cache is a convenience: a
//! missing, unreadable or stale file gives an empty cache, and a failed save
//! changes nothing else (the render goes on).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The environment variable naming the cache's folder, or `off`.
pub const PIPELINE_CACHE_ENV: &str = "KDRAY_PIPELINE_CACHE";

/// The folder the cache file lives in, from the environment values given
/// (`KDRAY_PIPELINE_CACHE`, `XDG_CACHE_HOME`, `HOME`); `None` when it is
/// `off` or no folder is known. Empty and relative values are ignored, as
/// the XDG base directory specification asks.
pub fn cache_folder(
    kdray: Option<&str>,
    xdg_cache_home: Option<&str>,
    home: Option<&str>,
) -> Option<PathBuf> {
    let absolute = |v: Option<&str>| v.filter(|v| Path::new(v).is_absolute()).map(PathBuf::from);
    match kdray {
        Some("off") => None,
        Some(v) if !v.is_empty() => Some(PathBuf::from(v)),
        _ => absolute(xdg_cache_home)
            .map(|d| d.join("kdray"))
            .or_else(|| absolute(home).map(|h| h.join(".cache").join("kdray"))),
    }
}

/// A device's pipeline cache and the file it is kept in.
pub struct PipelineCacheFile {
    cache: wgpu::PipelineCache,
    path: PathBuf,
    /// The bytes last read or written, so that an unchanged cache is not
    /// written again.
    saved: Mutex<Vec<u8>>,
}

impl PipelineCacheFile {
    /// Whether a device on `adapter` should ask for `Features::PIPELINE_CACHE`:
    /// the adapter offers it and a folder is known.
    pub fn wanted(adapter: &wgpu::Adapter) -> bool {
        adapter.features().contains(wgpu::Features::PIPELINE_CACHE)
            && wgpu::util::pipeline_cache_key(&adapter.get_info()).is_some()
            && folder_from_env().is_some()
    }

    /// The cache of `device` (opened with `Features::PIPELINE_CACHE` on
    /// `info`'s adapter), filled from its file where one is there.
    pub fn open(device: &wgpu::Device, info: &wgpu::AdapterInfo) -> Option<Self> {
        let path = folder_from_env()?.join(wgpu::util::pipeline_cache_key(info)?);
        let saved = std::fs::read(&path).unwrap_or_default();
        // SAFETY: the data is what `get_data` wrote for this adapter's key;
        // wgpu and the driver check its header (vendor, device, driver and
        // cache UUID), and with `fallback` an invalid one gives an empty
        // cache.
        let cache = unsafe {
            device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
                label: Some("kdray pipelines"),
                data: (!saved.is_empty()).then_some(saved.as_slice()),
                fallback: true,
            })
        };
        Some(PipelineCacheFile {
            cache,
            path,
            saved: Mutex::new(saved),
        })
    }

    pub fn cache(&self) -> &wgpu::PipelineCache {
        &self.cache
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes the cache's data to its file if it changed: a temporary file
    /// beside it, then a rename, so that a reader never sees half a cache
    /// and two processes saving at once leave one whole file.
    pub fn save(&self) {
        let Some(data) = self.cache.get_data() else {
            return;
        };
        let Ok(mut saved) = self.saved.lock() else {
            return;
        };
        if *saved == data {
            return;
        }
        if write_atomically(&self.path, &data).is_ok() {
            *saved = data;
        }
    }
}

fn folder_from_env() -> Option<PathBuf> {
    let var = |name: &str| std::env::var(name).ok();
    cache_folder(
        var(PIPELINE_CACHE_ENV).as_deref(),
        var("XDG_CACHE_HOME").as_deref(),
        var("HOME").as_deref(),
    )
}

fn write_atomically(path: &Path, data: &[u8]) -> std::io::Result<()> {
    let folder = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(folder)?;
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let temporary = folder.join(format!(".{name}.{}.tmp", std::process::id()));
    std::fs::write(&temporary, data)?;
    std::fs::rename(&temporary, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&temporary);
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_folder_follows_the_variable_then_xdg_then_home() {
        let home = Some("/home/u");
        assert_eq!(
            cache_folder(Some("/tmp/c"), Some("/x"), home),
            Some(PathBuf::from("/tmp/c"))
        );
        assert_eq!(cache_folder(Some("off"), Some("/x"), home), None);
        assert_eq!(
            cache_folder(None, Some("/x"), home),
            Some(PathBuf::from("/x/kdray"))
        );
        // A relative or empty XDG_CACHE_HOME is ignored.
        for xdg in [Some("x"), Some(""), None] {
            assert_eq!(
                cache_folder(Some(""), xdg, home),
                Some(PathBuf::from("/home/u/.cache/kdray"))
            );
        }
        assert_eq!(cache_folder(None, None, None), None);
        assert_eq!(cache_folder(None, None, Some("rel")), None);
    }

    #[test]
    fn a_saved_file_is_replaced_whole() {
        let folder = std::env::temp_dir().join(format!("kdray-cache-test-{}", std::process::id()));
        let path = folder.join("key");
        write_atomically(&path, b"first, longer").unwrap();
        write_atomically(&path, b"second").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second");
        let left: Vec<_> = std::fs::read_dir(&folder).unwrap().collect();
        assert_eq!(left.len(), 1, "a temporary file was left: {left:?}");
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
