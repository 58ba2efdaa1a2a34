//! Adapter choice and device creation.
//!
//! `WGPU_BACKEND` (e.g. `vulkan`, `gl`) limits the backends and
//! `WGPU_ADAPTER_NAME` picks adapters whose name contains it. Among the
//! rest, Vulkan comes first, then the other native APIs, then GL; within a
//! backend, real GPUs before software ones.

use std::any::Any;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::pipeline_cache::PipelineCacheFile;
use crate::error::{Error, Result};

/// What to install when no adapter is found.
pub const NO_ADAPTER_HELP: &str = "no GPU adapter found (Vulkan or GL). On Debian/Ubuntu install a driver, \
e.g. `apt-get install mesa-vulkan-drivers libvulkan1` (lavapipe, software Vulkan) or \
`apt-get install libegl1 libegl-mesa0` (llvmpipe over EGL); check WGPU_BACKEND and WGPU_ADAPTER_NAME";

pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    /// Whether compute passes can write timestamps (for `gpu_ms`).
    pub has_timestamps: bool,
    /// The first uncaptured error or device loss, reported by wgpu's callbacks.
    fault: Arc<Mutex<Option<String>>>,
    /// Each entry point's pipelines by its name, shared by every renderer,
    /// query and inspector made on this context: a pipeline is compiled
    /// once per process (llvmpipe takes seconds), not once per frame.
    /// Kept and read by gpu/trace_pipelines.rs (`trace_pipelines`).
    pub(super) trace_pipelines: Mutex<HashMap<&'static str, Arc<dyn Any + Send + Sync>>>,
    /// Compiled pipelines kept between processes, where the adapter offers
    /// a pipeline cache (gpu/pipeline_cache.rs).
    pub pipeline_cache: Option<PipelineCacheFile>,
}

fn instance(backends: wgpu::Backends) -> wgpu::Instance {
    give_mesa_a_runtime_dir();
    let desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    // WGPU_BACKEND, when set, has already narrowed desc.backends.
    wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: desc.backends & backends,
        ..desc
    })
}

/// Keeps Mesa from printing `error: XDG_RUNTIME_DIR is invalid or not set in
/// the environment.` on headless machines. wgpu enables `VK_KHR_wayland_surface`
/// on every Vulkan instance, so Mesa's device-selection layer
/// (`VK_LAYER_MESA_device_select`) tries to connect to a Wayland compositor
/// when it lists devices, and libwayland prints that line (twice per run) when
/// the variable is unset or not an absolute path. With it pointing at an empty
/// private folder the connection fails quietly (no socket there), and devices
/// are listed as before. A valid value is never touched.
///
/// Runs once, before the first instance (the window calls it before its
/// event loop, since it makes its own instances): in the CLI that is before
/// any other thread exists (setting a variable races with C code reading the
/// environment on other threads). The folder is `kdray-runtime-UID` in the
/// temporary folder, mode 0700, and is used only if it is a real folder owned
/// by this user that nobody else can open; otherwise nothing is set.
pub(crate) fn give_mesa_a_runtime_dir() {
    #[cfg(all(unix, not(target_os = "macos")))]
    {
        static ONCE: std::sync::Once = std::sync::Once::new();
        ONCE.call_once(|| {
            let valid = std::env::var_os("XDG_RUNTIME_DIR")
                .is_some_and(|dir| std::path::Path::new(&dir).is_absolute());
            if !valid {
                if let Some(dir) = private_runtime_dir() {
                    std::env::set_var("XDG_RUNTIME_DIR", dir);
                }
            }
        });
    }
}

/// `$TMPDIR/kdray-runtime-UID`, created with mode 0700 if absent; `None` if
/// it cannot be made or is not a folder of this user's that only they can open.
#[cfg(all(unix, not(target_os = "macos")))]
fn private_runtime_dir() -> Option<std::path::PathBuf> {
    use std::os::unix::fs::{DirBuilderExt, MetadataExt};
    // SAFETY: getuid has no preconditions and cannot fail.
    let uid = unsafe { libc::getuid() };
    let dir = std::env::temp_dir().join(format!("kdray-runtime-{uid}"));
    // An existing folder is checked below; any other failure shows there too.
    let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
    let meta = std::fs::symlink_metadata(&dir).ok()?;
    let private = meta.is_dir() && meta.uid() == uid && meta.mode() & 0o077 == 0;
    (private && dir.is_absolute()).then_some(dir)
}

fn backend_rank(b: wgpu::Backend) -> u32 {
    match b {
        wgpu::Backend::Vulkan => 0,
        wgpu::Backend::Metal | wgpu::Backend::Dx12 => 1,
        wgpu::Backend::Gl => 2,
        _ => 3,
    }
}

fn device_rank(t: wgpu::DeviceType) -> u32 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

/// All adapters wgpu sees (after WGPU_BACKEND), best first, and the index of
/// the one kdray picks (the first whose name matches WGPU_ADAPTER_NAME).
pub fn ranked_adapters() -> (Vec<wgpu::Adapter>, Option<usize>) {
    ranked_adapters_of(wgpu::Backends::all())
}

fn ranked_adapters_of(backends: wgpu::Backends) -> (Vec<wgpu::Adapter>, Option<usize>) {
    rank(pollster::block_on(
        instance(backends).enumerate_adapters(backends),
    ))
}

/// Sorts adapters best first and picks the first whose name contains
/// WGPU_ADAPTER_NAME (any, if it is unset).
fn rank(mut adapters: Vec<wgpu::Adapter>) -> (Vec<wgpu::Adapter>, Option<usize>) {
    adapters.sort_by_key(|a| {
        let info = a.get_info();
        (backend_rank(info.backend), device_rank(info.device_type))
    });
    let wanted = std::env::var("WGPU_ADAPTER_NAME")
        .ok()
        .map(|s| s.to_lowercase());
    let pick = adapters.iter().position(|a| match &wanted {
        Some(name) => a.get_info().name.to_lowercase().contains(name.as_str()),
        None => true,
    });
    (adapters, pick)
}

/// The largest storage buffer the device can bind, in bytes: kdray's limit
/// on any one buffer (scene arrays, output tiles, accumulation).
pub fn max_binding_bytes(limits: &wgpu::Limits) -> u64 {
    limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size)
}

/// A buffer holding `contents`, written through a mapping at creation. Not
/// `create_buffer_init`: it panics when the device is lost. A failed mapping
/// leaves an invalid buffer, which the caller's error scope
/// ([`GpuContext::checked`]) reports as one error line.
pub fn buffer_holding(
    device: &wgpu::Device,
    label: &str,
    contents: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: contents.len() as u64,
        usage,
        mapped_at_creation: true,
    });
    if let Ok(mut view) = buffer.slice(..).get_mapped_range_mut() {
        view.copy_from_slice(contents);
    }
    buffer.unmap();
    buffer
}

/// One line describing an adapter, as `kdray info` and `--stats` show it.
pub fn describe(info: &wgpu::AdapterInfo) -> String {
    format!(
        "{} ({:?}, {:?}, driver {} {})",
        info.name, info.backend, info.device_type, info.driver, info.driver_info
    )
}

impl GpuContext {
    pub fn new() -> Result<Self> {
        // Native APIs first; GL only if none of them offers an adapter (which
        // also spares the EGL probe and its warnings when Vulkan works).
        let (mut adapters, mut pick) = ranked_adapters_of(
            wgpu::Backends::VULKAN | wgpu::Backends::METAL | wgpu::Backends::DX12,
        );
        if pick.is_none() {
            (adapters, pick) = ranked_adapters();
        }
        let Some(pick) = pick else {
            return Err(match std::env::var("WGPU_ADAPTER_NAME") {
                Ok(name) if !adapters.is_empty() => Error::Gpu(format!("no adapter's name contains WGPU_ADAPTER_NAME={name:?}; `kdray info` lists them")),
                _ => Error::Gpu(NO_ADAPTER_HELP.to_string()),
            });
        };
        Self::open_device(adapters.swap_remove(pick))
    }

    /// Opens a device on the best adapter of `instance` that can present to
    /// `surface` (the interactive window). Adapters are ranked as in
    /// [`GpuContext::new`] (WGPU_ADAPTER_NAME honoured, Vulkan first, real GPUs
    /// before software ones), and the device is set up the same way.
    pub fn for_surface(instance: &wgpu::Instance, surface: &wgpu::Surface<'_>) -> Result<Self> {
        let supported = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
            .into_iter()
            .filter(|a| a.is_surface_supported(surface))
            .collect();
        let (mut adapters, pick) = rank(supported);
        let wanted = std::env::var("WGPU_ADAPTER_NAME").ok();
        let Some(pick) = pick else {
            return Err(Error::Gpu(match wanted {
                Some(name) if !adapters.is_empty() => format!("no adapter that can draw to the window has a name containing WGPU_ADAPTER_NAME={name:?}; `kdray info` lists adapters"),
                _ => format!("no GPU adapter can draw to the window; {NO_ADAPTER_HELP}"),
            }));
        };
        Self::open_device(adapters.swap_remove(pick))
    }

    /// Opens the device on `adapter` with its own limits, timestamps where
    /// offered, and wgpu's error callbacks recorded (as `new` does).
    fn open_device(adapter: wgpu::Adapter) -> Result<Self> {
        let info = adapter.get_info();
        let has_timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut required_features = wgpu::Features::empty();
        if has_timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        let cached = PipelineCacheFile::wanted(&adapter);
        if cached {
            required_features |= wgpu::Features::PIPELINE_CACHE;
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("kdray"),
            required_features,
            // Everything the adapter offers: large scenes need its real
            // storage-buffer limits, not WebGPU's defaults.
            required_limits: adapter.limits(),
            memory_hints: wgpu::MemoryHints::MemoryUsage,
            ..Default::default()
        }))
        .map_err(|e| Error::Gpu(format!("cannot open a device on {}: {e}", describe(&info))))?;
        // wgpu panics on uncaptured errors by default; record them instead
        // and turn them into one error line at the next check.
        let fault = Arc::new(Mutex::new(None));
        let record = |fault: &Arc<Mutex<Option<String>>>, message: String| {
            if let Ok(mut slot) = fault.lock() {
                slot.get_or_insert(message);
            }
        };
        let f = fault.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            record(&f, format!("GPU error: {e}"))
        }));
        let f = fault.clone();
        device.set_device_lost_callback(move |reason, message| {
            record(&f, format!("GPU device lost ({reason:?}): {message}"))
        });
        let pipeline_cache = cached
            .then(|| PipelineCacheFile::open(&device, &info))
            .flatten();
        Ok(GpuContext {
            adapter,
            device,
            queue,
            info,
            has_timestamps,
            fault,
            trace_pipelines: Mutex::new(HashMap::new()),
            pipeline_cache,
        })
    }

    /// Whether the adapter is Mesa's llvmpipe (lavapipe, or GL on llvmpipe),
    /// which silently ends an invocation's loops once they have run 65,535
    /// iterations in all: pixels whose paths need more come out wrong.
    pub fn has_loop_limit(&self) -> bool {
        self.info.name.contains("llvmpipe") || self.info.driver.contains("llvmpipe")
    }

    /// The adapter's description for reports.
    pub fn adapter_line(&self) -> String {
        describe(&self.info)
    }

    /// Fails if wgpu reported an uncaptured error or the device was lost.
    pub fn check_health(&self) -> Result<()> {
        match self.fault.lock().ok().and_then(|slot| slot.clone()) {
            Some(message) => Err(Error::Gpu(message)),
            None => Ok(()),
        }
    }

    /// Runs `f` inside validation and out-of-memory error scopes; an error
    /// becomes `Error::Gpu("<what>: <error>")`.
    pub fn checked<T>(&self, what: &str, f: impl FnOnce(&wgpu::Device) -> T) -> Result<T> {
        self.check_health()?;
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f(&self.device);
        // Scopes pop in reverse order. Out-of-memory comes first in the
        // report: a failed allocation leaves invalid buffers, and the
        // validation errors that follow from them are only its echo.
        let validation_error = pollster::block_on(validation.pop());
        let oom_error = pollster::block_on(oom.pop());
        let one_line = |e: wgpu::Error| {
            e.to_string()
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect::<Vec<_>>()
                .join(" ")
        };
        if let Some(e) = oom_error {
            let detail = one_line(e);
            let detail = if detail.eq_ignore_ascii_case("out of memory") {
                String::new()
            } else {
                format!(" ({detail})")
            };
            return Err(Error::Gpu(format!(
                "{what}: out of GPU memory on {}{detail}",
                self.info.name
            )));
        }
        if let Some(e) = validation_error {
            return Err(Error::Gpu(format!("{what}: {}", one_line(e))));
        }
        self.check_health()?;
        Ok(value)
    }
}
