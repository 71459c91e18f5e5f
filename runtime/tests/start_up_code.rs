// SPDX-License-Identifier: MIT OR Apache-2.0
//! Once start-up is over, procimgd lets go of the code it ran, and locks again only what runs
//! again. Checked in a process of its own (this test binary run again), which locks its memory
//! as procimgd does; locking needs root (or a large `RLIMIT_MEMLOCK`).

use procimg_runtime::sys::populate::mapping_of;
use procimg_runtime::sys::rt::lock_memory;
use procimg_runtime::sys::start_up_code::release_start_up_code;
use procimg_testkit::memory::{locked_bytes, resident_bytes, vm_flags};
use std::process::Command;

const CHILD_ENV: &str = "PROCIMG_TEST_START_UP_CODE_CHILD";

/// Run as a child process only: locks its memory as used, as procimgd does, lets go of its
/// start-up code and prints what its code mapping held before and after.
#[test]
fn child_releases_its_start_up_code() {
    if std::env::var_os(CHILD_ENV).is_none() {
        return;
    }
    if let Err(e) = lock_memory(false) {
        println!("RESULT cannot lock: {e}");
        return;
    }
    let code = mapping_of(child_releases_its_start_up_code as *const () as usize)
        .expect("this code's mapping");
    let before = (resident_bytes(code.start), locked_bytes(code.start));
    let released = release_start_up_code();
    if let Some(w) = released.warnings.first() {
        println!("RESULT warning: {w}");
        return;
    }
    let released = released.bytes;
    // Read at once: only the code that reads smaps has run since.
    let after = (resident_bytes(code.start), locked_bytes(code.start));
    let flags = vm_flags(code.start).join(" ");
    println!(
        "RESULT released {released} resident {} {} locked {} {} flags {flags}",
        before.0, after.0, before.1, after.1
    );
}

#[test]
#[ignore = "needs root (locks the memory of a process): run as root with --ignored"]
fn start_up_code_is_let_go_and_what_runs_again_is_locked() {
    let out = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "child_releases_its_start_up_code",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD_ENV, "1")
        .output()
        .expect("start this test binary again");
    let stdout = String::from_utf8_lossy(&out.stdout);
    // The harness prints the test's name on the line the child's output starts.
    let line = stdout
        .lines()
        .find_map(|l| l.find("RESULT").map(|at| &l[at..]))
        .unwrap_or("no result");
    let words: Vec<&str> = line.split_whitespace().collect();
    assert_eq!(words.get(1), Some(&"released"), "{line}\n{stdout}");
    let n = |i: usize| -> usize { words[i].parse().unwrap_or_else(|_| panic!("{line}")) };
    let (released, rss_before, rss_after, locked_before, locked_after) =
        (n(2), n(4), n(5), n(7), n(8));
    assert!(released > 0, "the program's code was let go: {line}");
    // `Locked` is the process's share of its locked pages: this binary's code is mapped by
    // the parent test process too, so it is half of what is resident.
    assert!(
        locked_before > 0,
        "before, the code that had run was locked: {line}"
    );
    assert!(
        rss_after < rss_before,
        "right after, less of the code is mapped than start-up had mapped: {line}"
    );
    assert!(
        locked_after > 0 && locked_after < locked_before,
        "what ran again since is locked again, and less is locked: {line}"
    );
    let flags = &words[10..];
    assert!(
        flags.contains(&"lo") && flags.contains(&"ex"),
        "the code mapping is still locked (as used): {line}"
    );
}
