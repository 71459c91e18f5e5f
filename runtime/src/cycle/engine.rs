// SPDX-License-Identifier: MIT OR Apache-2.0
//! One cycle of the server (DESIGN.md §3), run on the cycle thread.
//!
//! Per cycle k: apply queued commands and one mode step; receive inputs from the IO system
//! into the sample about to be published; publish it as one immutable image and loan the
//! next, which the clients' outputs are merged into; STARTOP; wait until every armed
//! synchronous client has sent its OPDONE, or the deadline; OPFAULT to the late ones; merge
//! outputs; send them; NEWCYCLE; statistics. Nothing here allocates, blocks on a lock or
//! logs once the engine is built.

use super::force::ForcePlan;
use super::link::{ClientLink, Taken};
use super::publication::Publication;
use super::shared::{Command, Shared};
use crate::config::{LatePolicy, OpdoneWait, OutputTiming};
use crate::image::{Image, Tables};
use crate::io::{CycleTime, IoSystem};
use crate::shm::CyclePorts;
use crate::stats::StatsRecorder;
use procimg_control::Space;
use procimg_shm_layout::events::{
    EVENT_MODE, EVENT_NEWCYCLE, EVENT_SHUTDOWN, EVENT_STARTOP, opfault_event,
};
use procimg_shm_layout::{
    CLIENT_SET_INPUT_IOCS, CLIENT_SET_OUTPUT_IOPS, CLIENT_WROTE_OUTPUTS, CycleInfo, IMAGE_MAGIC,
    IOXS_BAD_BY_CONTROLLER, IOXS_BAD_BY_DEVICE, IOXS_GOOD, ImageHeader, MAX_CLIENTS, MODE_HISTORY,
    Mode, OUTPUT_SYNCHRONOUS, OutputHeader, ROLE_DEVICE, cycle_count,
};
use std::sync::Arc;
use std::sync::atomic::Ordering;

/// The settings the engine runs with.
#[derive(Clone, Debug, PartialEq)]
pub struct EngineSettings {
    /// Cycle time T in ns.
    pub cycle_ns: u64,
    /// OPDONE deadline after the cycle start, in ns.
    pub opdone_deadline_ns: u64,
    /// What happens to a late client's outputs.
    pub late_policy: LatePolicy,
    /// When the outputs go out.
    pub output_timing: OutputTiming,
    /// How the thread waits for OPDONE.
    pub opdone_wait: OpdoneWait,
    /// With [`OpdoneWait::Event`]: how long after STARTOP it polls before it sleeps, in ns.
    pub opdone_spin_ns: u64,
    /// Server generation.
    pub generation: u64,
}

#[derive(Clone, Copy, Debug, Default)]
struct ClientRt {
    token: u64,
    active: bool,
    synchronous: bool,
    /// Waited for in this cycle. Cleared by an OPFAULT, set again by the client's next
    /// sample, so a client that died costs one OPFAULT, not one per cycle until it is reaped.
    armed: bool,
    /// Its OPDONE for this cycle arrived.
    done: bool,
    /// It asked for NEWCYCLE.
    newcycle: bool,
    /// It got an OPFAULT and has not handed in an OPDONE in time since.
    faulted: bool,
}

struct State {
    settings: EngineSettings,
    shared: Arc<Shared>,
    stats: StatsRecorder,
    image: Image,
    header: ImageHeader,
    clients: [ClientRt; MAX_CLIENTS],
    /// Per submodule: the output IOPS the owning client set.
    output_iops: Vec<u8>,
    /// The IOPS of data no client provides: BAD, detected by the controller, or in the
    /// device role by the device.
    bad_by_us: u8,
    /// Per submodule: the input IOCS the clients set.
    input_iocs: Vec<u8>,
    /// Per submodule: its owner is late (faulted) and the policy is IOPS BAD.
    late_bad: Vec<bool>,
    /// Per submodule: the owner token seen last; a change resets the output IOPS to BAD until
    /// the new owner writes.
    last_owner: Vec<u64>,
    mode: Mode,
    target: Mode,
    layout_hash: u64,
    output_payload_size: usize,
    /// Where an output sample's client status array starts: 4 bytes per submodule in table
    /// order, so a sample's statuses are one slice.
    client_status_offset: usize,
    cycle: u64,
    startop_ns: u64,
    /// Outputs merged but not yet sent (OutputTiming::AtNextCycleStart).
    outputs_pending: bool,
    /// What is forced (from the force table of the acyclic side).
    force: Box<ForcePlan>,
    /// CPUs this process may run on: polling for OPDONE helps only while the clients waited
    /// for have CPUs beside the cycle thread's.
    cpus: usize,
    /// The samples the image is built in and published from.
    publication: Publication,
}

/// The cycle engine: the link to the clients (the iceoryx2 ports in procimgd), the IO system
/// and the state of the cycle.
pub struct Engine<L: ClientLink = CyclePorts> {
    ports: L,
    io: Box<dyn IoSystem>,
    st: State,
}

impl<L: ClientLink> Engine<L> {
    /// An engine over `ports` and `io`; the server starts in OFFLINE and steps towards
    /// `Shared::target_mode`.
    pub fn new(
        settings: EngineSettings,
        tables: &Tables,
        ports: L,
        io: Box<dyn IoSystem>,
        shared: Arc<Shared>,
        stats: StatsRecorder,
    ) -> Engine<L> {
        let n = tables.submodules.len();
        let bad_by_us = if tables.role == ROLE_DEVICE {
            IOXS_BAD_BY_DEVICE
        } else {
            IOXS_BAD_BY_CONTROLLER
        };
        let mut header = ImageHeader::new(tables.hash, settings.generation);
        header.submodule_count = n as u32;
        header.payload_size = tables.layout.input_payload_size;
        header.cycle_ns = settings.cycle_ns;
        header.opdone_deadline_ns = settings.opdone_deadline_ns;
        let target =
            Mode::from_u32(shared.target_mode.load(Ordering::Acquire)).unwrap_or(Mode::Offline);
        shared
            .counters
            .mode
            .store(Mode::Offline.as_u32(), Ordering::Release);
        Engine {
            ports,
            io,
            st: State {
                settings,
                shared,
                stats,
                image: Image::new(tables),
                header,
                clients: [ClientRt::default(); MAX_CLIENTS],
                output_iops: vec![bad_by_us; n],
                bad_by_us,
                input_iocs: vec![IOXS_GOOD; n],
                late_bad: vec![false; n],
                last_owner: vec![0; n],
                mode: Mode::Offline,
                target,
                layout_hash: tables.hash,
                output_payload_size: tables.layout.output_payload_size as usize,
                client_status_offset: tables.layout.client_status_offset as usize,
                cycle: 0,
                startop_ns: 0,
                outputs_pending: false,
                force: Box::new(ForcePlan::empty(n)),
                cpus: std::thread::available_parallelism().map_or(1, |n| n.get()),
                publication: Publication::new(),
            },
        }
    }

    /// The mode the engine is in.
    pub fn mode(&self) -> Mode {
        self.st.mode
    }

    /// Runs cycle `k`, planned to start at `t0_ns`.
    pub fn run_cycle(&mut self, k: u64, t0_ns: u64) {
        let woke = self.ports.now_ns();
        // Clients that connected since the maintenance before this cycle: set up here, as
        // connection set-up, rather than lazily by iceoryx2 inside the publish, notify or
        // receive below (cheap when nothing changed).
        self.maintain_connections();
        let st = &mut self.st;
        st.cycle = k;
        st.stats.wakeup(woke.saturating_sub(t0_ns));
        st.apply_commands(&mut self.ports);
        let t = CycleTime {
            cycle: k,
            now_ns: woke,
        };
        // Outputs held back for the cycle start go out in the mode they were made for.
        if st.outputs_pending {
            self.io.send(t, st.mode, &mut st.image);
            st.outputs_pending = false;
        }
        let mode_changed = st.step_mode();

        // 1. Inputs from the IO system, straight into the sample to be published; the last
        // inputs of devices that sent nothing, forced inputs over them; local input status
        // from the clients.
        st.publication.begin(&mut self.ports, &mut st.image);
        self.io.receive(t, st.mode, &mut st.image);
        st.image.carry_over_inputs();
        st.force.apply(Space::Input, &mut st.image);
        st.apply_input_iocs();

        // 2. Publish the input image; loan the next, which this cycle's outputs go into.
        st.header.cycle = CycleInfo {
            cycle_number: k,
            cycle_start_ns: t0_ns,
            cycle_count: cycle_count(k, st.settings.cycle_ns),
            ..CycleInfo::default()
        };
        st.header.mode = st.mode.as_u32();
        // When every client finds the image by its mark, iceoryx2's copy of it goes out after
        // the outputs (step 6): its send then costs the clients' window nothing.
        let send_later = self.ports.read_by_mark(st.client_slots());
        // Stamped by the publication, last: the clock in the header is when the image was
        // complete, which clients measure their STARTOP latency from.
        let published =
            st.publication
                .finish(&mut self.ports, &mut st.image, &mut st.header, send_later);

        // 3. STARTOP (and the mode indication, now that the image carries the new mode). The
        // round trip counts from the image's stamp: a client that reads by its mark may see
        // the image from then on, before the announcement.
        st.startop_ns = if published {
            st.header.cycle.clock_ns
        } else {
            self.ports.now_ns()
        };
        if published {
            self.ports.notify(EVENT_STARTOP);
        } else {
            st.shared
                .counters
                .unpublished_images
                .fetch_add(1, Ordering::Relaxed);
        }
        if mode_changed {
            self.ports.notify(EVENT_MODE);
        }
        // The sample this cycle's outputs go into (loaned at the end of the last cycle).
        st.publication.loan_next(&mut self.ports, &mut st.image);

        // 4./5. Wait for OPDONE of the armed synchronous clients, merging outputs as they come.
        // Without a published image there is nothing to answer: nobody is waited for.
        let deadline = t0_ns + st.settings.opdone_deadline_ns;
        let spin_until = match st.settings.opdone_wait {
            OpdoneWait::BusyPoll => deadline,
            // More clients than the other CPUs: some share the cycle thread's CPU and could
            // not answer while it polls.
            OpdoneWait::Event if st.waited_for() < st.cpus => {
                st.startop_ns + st.settings.opdone_spin_ns
            }
            OpdoneWait::Event => 0,
        };
        loop {
            let mark = self.ports.opdone_mark();
            drain_outputs(&mut self.ports, st);
            if !published || st.all_done() {
                break;
            }
            if self.ports.now_ns() >= deadline {
                break;
            }
            self.ports.wait_outputs(mark, deadline, spin_until);
        }
        if published {
            st.opfault_late_clients(&mut self.ports);
        }
        // Outputs nobody wrote in this cycle stay as last sent.
        st.image.carry_over_outputs();
        st.mark_late_outputs();
        // Forced outputs over what the clients wrote.
        st.force.apply(Space::Output, &mut st.image);

        // 6. Outputs go out, NEWCYCLE.
        st.prepare_output_status();
        if st.mode != Mode::Offline {
            match st.settings.output_timing {
                OutputTiming::Immediately => {
                    self.io.send(
                        CycleTime {
                            cycle: k,
                            now_ns: self.ports.now_ns(),
                        },
                        st.mode,
                        &mut st.image,
                    );
                }
                OutputTiming::AtNextCycleStart => st.outputs_pending = true,
            }
        }
        // iceoryx2's readers missed an image the clients reading by their mark saw.
        if !self.ports.send_named() {
            st.shared
                .counters
                .unpublished_images
                .fetch_add(1, Ordering::Relaxed);
        }
        // The sample the next cycle's outputs go into, loaned now rather than after its
        // STARTOP.
        self.ports.loan_ahead(st.image.payload_len());
        st.stats.work(self.ports.now_ns().saturating_sub(t0_ns));
        // Only when asked for: every notification wakes every listener.
        if st.clients.iter().any(|c| c.active && c.newcycle) {
            self.ports.notify(EVENT_NEWCYCLE);
        }

        // 7. Statistics.
        st.shared.counters.cycles.store(k, Ordering::Release);
        if k.is_multiple_of(crate::stats::HANDOFF_CYCLES) {
            st.stats.hand_over();
        }
    }

    /// Sets up and tears down iceoryx2 connections to clients that came or went. Called just
    /// before a cycle starts: otherwise iceoryx2 does it lazily inside the next publish or
    /// receive, where the work (mapping, unmapping segments) eats into the OPDONE window of
    /// every client.
    pub fn maintain_connections(&mut self) {
        self.ports.maintain();
        // A loan reached into the last input samples faulted in: the control thread faults
        // in more, before a later loan needs them (`shm::reserve`).
        if self.st.shared.input_reserve.needs_extending() {
            self.st.shared.ring_control();
        }
    }

    /// Counts an overrun (cycles skipped because cycle work ran past the next start).
    pub fn count_overrun(&self) {
        self.st
            .shared
            .counters
            .overruns
            .fetch_add(1, Ordering::Relaxed);
    }

    /// Tells clients the server is going away.
    pub fn announce_shutdown(&mut self) {
        self.st.stats.hand_over();
        self.ports.notify(EVENT_SHUTDOWN);
    }
}

/// Merges every output sample waiting. iceoryx2 fails a whole `receive` when it cannot
/// update one connection (a dead client's, while it is being cleaned up) even though the
/// samples of the other clients are there; a few retries get past such a moment without
/// costing a healthy client its OPDONE.
fn drain_outputs(ports: &mut impl ClientLink, st: &mut State) {
    let mut retries = 0;
    // Bounded, so that a client writing in a tight loop cannot hold the cycle past its
    // deadline: what is left waits for the next drain.
    for _ in 0..4 * MAX_CLIENTS {
        match ports.take_output(&mut |h, payload, now| st.merge(h, payload, now)) {
            Taken::Sample => {}
            Taken::InPlace => {
                st.shared
                    .counters
                    .outputs_in_place
                    .fetch_add(1, Ordering::Relaxed);
            }
            Taken::Torn(slot) => st.tear(slot),
            Taken::Nothing => return,
            Taken::Failed => {
                st.shared
                    .counters
                    .receive_errors
                    .fetch_add(1, Ordering::Relaxed);
                retries += 1;
                if retries > 3 {
                    return;
                }
            }
        }
    }
}

impl State {
    fn apply_commands(&mut self, ports: &mut impl ClientLink) {
        while let Some(c) = self.shared.commands.pop() {
            match c {
                Command::Join {
                    slot,
                    token,
                    synchronous,
                    newcycle,
                } => {
                    ports.forget_client(slot, &self.shared.outputs);
                    if let Some(cl) = self.clients.get_mut(slot as usize) {
                        *cl = ClientRt {
                            token,
                            active: true,
                            synchronous,
                            // Waited for from its first OPDONE on: a client that is still
                            // setting up is not late.
                            armed: false,
                            done: false,
                            newcycle,
                            ..ClientRt::default()
                        };
                    }
                    let counters = &self.shared.counters;
                    if let Some(c) = counters.client_opfaults.get(slot as usize) {
                        c.store(0, Ordering::Relaxed);
                    }
                    if let Some(c) = counters.client_last_opfault.get(slot as usize) {
                        c.store(0, Ordering::Relaxed);
                    }
                }
                Command::Leave { slot } => {
                    ports.forget_client(slot, &self.shared.outputs);
                    if let Some(cl) = self.clients.get_mut(slot as usize) {
                        *cl = ClientRt::default();
                    }
                    if let Some(v) = self.header.opfault_cycle.get_mut(slot as usize) {
                        *v = 0;
                    }
                }
                Command::SetMode(m) => self.target = m,
            }
        }
        // After the commands: a port arrives after its client's Join was queued, and is taken
        // only for the registration it was made for.
        let clients = &self.clients;
        ports.adopt_outputs(&self.shared.outputs, &|slot, token| {
            clients
                .get(slot as usize)
                .is_some_and(|c| c.active && c.token == token)
        });
        self.shared.take_force_plan(&mut self.force);
        for c in &mut self.clients {
            c.done = false;
        }
        // A submodule whose owner changed (claimed, released, owner gone) goes out invalid
        // until its new owner writes it.
        for s in 0..self.last_owner.len() {
            let owner = self.shared.owner(s);
            if owner != self.last_owner[s] {
                self.last_owner[s] = owner;
                self.output_iops[s] = self.bad_by_us;
            }
        }
    }

    /// Moves one step towards the target mode (OFFLINE and OPERATE pass through CLEAR, as
    /// IO-Base reports them). Returns whether the mode changed.
    fn step_mode(&mut self) -> bool {
        if self.mode == self.target {
            return false;
        }
        let next = match (self.mode, self.target) {
            (Mode::Offline, Mode::Operate) | (Mode::Operate, Mode::Offline) => Mode::Clear,
            (_, t) => t,
        };
        if next == Mode::Offline {
            // IO-Base: in OFFLINE, the outputs and local states written are lost.
            for s in 0..self.output_iops.len() {
                self.image.outputs_mut(s).fill(0);
                self.output_iops[s] = self.bad_by_us;
                self.input_iocs[s] = IOXS_GOOD;
            }
        }
        self.mode = next;
        self.header.mode_changes = self.header.mode_changes.wrapping_add(1);
        let at = self.header.mode_changes as usize % MODE_HISTORY;
        self.header.mode_history[at] = next.as_u32();
        self.shared
            .counters
            .mode
            .store(next.as_u32(), Ordering::Release);
        true
    }

    fn apply_input_iocs(&mut self) {
        let connected = self.mode != Mode::Offline;
        for s in 0..self.input_iocs.len() {
            let e = self.image.submodules()[s];
            if e.input_length == 0 {
                continue;
            }
            let mut st = self.image.status(s);
            st.input_iocs = if connected {
                self.input_iocs[s]
            } else {
                self.bad_by_us
            };
            self.image.set_status(s, st);
        }
    }

    /// The slots of the clients registered now (bit per slot).
    fn client_slots(&self) -> u64 {
        self.clients
            .iter()
            .enumerate()
            .filter(|(_, c)| c.active)
            .fold(0, |slots, (slot, _)| slots | 1 << slot)
    }

    /// The synchronous clients whose OPDONE this cycle waits for.
    fn waited_for(&self) -> usize {
        self.clients
            .iter()
            .filter(|c| c.active && c.synchronous && c.armed)
            .count()
    }

    fn all_done(&self) -> bool {
        self.clients
            .iter()
            .all(|c| !(c.active && c.synchronous && c.armed) || c.done)
    }

    fn merge(&mut self, h: &OutputHeader, payload: &[u8], now: u64) {
        let h = *h;
        let slot = h.client_slot as usize;
        let valid = h.magic == IMAGE_MAGIC
            && h.layout_hash == self.layout_hash
            && payload.len() >= self.output_payload_size
            && self
                .clients
                .get(slot)
                .is_some_and(|c| c.active && c.token == h.client_token);
        if !valid {
            self.shared
                .counters
                .rejected_writes
                .fetch_add(1, Ordering::Relaxed);
            return;
        }
        if h.flags & OUTPUT_SYNCHRONOUS != 0 {
            let client = &mut self.clients[slot];
            client.armed = true;
            if h.cycle_number != self.cycle {
                // OPDONE of an earlier cycle, arriving late: those outputs are not used.
                return;
            }
            client.done = true;
            client.faulted = false;
            self.stats.handshake(now.saturating_sub(self.startop_ns));
            if h.sent_ns != 0 {
                self.stats.opdone(now.saturating_sub(h.sent_ns));
            }
        }
        let token = h.client_token;
        let at = self.client_status_offset;
        let Some(statuses) = payload.get(at..at + 4 * self.output_iops.len()) else {
            return;
        };
        // Most statuses in a sample are untouched (flags 0): they are skipped without a look
        // at the submodule table, which counts once many clients own a few submodules each.
        for (s, cs) in statuses.chunks_exact(4).enumerate() {
            let (iops, iocs, flags) = (cs[0], cs[1], cs[2]);
            if flags == 0 {
                continue;
            }
            let e = self.image.submodules()[s];
            if flags & CLIENT_SET_INPUT_IOCS != 0 {
                self.input_iocs[s] = iocs;
            }
            if flags & (CLIENT_WROTE_OUTPUTS | CLIENT_SET_OUTPUT_IOPS) == 0 {
                continue;
            }
            if self.shared.owner(s) != token {
                self.shared
                    .counters
                    .rejected_writes
                    .fetch_add(1, Ordering::Relaxed);
                continue;
            }
            self.last_owner[s] = token;
            if flags & CLIENT_WROTE_OUTPUTS != 0 {
                let from = e.output_offset as usize;
                let len = e.output_length as usize;
                if let Some(src) = payload.get(from..from + len) {
                    self.image.set_outputs(s, src);
                }
            }
            if flags & CLIENT_SET_OUTPUT_IOPS != 0 {
                self.output_iops[s] = iops;
            }
        }
    }

    /// The sample of `slot` just merged was written again while it was read (a busy client
    /// writing outside its window): not an answer (an OPFAULT follows), and no byte of it
    /// is trusted. The client's outputs are cleared and go out BAD until it writes them
    /// again, as after OFFLINE. A late sample (not this cycle's) wrote nothing, and its
    /// client did nothing wrong: it answered late, saw the next STARTOP and began its next
    /// window in the sample while the cycle was still looking at the late answer.
    fn tear(&mut self, slot: u32) {
        let Some(c) = self.clients.get_mut(slot as usize) else {
            return;
        };
        if !c.done {
            return;
        }
        self.shared
            .counters
            .rejected_writes
            .fetch_add(1, Ordering::Relaxed);
        c.done = false;
        let token = c.token;
        for s in 0..self.output_iops.len() {
            if self.shared.owner(s) == token {
                self.image.outputs_mut(s).fill(0);
                self.output_iops[s] = self.bad_by_us;
            }
        }
    }

    fn opfault_late_clients(&mut self, ports: &mut impl ClientLink) {
        for slot in 0..MAX_CLIENTS {
            let c = self.clients[slot];
            if !(c.active && c.synchronous && c.armed) || c.done {
                continue;
            }
            self.clients[slot].armed = false;
            self.clients[slot].faulted = true;
            self.header.opfault_cycle[slot] = self.cycle;
            let counters = &self.shared.counters;
            counters.opfaults.fetch_add(1, Ordering::Relaxed);
            counters.client_opfaults[slot].fetch_add(1, Ordering::Relaxed);
            counters.client_last_opfault[slot].store(self.cycle, Ordering::Relaxed);
            ports.notify(opfault_event(slot as u32));
        }
    }

    /// With `late_client_policy = "iops-bad"`, the submodules of every client that got an
    /// OPFAULT and has not been in time since go out BAD, for as long as that lasts.
    fn mark_late_outputs(&mut self) {
        self.late_bad.iter_mut().for_each(|b| *b = false);
        if self.settings.late_policy != LatePolicy::IopsBad {
            return;
        }
        for c in &self.clients {
            if !(c.active && c.synchronous && c.faulted) {
                continue;
            }
            for s in 0..self.late_bad.len() {
                if self.shared.owner(s) == c.token {
                    self.late_bad[s] = true;
                }
            }
        }
    }

    fn prepare_output_status(&mut self) {
        for s in 0..self.output_iops.len() {
            let e = self.image.submodules()[s];
            if e.output_length == 0 {
                continue;
            }
            let mut st = self.image.status(s);
            // Outputs nobody owns are not being written by anyone: they go out invalid, so the
            // device applies its substitute values. Forced outputs go out valid, as a PLC's
            // force reaches the process whatever the program does (but not in CLEAR).
            let owned = self.last_owner[s] != 0;
            st.output_iops = match self.mode {
                Mode::Operate if self.force.forces_outputs_of(s) => IOXS_GOOD,
                Mode::Operate if owned && !self.late_bad[s] => self.output_iops[s],
                _ => self.bad_by_us,
            };
            self.image.set_status(s, st);
        }
    }
}

#[cfg(test)]
#[path = "engine_tests.rs"]
mod tests;
