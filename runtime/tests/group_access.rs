// SPDX-License-Identifier: MIT OR Apache-2.0
//! `[access] group` with three users: procimgd runs as a user of its own (not root) with the
//! access group, with the capabilities and limits of `deploy/procimgd.service` (as systemd
//! would give them: `prlimit` and `setpriv`), and cycles in real time, its PROFINET and control
//! threads at the status priority; a member of the group attaches a synchronous client that runs cycles, and
//! `procimg status` works for it; a user outside the group is told "access denied" and can
//! open none of the shared-memory files. The users are plain ids (no accounts needed), the
//! processes are started through `setpriv` (util-linux), and iceoryx2's directory is moved
//! into the test's own directory with `PROCIMG_SHM_DIR`, so nothing of other tests' shared
//! memory is touched.

use procimg_client::{AttachError, AttachOptions, Client};
use procimg_testkit::build::{procimgd_bin, workspace_bin};
use std::os::unix::fs::{MetadataExt as _, PermissionsExt as _};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output};
use std::time::{Duration, Instant};

const CHILD_ENV: &str = "PROCIMG_TEST_GROUP_CHILD";
/// The access group, procimgd's user, a member and an outsider.
const GROUP: u32 = 47300;
const SERVER_UID: u32 = 47301;
const MEMBER_UID: u32 = 47302;
const OUTSIDER_UID: u32 = 47303;

/// Run as a child process only, as another user: what `PROCIMG_TEST_GROUP_CHILD` says.
#[test]
fn child_as_another_user() {
    let Ok(job) = std::env::var(CHILD_ENV) else {
        return;
    };
    let (what, instance) = job.split_once(':').expect("JOB:INSTANCE");
    match what {
        "cycles" => match Client::attach(instance, AttachOptions::synchronous("member")) {
            Ok(mut c) => {
                let mut done = 0;
                while done < 100 {
                    match c.wait_startop(Duration::from_secs(10)) {
                        Ok(cycle) => {
                            let _ = cycle.set_opdone();
                            done += 1;
                        }
                        Err(e) => {
                            println!("RESULT no-cycles: {e}");
                            return;
                        }
                    }
                }
                println!("RESULT cycles {done}");
            }
            Err(e) => println!("RESULT attach-failed: {e}"),
        },
        "intrude" => {
            match Client::attach(instance, AttachOptions::asynchronous("outsider")) {
                Ok(_) => println!("RESULT attached"),
                Err(e @ AttachError::AccessDenied { .. }) => println!("RESULT access-denied: {e}"),
                Err(e) => println!("RESULT other: {e}"),
            }
            // Nothing of the image either: no shared-memory file of procimg opens. iceoryx2's
            // global management segment (a node counter, no process data) is open to every
            // user by iceoryx2's design.
            let opened = std::fs::read_dir("/dev/shm")
                .map(|d| {
                    d.flatten()
                        .filter(|e| {
                            let name = e.file_name().to_string_lossy().into_owned();
                            name.starts_with("procimg_") && !name.ends_with(".global_mgmt")
                        })
                        .filter(|e| std::fs::File::open(e.path()).is_ok())
                        .count()
                })
                .unwrap_or(0);
            println!("RESULT opened {opened}");
        }
        other => println!("RESULT unknown job {other}"),
    }
}

/// `setpriv` arguments for a user with a group list.
fn as_user(uid: u32, gid: u32, groups: &[u32]) -> Vec<String> {
    let mut args = vec![format!("--reuid={uid}"), format!("--regid={gid}")];
    if groups.is_empty() {
        args.push("--clear-groups".into());
    } else {
        let list: Vec<String> = groups.iter().map(u32::to_string).collect();
        args.push(format!("--groups={}", list.join(",")));
    }
    args
}

/// The scheduling policy and real-time priority of the thread called `name` in process `pid`
/// (fields 41 and 40 of `/proc/PID/task/TID/stat`).
fn scheduling(pid: u32, name: &str) -> (u32, u32) {
    let tasks = std::fs::read_dir(format!("/proc/{pid}/task")).expect("procimgd's threads");
    for task in tasks.flatten() {
        let comm = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
        if comm.trim() != name {
            continue;
        }
        let stat = std::fs::read_to_string(task.path().join("stat")).unwrap_or_default();
        // After the command in parentheses: field 3 onwards.
        let fields: Vec<&str> = stat
            .rsplit_once(')')
            .map(|(_, rest)| rest.split_whitespace().collect())
            .unwrap_or_default();
        let field = |n: usize| fields.get(n - 3).and_then(|f| f.parse().ok()).unwrap_or(0);
        return (field(41), field(40));
    }
    panic!("procimgd has no thread {name}");
}

/// What `deploy/procimgd.service` gives procimgd, as `prlimit` and `setpriv` arguments.
struct Unit {
    limits: Vec<String>,
    capabilities: Vec<String>,
}

impl Unit {
    fn read() -> Unit {
        let path = procimg_testkit::workspace_dir().join("deploy/procimgd.service");
        let text = std::fs::read_to_string(&path).expect("deploy/procimgd.service");
        let value = |key: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(&format!("{key}=")))
                .unwrap_or_else(|| panic!("{key}= in {}", path.display()))
                .trim()
                .to_string()
        };
        let memlock = match value("LimitMEMLOCK").as_str() {
            "infinity" => "unlimited".to_string(),
            v => v.to_string(),
        };
        let rtprio = value("LimitRTPRIO");
        let caps: Vec<String> = value("AmbientCapabilities")
            .split_whitespace()
            .map(|c| format!("+{}", c.trim_start_matches("CAP_").to_ascii_lowercase()))
            .collect();
        assert_eq!(value("User"), "procimg");
        let mut limits = vec![
            format!("--memlock={memlock}:{memlock}"),
            format!("--rtprio={rtprio}:{rtprio}"),
        ];
        // Raising a hard limit needs CAP_SYS_RESOURCE, which root in a container may lack; the
        // unit's capabilities cover both anyway (CAP_IPC_LOCK, CAP_SYS_NICE).
        let raise = Command::new("prlimit").args(&limits).arg("true").status();
        if !raise.is_ok_and(|s| s.success()) {
            eprintln!("the unit's limits are not applied: prlimit may not raise them here");
            limits.clear();
        }
        Unit {
            limits,
            capabilities: vec![
                format!("--inh-caps={}", caps.join(",")),
                format!("--ambient-caps={}", caps.join(",")),
            ],
        }
    }
}

/// procimgd as its own user; stopped (SIGTERM, then SIGKILL) when dropped.
struct Server {
    child: Child,
    log: PathBuf,
}

impl Drop for Server {
    fn drop(&mut self) {
        procimg_testkit::signal::stop(&mut self.child, libc::SIGTERM, Duration::from_secs(10));
    }
}

/// Runs `program args` as the given user, with the test's iceoryx2 directory.
fn run_as(uid: u32, gid: u32, groups: &[u32], shm: &Path, program: &Path, args: &[&str]) -> Output {
    Command::new("setpriv")
        .args(as_user(uid, gid, groups))
        .arg(program)
        .args(args)
        .env("PROCIMG_SHM_DIR", shm)
        .env(CHILD_ENV, "")
        .output()
        .expect("setpriv (util-linux)")
}

fn result_line(out: &Output) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout);
    stdout
        .lines()
        .find(|l| l.starts_with("RESULT"))
        .map(str::to_string)
        .unwrap_or_else(|| {
            format!(
                "no result: {stdout} {}",
                String::from_utf8_lossy(&out.stderr)
            )
        })
}

#[test]
#[ignore = "needs root (starts processes as other users): run as root with --ignored"]
fn members_of_the_access_group_attach_and_nobody_else_does() {
    assert!(
        procimg_testkit::signal::is_root(),
        "this test starts processes as other users, which needs root: run it as root"
    );
    let me = std::env::current_exe().expect("the test binary");
    let procimgd = procimgd_bin();
    let procimg = workspace_bin("procimg", "PROCIMG_BIN", "procimg-tools");
    // Like /tmp: everybody may create, only owners remove.
    let dir = procimg_testkit::files::temp_dir("group-access");
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o1777)).unwrap();
    let shm = dir.path().join("iceoryx2");
    let instance = procimg_testkit::unique_instance("group");
    let demo = Command::new(&procimgd)
        .arg("--print-demo-config")
        .output()
        .expect("procimgd --print-demo-config");
    let config = String::from_utf8(demo.stdout)
        .unwrap()
        .replacen(
            "instance = \"procimg\"",
            &format!("instance = \"{instance}\""),
            1,
        )
        .replacen("# group = \"procimg\"", &format!("group = \"{GROUP}\""), 1)
        .replacen("mode = \"0600\"", "mode = \"0660\"", 1);
    assert!(config.contains(&format!("group = \"{GROUP}\"")), "{config}");
    let config_path = dir.path().join("procimgd.toml");
    std::fs::write(&config_path, config).unwrap();
    std::fs::set_permissions(&config_path, std::fs::Permissions::from_mode(0o644)).unwrap();
    let log = dir.path().join("procimgd.log");
    let log_file = std::fs::File::create(&log).unwrap();
    let unit = Unit::read();
    let server = Server {
        child: Command::new("prlimit")
            .args(&unit.limits)
            .arg("setpriv")
            .args(as_user(SERVER_UID, GROUP, &[]))
            .args(&unit.capabilities)
            .arg(&procimgd)
            .arg("-c")
            .arg(&config_path)
            .arg("--quiet")
            .env("PROCIMG_SHM_DIR", &shm)
            .stdout(log_file.try_clone().unwrap())
            .stderr(log_file)
            .spawn()
            .expect("setpriv (util-linux)"),
        log,
    };

    // A member of the group: `procimg status` answers (once procimgd is up) ...
    let until = Instant::now() + Duration::from_secs(30);
    let status = loop {
        let out = run_as(
            MEMBER_UID,
            MEMBER_UID,
            &[GROUP],
            &shm,
            &procimg,
            &["status", "--instance", &instance, "--json"],
        );
        if out.status.success() || Instant::now() >= until {
            break out;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let text = String::from_utf8_lossy(&status.stdout);
    assert!(
        status.status.success() && text.contains("\"mode\""),
        "procimg status as a member of the group: {text} {}\nprocimgd's log:\n{}",
        String::from_utf8_lossy(&status.stderr),
        std::fs::read_to_string(&server.log).unwrap_or_default()
    );
    assert!(
        text.contains("\"realtime\":true"),
        "the unit's capabilities and limits give the cycle thread SCHED_FIFO: {text}"
    );
    // The threads that turn the cycle's reports into status and events run at the status
    // priority (`[cycle_thread] status_priority`, default 40), as SCHED_FIFO.
    let pid = server.child.id();
    for (thread, what) in [
        ("procimg-pnio", "the PROFINET thread"),
        ("procimgd", "the control thread"),
    ] {
        let (policy, priority) = scheduling(pid, thread);
        assert_eq!(
            (policy, priority),
            (libc::SCHED_FIFO as u32, 40),
            "{what} ({thread}) runs SCHED_FIFO 40"
        );
    }
    let log_text = std::fs::read_to_string(&server.log).unwrap_or_default();
    assert!(
        !log_text.contains("cannot lock memory"),
        "the unit's capabilities let procimgd lock its memory: {log_text}"
    );
    // ... and a synchronous client runs 100 cycles.
    let member = Command::new("setpriv")
        .args(as_user(MEMBER_UID, MEMBER_UID, &[GROUP]))
        .arg(&me)
        .args(["--exact", "child_as_another_user", "--nocapture"])
        .env("PROCIMG_SHM_DIR", &shm)
        .env(CHILD_ENV, format!("cycles:{instance}"))
        .output()
        .expect("setpriv (util-linux)");
    assert_eq!(
        result_line(&member),
        "RESULT cycles 100",
        "the member's client: {}\nprocimgd's log:\n{}",
        String::from_utf8_lossy(&member.stderr),
        std::fs::read_to_string(&server.log).unwrap_or_default()
    );
    // The member's processes ended cleanly and left nothing in /dev/shm, where procimgd (another
    // user) could not remove it.
    let left: Vec<String> = std::fs::read_dir("/dev/shm")
        .unwrap()
        .flatten()
        .filter(|e| e.metadata().is_ok_and(|m| m.uid() == MEMBER_UID))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(left.is_empty(), "files of the member left behind: {left:?}");

    // Outside the group: access denied, and no file of the image opens.
    let outsider = Command::new("setpriv")
        .args(as_user(OUTSIDER_UID, OUTSIDER_UID, &[]))
        .arg(&me)
        .args(["--exact", "child_as_another_user", "--nocapture"])
        .env("PROCIMG_SHM_DIR", &shm)
        .env(CHILD_ENV, format!("intrude:{instance}"))
        .output()
        .expect("setpriv (util-linux)");
    let stdout = String::from_utf8_lossy(&outsider.stdout);
    assert!(
        stdout.contains("RESULT access-denied"),
        "the outsider is denied: {stdout}"
    );
    assert!(
        stdout.contains("member of the group"),
        "the message says what to do: {stdout}"
    );
    assert!(stdout.contains("RESULT opened 0"), "{stdout}");
    drop(server);
}
