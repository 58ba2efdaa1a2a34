//! Hot reload: the window polls the scene file and the files it loads (OBJ
//! meshes and their MTL libraries) for changes of modification time or size.
//! No watcher crate and no thread: a `stat` per file every [`POLL_INTERVAL`].
//!
//! A change is acted on once the files have stayed the same for one more
//! poll, so an editor's half-written file is not read (a reload that does see
//! one fails, and the completed write is picked up by the next poll).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

/// Time between two polls of the files.
pub const POLL_INTERVAL: Duration = Duration::from_millis(100);

/// What identifies a version of a file: modification time, size and (on
/// Unix) inode, which an editor's save-by-rename changes; None if it cannot
/// be read.
type Stamp = Option<(SystemTime, u64, u64)>;

fn stamp(path: &Path) -> Stamp {
    let meta = std::fs::metadata(path).ok()?;
    #[cfg(unix)]
    let inode = std::os::unix::fs::MetadataExt::ino(&meta);
    #[cfg(not(unix))]
    let inode = 0;
    Some((meta.modified().ok()?, meta.len(), inode))
}

pub struct SceneWatcher {
    scene: PathBuf,
    /// Scene file first, then its meshes and MTL files, with their stamps.
    files: Vec<(PathBuf, Stamp)>,
    next_poll: Instant,
    /// A change was seen and the files have not been stable since.
    unsettled: bool,
}

impl SceneWatcher {
    /// Starts watching `scene` and the files it names, as they are now.
    pub fn new(scene: &Path) -> Self {
        let mut watcher = SceneWatcher {
            scene: scene.to_path_buf(),
            files: Vec::new(),
            next_poll: Instant::now() + POLL_INTERVAL,
            unsettled: false,
        };
        watcher.rescan();
        watcher
    }

    /// The files watched now.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        self.files.iter().map(|(p, _)| p.as_path())
    }

    /// When the next poll is due.
    pub fn next_poll(&self) -> Instant {
        self.next_poll
    }

    /// Polls if one is due at `now`: true when a change has settled and the
    /// scene should be reloaded (then call [`SceneWatcher::rescan`] after
    /// reloading, so the watched files follow the scene's new mesh list).
    pub fn poll(&mut self, now: Instant) -> bool {
        if now < self.next_poll {
            return false;
        }
        self.next_poll = now + POLL_INTERVAL;
        let mut changed = false;
        for (path, old) in &mut self.files {
            let new = stamp(path);
            if new != *old {
                *old = new;
                changed = true;
            }
        }
        if changed {
            self.unsettled = true;
            return false;
        }
        std::mem::take(&mut self.unsettled)
    }

    /// Re-reads the list of files the scene loads and their stamps.
    pub fn rescan(&mut self) {
        let mut paths = vec![self.scene.clone()];
        for p in scene_dependencies(&self.scene) {
            if !paths.contains(&p) {
                paths.push(p);
            }
        }
        self.files = paths
            .into_iter()
            .map(|p| {
                let s = stamp(&p);
                (p, s)
            })
            .collect();
    }
}

/// The OBJ files a scene file's `[[meshes]]` name (relative to its folder,
/// as the scene loader resolves them) and the MTL files those OBJs name.
/// Best effort: a file that does not parse names nothing.
pub fn scene_dependencies(scene: &Path) -> Vec<PathBuf> {
    let Ok(text) = std::fs::read_to_string(scene) else {
        return Vec::new();
    };
    let mesh_paths: Vec<String> = match crate::scene::SceneFormat::from_path(scene) {
        crate::scene::SceneFormat::Json => serde_json::from_str::<serde_json::Value>(&text)
            .ok()
            .and_then(|v| {
                v.get("meshes")?.as_array().map(|meshes| {
                    meshes
                        .iter()
                        .filter_map(|m| Some(m.get("path")?.as_str()?.to_string()))
                        .collect()
                })
            })
            .unwrap_or_default(),
        crate::scene::SceneFormat::Toml => toml::from_str::<toml::Table>(&text)
            .ok()
            .and_then(|t| {
                t.get("meshes")?.as_array().map(|meshes| {
                    meshes
                        .iter()
                        .filter_map(|m| Some(m.get("path")?.as_str()?.to_string()))
                        .collect()
                })
            })
            .unwrap_or_default(),
    };
    let base = scene.parent().unwrap_or(Path::new(""));
    let mut files = Vec::new();
    for mesh in mesh_paths {
        let obj = base.join(mesh);
        if let Ok(obj_text) = std::fs::read(&obj) {
            let obj_dir = obj.parent().unwrap_or(Path::new("")).to_path_buf();
            for line in String::from_utf8_lossy(&obj_text).lines() {
                let mut tokens = line.split('#').next().unwrap_or("").split_whitespace();
                if tokens.next() == Some("mtllib") {
                    files.extend(tokens.map(|name| obj_dir.join(name)));
                }
            }
        }
        files.push(obj);
    }
    files
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("kdray-reload-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("models")).unwrap();
        dir
    }

    #[test]
    fn finds_meshes_and_their_mtl_files() {
        let dir = temp_dir("deps");
        std::fs::write(
            dir.join("models/a.obj"),
            "mtllib a.mtl b.mtl # two\nv 0 0 0\n",
        )
        .unwrap();
        std::fs::write(dir.join("s.toml"), "[[meshes]]\npath = \"models/a.obj\"\n").unwrap();
        std::fs::write(
            dir.join("s.json"),
            r#"{"meshes": [{"path": "models/a.obj"}, {"path": "missing.obj"}]}"#,
        )
        .unwrap();
        let expected = vec![
            dir.join("models/a.mtl"),
            dir.join("models/b.mtl"),
            dir.join("models/a.obj"),
        ];
        assert_eq!(scene_dependencies(&dir.join("s.toml")), expected);
        let mut json = expected.clone();
        json.push(dir.join("missing.obj"));
        assert_eq!(scene_dependencies(&dir.join("s.json")), json);
        // Broken or missing scene files name nothing.
        std::fs::write(dir.join("broken.toml"), "[[meshes]\n").unwrap();
        assert!(scene_dependencies(&dir.join("broken.toml")).is_empty());
        assert!(scene_dependencies(&dir.join("nothing.toml")).is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_change_is_reported_once_it_has_settled() {
        let dir = temp_dir("poll");
        let scene = dir.join("s.toml");
        let obj = dir.join("models/a.obj");
        std::fs::write(&obj, "v 0 0 0\n").unwrap();
        std::fs::write(&scene, "[[meshes]]\npath = \"models/a.obj\"\n").unwrap();
        let mut w = SceneWatcher::new(&scene);
        assert_eq!(w.files().count(), 2);
        let mut t = Instant::now();
        let tick = |w: &mut SceneWatcher, t: &mut Instant| {
            *t += POLL_INTERVAL;
            w.poll(*t)
        };
        assert!(!tick(&mut w, &mut t));
        // A different size is a change even within one timestamp tick.
        std::fs::write(&obj, "v 0 0 0\nv 1 0 0\n").unwrap();
        assert!(!tick(&mut w, &mut t), "reported before it settled");
        assert!(tick(&mut w, &mut t), "not reported after it settled");
        assert!(!tick(&mut w, &mut t), "reported twice");
        // Polls are not due before the interval.
        std::fs::write(&scene, "# changed\n[[meshes]]\npath = \"models/a.obj\"\n").unwrap();
        assert!(!w.poll(t));
        assert!(!tick(&mut w, &mut t));
        assert!(tick(&mut w, &mut t));
        // A deleted file is a change too.
        std::fs::remove_file(&obj).unwrap();
        assert!(!tick(&mut w, &mut t));
        assert!(tick(&mut w, &mut t));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
