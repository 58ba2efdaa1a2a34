//! What the window tests share: an X server of their own (Xvfb, on a free
//! display, stopped on drop), the `kdray` command run on it, and a window
//! process whose stderr is read line by line and which is killed if a test
//! fails before it closes.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use kdray::output::read_png_rgb;

/// Window size and samples of the tests: small, so each run takes a moment
/// on lavapipe.
pub(crate) const W: u32 = 96;
pub(crate) const H: u32 = 64;
pub(crate) const SAMPLES: &str = "4";
/// Longest wait for anything the window should do.
pub(crate) const TIMEOUT: Duration = Duration::from_secs(60);

/// An X server for one test, stopped on drop.
pub(crate) struct Xvfb {
    child: Child,
    pub(crate) display: String,
}

/// How long one Xvfb may take to make its socket before it is stopped
/// and another display tried. It takes well under a second alone; 20 s
/// was once too short with the suite's other tests on both cores, and
/// once, on a machine whose Xvfb had never run, one of two servers started
/// together made no socket in 90 s while the other was up at once: a hung
/// server is replaced, not waited on.
const XVFB_START: Duration = Duration::from_secs(30);
/// Servers that may hang before the test gives up.
const XVFB_HUNG_TRIES: usize = 3;

impl Xvfb {
    pub(crate) fn start() -> Xvfb {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let mut hung = Vec::new();
        for _ in 0..50 {
            let n = 100 + (std::process::id() * 7 + NEXT.fetch_add(1, Ordering::SeqCst)) % 30000;
            let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
            if socket.exists() || Path::new(&format!("/tmp/.X{n}-lock")).exists() {
                continue;
            }
            // Its own words, for the failure message if it hangs.
            let log = std::env::temp_dir().join(format!("kdray-xvfb-{n}.log"));
            let stderr = std::fs::File::create(&log)
                .map(Stdio::from)
                .unwrap_or_else(|_| Stdio::null());
            let spawned = Command::new("Xvfb")
                .args([
                    &format!(":{n}"),
                    "-screen",
                    "0",
                    "1024x768x24",
                    "-nolisten",
                    "tcp",
                ])
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(stderr)
                .spawn();
            let child = match spawned {
                Ok(child) => child,
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => panic!(
                    "the window tests need Xvfb, which is not installed: \
                     apt-get install xvfb xauth libxkbcommon-x11-0 (CI's .ci/run installs them)"
                ),
                Err(e) => panic!("cannot start Xvfb: {e}"),
            };
            let mut server = Xvfb {
                child,
                display: format!(":{n}"),
            };
            let deadline = Instant::now() + XVFB_START;
            let started = loop {
                if socket.exists() {
                    break true;
                }
                // Exited: most likely another server took this display; try the next.
                if server.child.try_wait().unwrap().is_some() {
                    break false;
                }
                if Instant::now() >= deadline {
                    let said = std::fs::read_to_string(&log).unwrap_or_default();
                    hung.push(format!("{}: {}", server.display, said.trim()));
                    break false;
                }
                std::thread::sleep(Duration::from_millis(20));
            };
            let _ = std::fs::remove_file(&log);
            if started {
                return server;
            }
            drop(server); // stopped (SIGTERM, then SIGKILL) before the next try
            assert!(
                hung.len() < XVFB_HUNG_TRIES,
                "{} Xvfb servers made no socket in {:?} each: {}",
                hung.len(),
                XVFB_START,
                hung.join("; ")
            );
        }
        panic!("found no free X display for Xvfb");
    }

    /// [`kdray`] with this server as its display (and no Wayland one).
    pub(crate) fn kdray(&self, dir: &Path) -> Command {
        let mut command = kdray(dir);
        command
            .env("DISPLAY", &self.display)
            .env_remove("WAYLAND_DISPLAY");
        command
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // SIGTERM lets Xvfb remove its socket and lock file; SIGKILL if it
        // does not stop.
        // SAFETY: kill(2) on our own child's pid.
        unsafe { libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM) };
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A fresh folder for one test's files (and its XDG_RUNTIME_DIR).
pub(crate) fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kdray-window-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("xdg")).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(dir.join("xdg"), std::fs::Permissions::from_mode(0o700)).unwrap();
    dir
}

pub(crate) fn kdray(dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_kdray"));
    command
        .env("XDG_RUNTIME_DIR", dir.join("xdg"))
        .env_remove("KDRAY_AUTO_ORBIT")
        .stdin(Stdio::null());
    command
}

/// The test image at `path`, which must be the tests' size.
pub(crate) fn read(path: &Path) -> Vec<u8> {
    let (w, h, rgb) = read_png_rgb(path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((w, h), (W, H), "{}", path.display());
    rgb
}

/// Lines the window prints on stderr, as they come.
fn stderr_lines(child: &mut Child) -> Receiver<String> {
    let (send, receive) = std::sync::mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            if send.send(line).is_err() {
                break;
            }
        }
    });
    receive
}

/// Waits for a line containing `needle`; returns every line read so far.
fn wait_for(lines: &Receiver<String>, seen: &mut Vec<String>, needle: &str) {
    let deadline = Instant::now() + TIMEOUT;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        match lines.recv_timeout(left) {
            Ok(line) => {
                let found = line.contains(needle);
                seen.push(line);
                if found {
                    return;
                }
            }
            Err(RecvTimeoutError::Timeout) => {
                panic!(
                    "no line with {needle:?} on stderr; got:\n{}",
                    seen.join("\n")
                )
            }
            Err(RecvTimeoutError::Disconnected) => panic!(
                "the window exited before printing {needle:?}; stderr:\n{}",
                seen.join("\n")
            ),
        }
    }
}

/// A window process whose stderr is read line by line as it comes; killed
/// if the test fails before [`RunningWindow::close`].
pub(crate) struct RunningWindow {
    child: Child,
    lines: Receiver<String>,
    /// Every stderr line read so far.
    pub(crate) seen: Vec<String>,
}

impl RunningWindow {
    /// Starts `command`, its stdout dropped and its stderr read.
    pub(crate) fn spawn(mut command: Command) -> RunningWindow {
        let mut child = command
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let lines = stderr_lines(&mut child);
        RunningWindow {
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// Waits for a stderr line with `needle` (within [`TIMEOUT`]) and
    /// returns it.
    pub(crate) fn line_with(&mut self, needle: &str) -> String {
        wait_for(&self.lines, &mut self.seen, needle);
        self.seen.last().cloned().unwrap_or_default()
    }

    /// Whether it is still running.
    pub(crate) fn running(&mut self) -> bool {
        self.child.try_wait().unwrap().is_none()
    }

    /// Closes it with SIGTERM, which closes the window as Esc does (saving
    /// `--screenshot`), and waits for it within [`TIMEOUT`]: its exit
    /// status, and all it printed on stderr.
    pub(crate) fn close(mut self) -> (ExitStatus, String) {
        // SAFETY: kill(2) on our own child's pid.
        assert_eq!(
            unsafe { libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM) },
            0
        );
        let deadline = Instant::now() + TIMEOUT;
        let status = loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                break status;
            }
            assert!(
                Instant::now() < deadline,
                "the window did not close on SIGTERM"
            );
            std::thread::sleep(Duration::from_millis(20));
        };
        self.seen.extend(self.lines.try_iter());
        (status, self.seen.join("\n"))
    }
}

impl Drop for RunningWindow {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
