// SPDX-License-Identifier: MIT OR Apache-2.0
//! One cycle of a synchronous client: between STARTOP and OPDONE.
//!
//! The input views are slices of the shared-memory sample the server published (no copy);
//! the output views are slices of the shared-memory sample this client will send with its
//! OPDONE. A submodule's outputs start as last sent when the program first touches them in a
//! cycle ([`Cycle::output_mut`]), so a program may change single bytes or bits; a program that
//! writes all of them takes [`Cycle::output_overwrite`] and no copy is made.

use crate::access::resolve_write;
use crate::client::{Client, LIVENESS_PERIOD, REATTACH_PERIOD};
use crate::error::IoError;
use crate::error::WaitError;
use crate::io::{ReadResult, read_inputs, stamp};
use crate::layout::Layout;
use crate::output_sample::OutputSample;
use crate::status::{Ioxs, SubmoduleIoxs, read_status};
use procimg_control::futex::LinuxFutex;
use procimg_shm_layout::handshake::Woken;
use procimg_shm_layout::{CLIENT_WROTE_OUTPUTS, CycleInfo, Mode};
use std::time::{Duration, Instant};

impl Client {
    /// Waits for the next STARTOP and returns this cycle: a read-only view of the inputs and
    /// a writable view of the outputs, both in shared memory. Other events that arrive
    /// meanwhile are kept for [`Client::events`]. If the server went away, the client tries to
    /// re-attach until the timeout.
    pub fn wait_startop(&mut self, timeout: Duration) -> Result<Cycle<'_>, WaitError> {
        let until = Instant::now() + timeout;
        // A thread that waits for STARTOP runs a cycle loop: with procimg's real-time
        // allocator installed (the C library has it) its loans come from the pool.
        crate::rt_alloc::mark_current_thread_realtime();
        loop {
            if self.conn.is_none() {
                self.try_reattach()?;
            }
            // Read before looking for the image: what the server signals after this ends the
            // wait below at once.
            let seen = self.conn.as_ref().map(|c| {
                let block = c.handshake.block();
                (block.events_seen(), block.pins.newest_word())
            });
            self.drain_events();
            if self.conn.is_some() && self.take_new_cycle() {
                return Ok(Cycle::new(self));
            }
            let now = Instant::now();
            if now >= until {
                return Err(if self.conn.is_none() {
                    WaitError::ServerGone {
                        instance: self.instance().to_string(),
                    }
                } else {
                    WaitError::Timeout(timeout)
                });
            }
            let slice = (until - now).min(LIVENESS_PERIOD);
            let deadline = now_ns().saturating_add(slice.as_nanos() as u64);
            let woken = match (&self.conn, seen) {
                (Some(conn), Some((seen, newest))) => {
                    let block = conn.handshake.block();
                    if self.opts.busy_poll {
                        block.spin_startop(&LinuxFutex, seen, newest, deadline)
                    } else {
                        // Asleep until shortly before STARTOP is due, then polling for it:
                        // the CPU is running when it comes.
                        let poll = self.poll_window();
                        block.wait_startop_ahead(
                            &LinuxFutex,
                            self.slot,
                            (seen, newest),
                            poll,
                            deadline,
                        )
                    }
                }
                _ => {
                    std::thread::sleep(slice.min(REATTACH_PERIOD));
                    continue;
                }
            };
            if woken == Woken::TimedOut {
                self.check_server();
            }
        }
    }
}

/// This cycle's inputs and outputs, valid until [`Cycle::set_opdone`] (or drop, which sends
/// nothing: the server then counts an OPFAULT for a synchronous client).
pub struct Cycle<'c> {
    client: &'c mut Client,
    output: Option<OutputSample>,
}

/// A cycle window held apart from its client, for callers that cannot keep the borrow of
/// [`Cycle`] (a C handle, an IO-Base controller whose calls come from several threads): take
/// it with [`Cycle::detach`], continue it with [`DetachedCycle::resume`] on the same client.
pub struct DetachedCycle {
    output: Option<OutputSample>,
    number: u64,
}

impl DetachedCycle {
    /// The cycle number k of this window.
    pub fn number(&self) -> u64 {
        self.number
    }

    /// Continues the window on `client` (the one it was detached from). `None` when the client
    /// has moved on to a newer cycle meanwhile: the window is over, its outputs unsent.
    pub fn resume(self, client: &mut Client) -> Option<Cycle<'_>> {
        let current = client.cycle_info().map_or(0, |i| i.cycle_number);
        (current == self.number).then_some(Cycle {
            client,
            output: self.output,
        })
    }
}

impl<'c> Cycle<'c> {
    pub(crate) fn new(client: &'c mut Client) -> Cycle<'c> {
        Cycle {
            client,
            output: None,
        }
    }

    /// Ends the borrow of the client and keeps the window (and any outputs written so far)
    /// for [`DetachedCycle::resume`].
    pub fn detach(self) -> DetachedCycle {
        DetachedCycle {
            number: self.number(),
            output: self.output,
        }
    }

    fn payload(&self) -> &[u8] {
        self.client.latest.as_ref().map_or(&[], |s| s.payload())
    }

    /// The cycle's timing as the server stamped it at STARTOP.
    pub fn info(&self) -> CycleInfo {
        self.client.cycle_info().unwrap_or_default()
    }

    /// The cycle number k.
    pub fn number(&self) -> u64 {
        self.info().cycle_number
    }

    /// The server's mode in this cycle.
    pub fn mode(&self) -> Mode {
        self.client.mode().unwrap_or(Mode::Offline)
    }

    /// The layout.
    pub fn layout(&self) -> &Layout {
        &self.client.layout
    }

    /// The server instance.
    pub fn instance(&self) -> &str {
        self.client.instance()
    }

    /// All input data of this cycle, in place in shared memory.
    pub fn inputs(&self) -> &[u8] {
        let n = self.client.layout.header.input_size as usize;
        self.payload().get(..n).unwrap_or(&[])
    }

    /// The inputs of submodule `s`, in place.
    pub fn input(&self, s: usize) -> Option<&[u8]> {
        let e = self.client.layout.submodules.get(s)?;
        let at = e.input_offset as usize;
        self.payload().get(at..at + e.input_length as usize)
    }

    /// The outputs of submodule `s` as they went out last cycle, in place.
    pub fn outputs_sent(&self, s: usize) -> Option<&[u8]> {
        let e = self.client.layout.submodules.get(s)?;
        let at = e.output_mirror_offset as usize;
        self.payload().get(at..at + e.output_length as usize)
    }

    /// The status bytes of submodule `s` in this cycle.
    pub fn status(&self, s: usize) -> Option<SubmoduleIoxs> {
        let e = self.client.layout.submodules.get(s)?;
        Some(read_status(self.payload(), e))
    }

    /// Reads inputs at a logical address (IO-Base `PNIO_data_read` inside the window).
    pub fn read(
        &mut self,
        address: u32,
        buf: &mut [u8],
        local: Ioxs,
    ) -> Result<ReadResult, IoError> {
        let (res, s) = read_inputs(self.client, self.payload(), address, buf)?;
        if read_status(self.payload(), &self.client.layout.submodules[s]).input_local != local {
            let e = self.client.layout.submodules[s];
            stamp(self.output_sample()?, &e, None, None, Some(local));
        }
        Ok(res)
    }

    fn output_sample(&mut self) -> Result<&mut [u8], IoError> {
        if self.output.is_none() {
            self.output = Some(self.client.loan_output()?);
        }
        // Just set when it was None.
        Ok(self.output.as_mut().map_or(&mut [], |s| s.payload_mut()))
    }

    /// The outputs of submodule `s` for this cycle, writable in place, starting as last
    /// sent. Marks them written with local status GOOD.
    pub fn output_mut(&mut self, s: usize) -> Result<&mut [u8], IoError> {
        self.claimed_output(s, true)
    }

    /// The outputs of submodule `s` for this cycle, writable in place, for a program that
    /// writes every byte of them: unlike [`Cycle::output_mut`] they do not start as last sent
    /// (what they hold is unspecified until written), which saves copying them. Marks them
    /// written with local status GOOD.
    pub fn output_overwrite(&mut self, s: usize) -> Result<&mut [u8], IoError> {
        self.claimed_output(s, false)
    }

    fn claimed_output(&mut self, s: usize, keep_last: bool) -> Result<&mut [u8], IoError> {
        let e = *self
            .client
            .layout
            .submodules
            .get(s)
            .ok_or(IoError::NotClaimed {
                submodule: s,
                address: procimg_shm_layout::NO_ADDRESS,
            })?;
        if !self.client.holds(s) {
            return Err(IoError::NotClaimed {
                submodule: s,
                address: e.output_address,
            });
        }
        // Written here, not through the write cache: the cache's copy is no longer current.
        self.client.write_cache.valid[s] = false;
        self.output_sample()?;
        let (client, output) = (&*self.client, &mut self.output);
        let payload = output.as_mut().map_or(&mut [][..], |o| o.payload_mut());
        let cs = e.client_status_offset as usize;
        let at = e.output_offset as usize;
        let len = e.output_length as usize;
        let written = payload
            .get(cs + 2)
            .is_some_and(|f| f & CLIENT_WROTE_OUTPUTS != 0);
        // The first touch in this cycle: the sample's bytes are not this submodule's yet.
        if keep_last && !written {
            client.copy_last_sent(s, &mut payload[at..at + len]);
        }
        stamp(payload, &e, None, Some(Ioxs::Good), None);
        payload[cs + 2] |= CLIENT_WROTE_OUTPUTS;
        Ok(&mut payload[at..at + len])
    }

    /// All output data of this cycle, writable in place, starting as last sent (the Q area of
    /// a PLC's process image). Every submodule this client has claimed is marked written
    /// with local status GOOD; bytes of submodules it has not claimed are ignored by the
    /// server.
    pub fn outputs_mut(&mut self) -> Result<&mut [u8], IoError> {
        self.client
            .write_cache
            .valid
            .iter_mut()
            .for_each(|v| *v = false);
        self.output_sample()?;
        let (client, output) = (&*self.client, &mut self.output);
        let payload = output.as_mut().map_or(&mut [][..], |o| o.payload_mut());
        // What this cycle has not written yet starts as last sent.
        for (s, e) in client.layout.submodules.iter().enumerate() {
            let cs = e.client_status_offset as usize;
            if payload
                .get(cs + 2)
                .is_some_and(|f| f & CLIENT_WROTE_OUTPUTS != 0)
            {
                continue;
            }
            let at = e.output_offset as usize;
            client.copy_last_sent(s, &mut payload[at..at + e.output_length as usize]);
        }
        for &s in &client.claims {
            if let Some(e) = client.layout.submodules.get(s) {
                stamp(payload, e, None, Some(Ioxs::Good), None);
                payload[e.client_status_offset as usize + 2] |= CLIENT_WROTE_OUTPUTS;
            }
        }
        let size = client.layout.header.output_size as usize;
        Ok(&mut payload[..size])
    }

    /// Sets the local status (IOPS) of submodule `s`'s outputs for this cycle.
    pub fn set_output_status(&mut self, s: usize, local: Ioxs) -> Result<(), IoError> {
        let _ = self.output_mut(s)?;
        let e = self.client.layout.submodules[s];
        stamp(self.output_sample()?, &e, None, Some(local), None);
        Ok(())
    }

    /// Writes outputs at a logical address (IO-Base `PNIO_data_write` inside the window).
    /// Returns the remote status of the previous cycle's outputs.
    pub fn write(&mut self, address: u32, data: &[u8], local: Ioxs) -> Result<Ioxs, IoError> {
        let r = resolve_write(
            &self.client.layout.submodules,
            address,
            data.len(),
            self.client.opts.slice_access,
        )?;
        let remote = self
            .status(r.submodule)
            .map_or(Ioxs::Bad, |st| st.output_remote);
        // A write of the whole submodule needs nothing of its last outputs.
        let whole = r.offset == 0
            && r.len == self.client.layout.submodules[r.submodule].output_length as usize;
        let out = self
            .claimed_output(r.submodule, !whole)
            .map_err(|e| match e {
                IoError::NotClaimed { submodule, .. } => IoError::NotClaimed { submodule, address },
                e => e,
            })?;
        out[r.offset..r.offset + r.len].copy_from_slice(data);
        let e = self.client.layout.submodules[r.submodule];
        stamp(self.output_sample()?, &e, None, Some(local), None);
        Ok(remote)
    }

    /// Sends this cycle's outputs and signals OPDONE (IO-Base `PNIO_CP_set_opdone`). Returns
    /// the cycle info at OPDONE time: `since_cycle_start_ns` minus STARTOP's is the time the
    /// client took.
    pub fn set_opdone(mut self) -> Result<CycleInfo, IoError> {
        let cycle = self.number();
        let sample = match self.output.take() {
            Some(s) => s,
            None => self.client.loan_output()?,
        };
        self.client.send_output(sample, Some(cycle))?;
        let mut info = self.info();
        info.stamp(now_ns());
        Ok(info)
    }
}

/// `CLOCK_MONOTONIC` in ns: the clock of `CycleInfo` (the server's clock).
pub use procimg_shm_layout::os::monotonic_ns as now_ns;
