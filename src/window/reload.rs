//! Hot reload: the window polls the scene file and the files it loads (meshes,
//! MTL libraries, glTF buffers: whatever the scene loader reported reading)
//! for changes of modification time or size.
//! No watcher crate: a `stat` per file every [`POLL_INTERVAL`].
//!
//! A change is acted on once the files have stayed the same for one more
//! poll, so an editor's half-written file is not read (a reload that does see
//! one fails, and the completed write is picked up by the next poll). The
//! reload itself (parsing, the tree build) runs on a worker thread through
//! [`LatestJob`], so the window keeps drawing while a big scene loads.
//! [`load`] is what it runs.

use std::path::{Path, PathBuf};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime};

/// Loads `path` and prepares it with the k-d tree built by `flags.build`:
/// the window switches between the tree and brute force per frame (brute
/// force only changes a flag the kernel reads), so the tree is always built.
/// `--integrator` and `--seed` replace the file's; the window applies the
/// other flags itself. `seen` is told of every file read (the files to
/// watch for hot reload).
pub fn load(
    path: &Path,
    flags: &crate::render::RenderFlags,
    seen: &mut dyn FnMut(&Path),
) -> crate::Result<crate::gpu::PreparedScene> {
    let mut scene = crate::scene::load_scene_observed(path, seen)?;
    let render = &mut scene.render;
    render.integrator = flags.integrator.unwrap_or(render.integrator);
    render.seed = flags.seed.unwrap_or(render.seed);
    Ok(crate::gpu::PreparedScene::built_by(
        scene,
        crate::gpu::Accel::Kdtree,
        flags.build,
    ))
}

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

/// The files a scene loads, scene file first, then its meshes and their MTL
/// or buffer files, each with its stamp.
pub struct WatchList(Vec<(PathBuf, Stamp)>);

impl WatchList {
    /// Runs `load` (a scene load, given the observer to pass as
    /// [`crate::scene::load_scene_observed`]'s `on_read`) and lists the files
    /// it read, each stamped just before it was read: a change made after
    /// that is a change of stamp, even while the load goes on (it runs on
    /// the reload thread, and a big scene takes a while). A load that fails
    /// lists the files it got to, the one that broke included.
    pub fn record<T>(load: impl FnOnce(&mut dyn FnMut(&Path)) -> T) -> (WatchList, T) {
        let mut files: Vec<(PathBuf, Stamp)> = Vec::new();
        let result = load(&mut |path: &Path| {
            if !files.iter().any(|(p, _)| p == path) {
                files.push((path.to_path_buf(), stamp(path)));
            }
        });
        (WatchList(files), result)
    }
}

pub struct SceneWatcher {
    files: WatchList,
    next_poll: Instant,
    /// A change was seen and the files have not been stable since.
    unsettled: bool,
}

impl SceneWatcher {
    /// Starts watching `files` (from [`WatchList::record`] around the first load).
    pub fn new(files: WatchList) -> Self {
        SceneWatcher {
            files,
            next_poll: Instant::now() + POLL_INTERVAL,
            unsettled: false,
        }
    }

    /// The files watched now.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        self.files.0.iter().map(|(p, _)| p.as_path())
    }

    /// When the next poll is due.
    pub fn next_poll(&self) -> Instant {
        self.next_poll
    }

    /// Polls if one is due at `now`: true when a change has settled and the
    /// scene should be reloaded (then watch the files of the reload:
    /// [`SceneWatcher::watch`], so the watched files follow the scene's new
    /// mesh list).
    pub fn poll(&mut self, now: Instant) -> bool {
        if now < self.next_poll {
            return false;
        }
        self.next_poll = now + POLL_INTERVAL;
        let mut changed = false;
        for (path, old) in &mut self.files.0 {
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

    /// Takes the files watched now as they are (for a reload that produced
    /// no list: its thread failed), so only a later change triggers a reload.
    pub fn rescan(&mut self) {
        for (path, old) in &mut self.files.0 {
            *old = stamp(path);
        }
        self.unsettled = false;
    }

    /// Watches `files` from now on (recorded by [`WatchList::record`] while
    /// a reload ran: a file changed since it was read has a different
    /// stamp, so it triggers the next reload).
    pub fn watch(&mut self, files: WatchList) {
        self.files = files;
    }
}

/// A job for [`LatestJob`].
pub type Job<T> = Box<dyn FnOnce() -> T + Send>;

/// Runs the most recently requested job on a worker thread, one at a time.
/// A request made while a job runs supersedes it: when the running job ends
/// its result is dropped and the newest request starts. So a burst of saves
/// costs at most one load more than the last one, and only the newest
/// version of the scene is ever shown.
pub struct LatestJob<T> {
    running: Option<JoinHandle<T>>,
    queued: Option<Job<T>>,
    /// A failure to start a worker, reported by the next poll.
    failed: Option<String>,
}

impl<T> Default for LatestJob<T> {
    fn default() -> Self {
        LatestJob {
            running: None,
            queued: None,
            failed: None,
        }
    }
}

impl<T: Send + 'static> LatestJob<T> {
    /// Runs `job`, now or (if one is running) once the running one ends,
    /// replacing any job already waiting.
    pub fn request(&mut self, job: impl FnOnce() -> T + Send + 'static) {
        if self.running.is_some() {
            self.queued = Some(Box::new(job));
        } else {
            self.start(Box::new(job));
        }
    }

    fn start(&mut self, job: Job<T>) {
        match std::thread::Builder::new()
            .name("kdray-reload".into())
            .spawn(job)
        {
            Ok(handle) => self.running = Some(handle),
            Err(e) => self.failed = Some(format!("cannot start the reload thread: {e}")),
        }
    }

    /// Whether a job is running or waiting.
    pub fn busy(&self) -> bool {
        self.running.is_some() || self.queued.is_some()
    }

    /// The result of the newest request, once it has finished (never
    /// blocks). `Err` if its thread could not start or panicked.
    pub fn poll(&mut self) -> Option<Result<T, String>> {
        if let Some(message) = self.failed.take() {
            return Some(Err(message));
        }
        let handle = self.running.take()?;
        if !handle.is_finished() {
            self.running = Some(handle);
            return None;
        }
        let result = handle
            .join()
            .map_err(|_| "the reload thread panicked".to_string());
        match self.queued.take() {
            // Superseded: drop this result, run the newest request.
            Some(next) => {
                self.start(next);
                None
            }
            None => Some(result),
        }
    }
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

    /// A valid scene whose one mesh is `mesh` (relative to the scene), in
    /// the material given by the mesh's MTL when `material` is None.
    fn scene_text(mesh: &str, material: Option<&str>) -> String {
        let material = material.map_or(String::new(), |m| format!("material = \"{m}\"\n"));
        format!(
            "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n\
             [[lights]]\nposition = [0, 5, 5]\n\
             [materials.red]\ndiffuse = [1, 0, 0]\n\
             [[meshes]]\npath = \"{mesh}\"\n{material}"
        )
    }

    const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

    fn recorded(scene: &Path) -> (Vec<PathBuf>, bool) {
        let (files, result) =
            WatchList::record(|seen| crate::scene::load_scene_observed(scene, seen));
        (
            files.0.into_iter().map(|(p, _)| p).collect(),
            result.is_ok(),
        )
    }

    #[test]
    fn the_loader_lists_the_scene_its_meshes_and_their_mtl_files() {
        let dir = temp_dir("deps");
        std::fs::write(
            dir.join("models/a.obj"),
            format!("mtllib a.mtl b.mtl # two\nusemtl m\n{TRIANGLE}"),
        )
        .unwrap();
        std::fs::write(dir.join("models/a.mtl"), "newmtl m\nKd 1 1 1\n").unwrap();
        std::fs::write(dir.join("models/b.mtl"), "").unwrap();
        std::fs::write(dir.join("s.toml"), scene_text("models/a.obj", None)).unwrap();
        let expected = vec![
            dir.join("s.toml"),
            dir.join("models/a.obj"),
            dir.join("models/a.mtl"),
            dir.join("models/b.mtl"),
        ];
        assert_eq!(recorded(&dir.join("s.toml")), (expected, true));
        // With a material override the MTL files are not read, so not watched.
        std::fs::write(dir.join("o.toml"), scene_text("models/a.obj", Some("red"))).unwrap();
        assert_eq!(
            recorded(&dir.join("o.toml")),
            (vec![dir.join("o.toml"), dir.join("models/a.obj")], true)
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_failed_load_lists_the_files_up_to_the_one_that_broke() {
        let dir = temp_dir("broken");
        // A missing mesh: watched, so creating it triggers a reload.
        std::fs::write(dir.join("s.toml"), scene_text("missing.obj", Some("red"))).unwrap();
        assert_eq!(
            recorded(&dir.join("s.toml")),
            (vec![dir.join("s.toml"), dir.join("missing.obj")], false)
        );
        // A broken MTL file is watched; the mesh after it was never reached.
        std::fs::write(
            dir.join("a.obj"),
            format!("mtllib a.mtl\nusemtl m\n{TRIANGLE}"),
        )
        .unwrap();
        std::fs::write(dir.join("a.mtl"), "Kd 1 1 1\n").unwrap();
        let mut text = scene_text("a.obj", None);
        text.push_str("[[meshes]]\npath = \"later.obj\"\n");
        std::fs::write(dir.join("t.toml"), text).unwrap();
        assert_eq!(
            recorded(&dir.join("t.toml")),
            (
                vec![dir.join("t.toml"), dir.join("a.obj"), dir.join("a.mtl")],
                false
            )
        );
        // A scene file that does not parse, or does not exist: itself only.
        std::fs::write(dir.join("bad.toml"), "[[meshes]\n").unwrap();
        assert_eq!(
            recorded(&dir.join("bad.toml")),
            (vec![dir.join("bad.toml")], false)
        );
        assert_eq!(
            recorded(&dir.join("nothing.toml")),
            (vec![dir.join("nothing.toml")], false)
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_change_made_while_a_reload_runs_triggers_the_next_one() {
        let dir = temp_dir("during");
        let scene = dir.join("s.toml");
        let obj = dir.join("models/a.obj");
        std::fs::write(&obj, TRIANGLE).unwrap();
        std::fs::write(&scene, scene_text("models/a.obj", Some("red"))).unwrap();
        let load = |seen: &mut dyn FnMut(&Path)| crate::scene::load_scene_observed(&scene, seen);
        let mut w = SceneWatcher::new(WatchList::record(load).0);
        let mut t = Instant::now();
        // The reload thread reads the files, then (while it still works) the
        // OBJ is edited; then the reload finishes and its list is watched.
        let (files, loaded) = WatchList::record(load);
        assert!(loaded.is_ok());
        std::fs::write(&obj, format!("{TRIANGLE}v 1 1 1\n")).unwrap();
        w.watch(files);
        assert_eq!(w.files().count(), 2);
        t += POLL_INTERVAL;
        assert!(!w.poll(t), "reported before it settled");
        t += POLL_INTERVAL;
        assert!(w.poll(t), "the edit made during the reload was missed");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Polls until the job in flight has finished (or 10 s have passed).
    fn wait<T: Send + 'static>(jobs: &mut LatestJob<T>) -> Option<Result<T, String>> {
        let deadline = Instant::now() + Duration::from_secs(10);
        while Instant::now() < deadline {
            if let Some(result) = jobs.poll() {
                return Some(result);
            }
            if !jobs.busy() {
                return None;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        panic!("the job did not finish in 10 s");
    }

    #[test]
    fn a_job_runs_off_the_calling_thread_and_its_result_arrives_once() {
        let mut jobs = LatestJob::default();
        assert!(!jobs.busy());
        assert!(jobs.poll().is_none());
        let (release, gate) = std::sync::mpsc::channel::<()>();
        let caller = std::thread::current().id();
        jobs.request(move || {
            gate.recv().unwrap();
            std::thread::current().id()
        });
        // The job waits for the gate, and the caller is not blocked.
        std::thread::sleep(Duration::from_millis(20));
        assert!(jobs.busy());
        assert!(jobs.poll().is_none());
        release.send(()).unwrap();
        let worker = wait(&mut jobs).unwrap().unwrap();
        assert_ne!(worker, caller);
        assert!(!jobs.busy());
        assert!(jobs.poll().is_none(), "a result is delivered once");
    }

    #[test]
    fn a_request_during_a_job_supersedes_it_and_only_the_newest_result_arrives() {
        use std::sync::{Arc, Mutex};
        let mut jobs = LatestJob::default();
        let (release, gate) = std::sync::mpsc::channel::<()>();
        let gate = Arc::new(Mutex::new(gate));
        let ran = Arc::new(Mutex::new(Vec::new()));
        let job = |value: u32| {
            let (gate, ran) = (gate.clone(), ran.clone());
            move || {
                gate.lock().unwrap().recv().unwrap();
                ran.lock().unwrap().push(value);
                value
            }
        };
        jobs.request(job(1));
        // Two more versions while the first runs: only the last will run.
        jobs.request(job(2));
        jobs.request(job(3));
        release.send(()).unwrap();
        release.send(()).unwrap();
        assert_eq!(wait(&mut jobs), Some(Ok(3)));
        assert!(!jobs.busy());
        assert_eq!(*ran.lock().unwrap(), vec![1, 3], "job 2 was superseded");
    }

    #[test]
    fn a_panicking_job_is_an_error_not_a_panic() {
        let mut jobs: LatestJob<u32> = LatestJob::default();
        jobs.request(|| panic!("deliberate panic in a reload job (this test)"));
        let result = wait(&mut jobs).unwrap();
        assert_eq!(result, Err("the reload thread panicked".to_string()));
    }

    #[test]
    fn a_change_is_reported_once_it_has_settled() {
        let dir = temp_dir("poll");
        let scene = dir.join("s.toml");
        let obj = dir.join("models/a.obj");
        std::fs::write(&obj, TRIANGLE).unwrap();
        std::fs::write(&scene, scene_text("models/a.obj", Some("red"))).unwrap();
        let (files, loaded) =
            WatchList::record(|seen| crate::scene::load_scene_observed(&scene, seen));
        assert!(loaded.is_ok());
        let mut w = SceneWatcher::new(files);
        assert_eq!(w.files().count(), 2);
        let mut t = Instant::now();
        let tick = |w: &mut SceneWatcher, t: &mut Instant| {
            *t += POLL_INTERVAL;
            w.poll(*t)
        };
        assert!(!tick(&mut w, &mut t));
        // A different size is a change even within one timestamp tick.
        std::fs::write(&obj, format!("{TRIANGLE}v 1 1 1\n")).unwrap();
        assert!(!tick(&mut w, &mut t), "reported before it settled");
        assert!(tick(&mut w, &mut t), "not reported after it settled");
        assert!(!tick(&mut w, &mut t), "reported twice");
        // Polls are not due before the interval.
        std::fs::write(
            &scene,
            format!("# changed\n{}", scene_text("models/a.obj", Some("red"))),
        )
        .unwrap();
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
