// SPDX-License-Identifier: MIT OR Apache-2.0
//! The library as a user gets it: built and installed with CMake into a prefix, then programs
//! built against the INSTALLED headers and library — with `pkg-config --cflags --libs procimg`
//! and with CMake's `find_package(procimg)` — run against a procimgd the test starts: the
//! manual's PnioEasy flow in C (shared library) and C++17 (static library), the isochronous
//! IO-Base loop and the native STARTOP/OPDONE loop; and a PN Driver program that starts its
//! own stack.
//!
//! Needs cmake, pkg-config, gcc and g++ (`.ci/run` installs them).

use procimg_testkit::c::{assert_success, crate_dir, run, run_with_env, scratch};
use procimg_testkit::{Procimgd, procimgd_bin, profile_dir};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

fn sh(cmd: &mut Command, what: &str) -> String {
    let o = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {cmd:?}: {e} (is it installed?)"));
    assert!(
        o.status.success(),
        "{what} failed:\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Configures, builds and installs clients/c into a fresh prefix; returns the prefix.
fn install() -> PathBuf {
    let dir = scratch("installed");
    let prefix = dir.join("prefix");
    let build = dir.join("build");
    let _ = std::fs::remove_dir_all(&prefix);
    let target_root = profile_dir().parent().unwrap().to_path_buf();
    let profile = if profile_dir().ends_with("release") {
        "release"
    } else {
        "debug"
    };
    sh(
        Command::new("cmake")
            .arg("-S")
            .arg(crate_dir())
            .arg("-B")
            .arg(&build)
            .arg(format!("-DCMAKE_INSTALL_PREFIX={}", prefix.display()))
            .arg("-DCMAKE_INSTALL_LIBDIR=lib")
            .arg(format!("-DPROCIMG_CARGO_PROFILE={profile}"))
            .arg(format!(
                "-DPROCIMG_CARGO_TARGET_DIR={}",
                target_root.display()
            )),
        "cmake configure",
    );
    sh(
        Command::new("cmake").arg("--build").arg(&build),
        "cmake --build",
    );
    sh(
        Command::new("cmake").arg("--install").arg(&build),
        "cmake --install",
    );
    prefix
}

fn pkg_config(prefix: &Path, args: &[&str]) -> Vec<String> {
    let out = sh(
        Command::new("pkg-config")
            .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig"))
            .args(args)
            .arg("procimg"),
        "pkg-config",
    );
    out.split_whitespace().map(str::to_string).collect()
}

/// `cc $(pkg-config --cflags procimg) example.c $(pkg-config --libs procimg)`.
fn build_with_pkg_config(prefix: &Path, example: &str, out: &Path, static_link: bool) {
    let cpp = example.ends_with(".cpp");
    let mut cmd = Command::new(if cpp { "g++" } else { "gcc" });
    cmd.arg(if cpp { "-std=c++17" } else { "-std=c11" })
        .args(["-Wall", "-Wextra", "-Werror", "-pedantic"])
        .args(pkg_config(prefix, &["--cflags"]))
        .arg(crate_dir().join("examples").join(example))
        .arg("-o")
        .arg(out);
    if static_link {
        // The static archive itself, then what it needs (Libs.private).
        cmd.arg(prefix.join("lib/libprocimg.a"));
        let libs = pkg_config(prefix, &["--static", "--libs"]);
        cmd.args(
            libs.iter()
                .filter(|l| !l.starts_with("-L") && *l != "-lprocimg"),
        );
    } else {
        // Nothing more: the .pc file's rpath makes the program find libprocimg.so.
        cmd.args(pkg_config(prefix, &["--libs"]));
    }
    sh(&mut cmd, &format!("building {example} with pkg-config"));
}

#[test]
fn installed_library_builds_and_runs_the_examples() {
    let prefix = install();
    for header in [
        "procimg.h",
        "procimg_shm.h",
        "pniobase.h",
        "pniousrx.h",
        "pniousrd.h",
        "pnioerrx.h",
        "servusrx.h",
    ] {
        assert!(
            prefix.join("include/procimg").join(header).exists(),
            "{header} is not installed"
        );
    }
    let cflags = pkg_config(&prefix, &["--cflags", "--libs"]);
    assert!(
        cflags.iter().any(|f| f.ends_with("include/procimg"))
            && cflags.contains(&"-lprocimg".into()),
        "pkg-config --cflags --libs procimg gave {cflags:?}"
    );
    // Not a system directory: the programs find the library through an rpath.
    let rpath = format!("-Wl,-rpath,{}", prefix.join("lib").display());
    assert!(
        cflags.contains(&rpath),
        "pkg-config --libs procimg has no {rpath}: {cflags:?}"
    );

    let bin = scratch("installed").join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let easy_c = bin.join("pnio_easy_pkgconfig");
    let native_static = bin.join("native_cycle_pkgconfig_static");
    build_with_pkg_config(&prefix, "pnio_easy.c", &easy_c, false);
    build_with_pkg_config(&prefix, "native_cycle.c", &native_static, true);

    // find_package(procimg): the examples' own CMake project.
    let ex_build = scratch("installed").join("examples-build");
    let _ = std::fs::remove_dir_all(&ex_build);
    sh(
        Command::new("cmake")
            .arg("-S")
            .arg(crate_dir().join("examples"))
            .arg("-B")
            .arg(&ex_build)
            .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())),
        "cmake configure of the examples (find_package(procimg))",
    );
    sh(
        Command::new("cmake").arg("--build").arg(&ex_build),
        "cmake --build of the examples",
    );

    let server = Procimgd::demo("installed");
    let t = Duration::from_secs(60);
    let runs: [(PathBuf, &[&str], &str); 5] = [
        (easy_c, &["50"], "PnioEasy in C (pkg-config, shared)"),
        (
            ex_build.join("pnio_easy_cpp"),
            &["50"],
            "PnioEasy in C++17 (find_package, static)",
        ),
        (
            ex_build.join("pnio_isochronous"),
            &["400"],
            "isochronous IO-Base loop",
        ),
        (
            native_static,
            &["", "200"],
            "native loop (pkg-config, static)",
        ),
        (
            ex_build.join("native_cycle"),
            &["", "200"],
            "native loop (find_package, static)",
        ),
    ];
    for (program, args, what) in runs {
        let args: Vec<&str> = args
            .iter()
            .map(|a| {
                if a.is_empty() {
                    server.instance.as_str()
                } else {
                    a
                }
            })
            .collect();
        // The IO-Base programs end the manual's flow in OFFLINE and then give the server
        // back its mode: each program finds it in OPERATE (the native loop fails without an
        // echo). Between them, the devices reconnect.
        server.wait_ready(Duration::from_secs(15));
        // No LD_LIBRARY_PATH (`run` removes cargo's): the shared builds find the installed
        // library by their rpath alone.
        let o = run(&program, &args, &server.instance, t);
        assert_success(&o, what);
        println!("{what}:\n{}", String::from_utf8_lossy(&o.stdout));
        assert_eq!(
            server.mode(),
            procimg_client::Mode::Operate,
            "{what} left the server so"
        );
    }

    // A PN Driver program starts its own stack from a configuration file: no server before.
    let instance = procimg_testkit::unique_instance("installed-pnd");
    let plant = scratch("installed").join("plant.toml");
    let demo = Command::new(procimgd_bin())
        .arg("--print-demo-config")
        .output()
        .expect("procimgd --print-demo-config");
    std::fs::write(&plant, demo.stdout).unwrap();
    let procimgd = procimgd_bin();
    let o = run_with_env(
        &ex_build.join("pnd_easy"),
        &[plant.to_str().unwrap(), "", "50"],
        &instance,
        &[("PROCIMGD", procimgd.as_os_str())],
        t,
    );
    assert_success(&o, "the PN Driver program (find_package, shared)");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("50 exchanges") && stdout.contains("stack ended"),
        "pnd_easy said:\n{stdout}"
    );
}
