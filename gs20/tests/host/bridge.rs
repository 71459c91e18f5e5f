// SPDX-License-Identifier: MIT OR Apache-2.0
//! The module the host talks to: `procimg-gs20 run` as a child process on the host's pty,
//! and the host's first exchange with it.

use super::{GENEROUS, Got, Host};
use procimg_gs20::messages::{AdapterResponse, RequestStatus};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The bridge as a child process, killed and reaped when dropped (also when the test fails).
pub struct Bridge(pub Child);

impl Bridge {
    /// `procimg-gs20 run` on `port` for procimgd `instance`, Adapter Data at least every
    /// 20 ms.
    pub fn start(port: &str, instance: &str) -> Bridge {
        Bridge::start_with(port, instance, &["--min-period-ms", "20"])
    }

    /// `procimg-gs20 run` on `port` for procimgd `instance` with further arguments `more`.
    /// Its log at `GS20_TEST_LOG` (default `info`) on the test's standard error.
    pub fn start_with(port: &str, instance: &str, more: &[&str]) -> Bridge {
        let child = Command::new(env!("CARGO_BIN_EXE_procimg-gs20"))
            .args(["run", "--port", port, "--instance", instance])
            .args(more)
            .env(
                "RUST_LOG",
                std::env::var("GS20_TEST_LOG").unwrap_or_else(|_| "info".into()),
            )
            .env("NO_COLOR", "1")
            .stdin(Stdio::null())
            .spawn()
            .expect("start procimg-gs20");
        Bridge(child)
    }

    /// Fails the test if the bridge has stopped.
    pub fn assert_running(&mut self) {
        assert!(
            self.0.try_wait().unwrap().is_none(),
            "procimg-gs20 stopped (its log is above)"
        );
    }
}

impl Drop for Bridge {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Request Status until the module answers: the host's synchronisation point (the bridge
/// may still be opening the port or attaching).
pub fn synchronise(host: &mut Host, bridge: &mut Bridge) -> AdapterResponse {
    let deadline = Instant::now() + GENEROUS;
    loop {
        bridge.assert_running();
        let from = host.mark();
        host.send(RequestStatus);
        // A second's worth of frames, then ask again.
        let until = Instant::now() + Duration::from_secs(1);
        while Instant::now() < until {
            if let Some(Got::Response(r)) = host.got[from..]
                .iter()
                .find(|g| matches!(g, Got::Response(_)))
            {
                return *r;
            }
            host.poll_once();
        }
        assert!(Instant::now() < deadline, "no answer to Request Status");
    }
}
