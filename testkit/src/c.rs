// SPDX-License-Identifier: MIT OR Apache-2.0
//! C and C++ programs built against `libprocimg`'s headers and library with strict warnings
//! (and, on request, the sanitizers), and run against a real procimgd.

use crate::build::{cargo_build_once, profile_dir, workspace_dir};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The C library's crate directory (clients/c).
pub fn crate_dir() -> PathBuf {
    workspace_dir().join("clients/c")
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

/// The library file of this build (libprocimg.a or libprocimg.so), up to date.
pub fn library(link: Link) -> PathBuf {
    cargo_build_once(&["-p", "procimg-c", "--lib"]);
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
    // The linker takes the process's umask, which iceoryx2 narrows to owner-only for a
    // moment whenever another test thread creates an event listener (its socket): the
    // program would come out without execute permission.
    use std::os::unix::fs::PermissionsExt as _;
    std::fs::set_permissions(out, std::fs::Permissions::from_mode(0o755))
        .expect("make the compiled program executable");
}

/// Runs a built program with `args` and the instance in `PROCIMG_INSTANCE`; kills it after
/// `timeout`. Sanitizer reports fail the run (exit code). Without `LD_LIBRARY_PATH`: cargo
/// test's holds this build's libprocimg.so, and a program must find it the way a user's does
/// (its rpath).
pub fn run(program: &Path, args: &[&str], instance: &str, timeout: Duration) -> Output {
    run_with_env(program, args, instance, &[], timeout)
}

/// [`run`] with more environment variables (`PROCIMGD` for a program that starts its own).
pub fn run_with_env(
    program: &Path,
    args: &[&str],
    instance: &str,
    env: &[(&str, &std::ffi::OsStr)],
    timeout: Duration,
) -> Output {
    let mut child = Command::new(program)
        .args(args)
        .envs(env.iter().copied())
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
