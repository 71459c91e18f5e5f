// SPDX-License-Identifier: MIT OR Apache-2.0
//! For the C tests: building C and C++ programs against this crate's header and library
//! with strict warnings (and, on request, the sanitizers), and running them against a real
//! procimgd that the test starts under its own instance name and stops even when it fails.
#![allow(dead_code)]

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

static NEXT: AtomicU32 = AtomicU32::new(0);

/// The crate directory (clients/c).
pub fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The workspace root.
pub fn workspace_dir() -> PathBuf {
    crate_dir().join("../..")
}

/// The cargo profile directory this test runs from (target/debug).
pub fn profile_dir() -> PathBuf {
    let me = std::env::current_exe().expect("the test's own path");
    // target/debug/deps/<test> → target/debug
    me.parent()
        .and_then(Path::parent)
        .expect("target dir")
        .to_path_buf()
}

/// Where a test keeps what it builds.
pub fn scratch(tag: &str) -> PathBuf {
    let d = profile_dir().join("c-tests").join(tag);
    std::fs::create_dir_all(&d).expect("create the C test build directory");
    d
}

/// Which library a C program links.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Link {
    /// libprocimg.a
    Static,
    /// libprocimg.so
    Shared,
}

/// Sanitizers for a C build (`PROCIMG_C_SANITIZE=1` turns them on for every build).
pub fn sanitize_from_env() -> bool {
    std::env::var_os("PROCIMG_C_SANITIZE").is_some_and(|v| v != "0")
}

/// Runs `cargo build` for `args` once per test process, in this test's profile: a test must
/// never link or start a stale build of another package.
fn cargo_build_once(once: &'static OnceLock<()>, args: &[&str]) {
    once.get_or_init(|| {
        let mut cmd = Command::new(env!("CARGO"));
        cmd.current_dir(workspace_dir()).arg("build").args(args);
        if profile_dir().ends_with("release") {
            cmd.arg("--release");
        }
        let st = cmd.status().expect("run cargo build");
        assert!(st.success(), "cargo build {args:?} failed");
    });
}

/// The library file of this build (libprocimg.a or libprocimg.so), up to date.
pub fn library(link: Link) -> PathBuf {
    static BUILT: OnceLock<()> = OnceLock::new();
    cargo_build_once(&BUILT, &["-p", "procimg-c", "--lib"]);
    let name = match link {
        Link::Static => "libprocimg.a",
        Link::Shared => "libprocimg.so",
    };
    let path = profile_dir().join(name);
    assert!(path.exists(), "{} was not built", path.display());
    path
}

/// Compiles C (`.c`, as C11) or C++ (`.cpp`, as C++17) sources into `out` with
/// `-Wall -Wextra -Werror` against the crate's headers and library.
pub fn compile(sources: &[PathBuf], out: &Path, link: Link, sanitize: bool) {
    let cpp = sources
        .iter()
        .any(|s| s.extension().is_some_and(|e| e == "cpp"));
    let mut cmd = Command::new(if cpp { "g++" } else { "gcc" });
    cmd.arg(if cpp { "-std=c++17" } else { "-std=c11" })
        .args(["-Wall", "-Wextra", "-Werror", "-pedantic", "-g", "-O1"])
        .arg("-I")
        .arg(crate_dir().join("include"))
        .arg("-I")
        .arg(workspace_dir().join("shm-layout/include"));
    if sanitize {
        cmd.args([
            "-fsanitize=address,undefined",
            "-fno-sanitize-recover=undefined",
            "-fno-omit-frame-pointer",
        ]);
    }
    cmd.args(sources).arg("-o").arg(out);
    let lib = library(link);
    match link {
        Link::Static => {
            cmd.arg(&lib);
        }
        Link::Shared => {
            let dir = lib.parent().unwrap();
            cmd.arg("-L").arg(dir).arg("-lprocimg");
            cmd.arg(format!("-Wl,-rpath,{}", dir.display()));
        }
    }
    cmd.args(["-lpthread", "-ldl", "-lm"]);
    let o = cmd
        .output()
        .expect("run the C compiler (install gcc and g++)");
    assert!(
        o.status.success(),
        "compiling {:?} failed:\n{}",
        sources,
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Runs a built program with `args` and the instance in `PROCIMG_INSTANCE`; kills it after
/// `timeout`. Sanitizer reports fail the run (exit code). Without `LD_LIBRARY_PATH`: cargo
/// test's holds this build's libprocimg.so, and a program must find it the way a user's does
/// (its rpath).
pub fn run(program: &Path, args: &[&str], instance: &str, timeout: Duration) -> Output {
    let mut child = Command::new(program)
        .args(args)
        .env_remove("LD_LIBRARY_PATH")
        .env("PROCIMG_INSTANCE", instance)
        .env(
            "ASAN_OPTIONS",
            "detect_leaks=1:abort_on_error=0:exitcode=86",
        )
        .env(
            "UBSAN_OPTIONS",
            "print_stacktrace=1:halt_on_error=1:exitcode=87",
        )
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("start {}: {e}", program.display()));
    let until = Instant::now() + timeout;
    loop {
        if child.try_wait().expect("wait for the C program").is_some() {
            break;
        }
        if Instant::now() > until {
            let _ = child.kill();
            let o = child.wait_with_output().unwrap();
            panic!(
                "{} did not finish within {timeout:?}\nstdout:\n{}\nstderr:\n{}",
                program.display(),
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    child.wait_with_output().unwrap()
}

/// Asserts a program run succeeded, showing its output otherwise.
pub fn assert_success(o: &Output, what: &str) {
    assert!(
        o.status.success(),
        "{what} failed ({:?})\nstdout:\n{}\nstderr:\n{}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A unique instance name for this test process.
pub fn unique_instance(tag: &str) -> String {
    format!(
        "c{}-{}-{}",
        std::process::id(),
        tag,
        NEXT.fetch_add(1, Ordering::Relaxed)
    )
}

/// The procimgd binary of this build, up to date.
pub fn procimgd() -> PathBuf {
    static BUILT: OnceLock<()> = OnceLock::new();
    cargo_build_once(&BUILT, &["-p", "procimg-runtime", "--bin", "procimgd"]);
    profile_dir().join("procimgd")
}

/// A running procimgd, stopped on drop.
pub struct Server {
    pub instance: String,
    child: Option<Child>,
    config: Option<PathBuf>,
}

impl Server {
    /// `procimgd --demo` under a fresh instance name, cycling, its devices in data exchange.
    pub fn demo(tag: &str) -> Server {
        Server::start(&unique_instance(tag), None)
    }

    /// procimgd with a configuration text (TOML) under a fresh instance name.
    pub fn with_config(tag: &str, toml: &str) -> Server {
        let instance = unique_instance(tag);
        let path = std::env::temp_dir().join(format!("procimg-{instance}.toml"));
        let mut f = std::fs::File::create(&path).expect("write the test configuration");
        f.write_all(toml.as_bytes()).unwrap();
        Server::start(&instance, Some(path))
    }

    fn start(instance: &str, config: Option<PathBuf>) -> Server {
        let mut cmd = Command::new(procimgd());
        match &config {
            Some(path) => cmd.arg("--config").arg(path),
            None => cmd.arg("--demo").arg("--quiet"),
        };
        cmd.arg("--instance")
            .arg(instance)
            .env("RUST_LOG", "warn")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::inherit());
        let child = cmd.spawn().expect("start procimgd");
        let server = Server {
            instance: instance.to_string(),
            child: Some(child),
            config,
        };
        server.wait_ready(Duration::from_secs(15));
        server
    }

    /// The server's mode now.
    pub fn mode(&self) -> procimg_client::Mode {
        procimg_client::ControlHandle::open(&self.instance, "c-test-mode")
            .expect("open the control service")
            .status()
            .expect("the server's status")
            .mode
    }

    /// Asks for `mode` and waits until the server is there.
    pub fn set_mode(&self, mode: procimg_client::Mode) {
        procimg_client::ControlHandle::open(&self.instance, "c-test-mode")
            .expect("open the control service")
            .set_mode(mode)
            .expect("set the mode");
        let until = Instant::now() + Duration::from_secs(15);
        while self.mode() != mode {
            assert!(Instant::now() < until, "{mode:?} was not reached");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Waits until the server cycles and every device is in data exchange.
    pub fn wait_ready(&self, timeout: Duration) {
        let until = Instant::now() + timeout;
        loop {
            if let Ok(c) = procimg_client::ControlHandle::open(&self.instance, "c-test-wait")
                && let Ok(s) = c.status()
                && s.cycle_count > 5
                && s.devices.iter().all(|d| d.state == "running")
            {
                return;
            }
            assert!(
                Instant::now() < until,
                "procimgd for {} did not come up",
                self.instance
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            // SAFETY: kill(2) on our own child's pid.
            #[allow(unsafe_code)]
            unsafe {
                libc::kill(c.id() as i32, libc::SIGTERM)
            };
            let until = Instant::now() + Duration::from_secs(3);
            while Instant::now() < until {
                if let Ok(Some(_)) = c.try_wait() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            let _ = c.kill();
            let _ = c.wait();
        }
        if let Some(p) = &self.config {
            let _ = std::fs::remove_file(p);
        }
    }
}
