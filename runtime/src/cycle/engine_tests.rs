// SPDX-License-Identifier: MIT OR Apache-2.0
//! The cycle's rules as exact tables: the engine over an in-memory link with a clock the test
//! sets, the demo's layout, and an IO system that records what would go on the wire. No
//! process, no sleep, no real time.

use super::*;
use crate::config::Config;
use crate::cycle::MemoryLink;
use crate::image::{Image, Tables};
use crate::io::{CycleTime, IoSystem};
use procimg_shm_layout::{CLIENT_WROTE_OUTPUTS, IOXS_BAD_BY_CONTROLLER, IOXS_GOOD};
use std::sync::Mutex;

const T: u64 = 1_000_000;
const DEADLINE: u64 = 500_000;

/// What one `send` put on the wire: the mode and, per submodule, outputs and IOPS.
type Sent = (Mode, Vec<(Vec<u8>, u8)>);

/// Inputs the next `receive` delivers: per submodule, its new inputs.
type Arriving = Arc<Mutex<Vec<(usize, Vec<u8>)>>>;

/// An IO system that delivers the inputs the test puts in `1` and records every send.
struct RecordingIo(Arc<Mutex<Vec<Sent>>>, Arriving);

impl IoSystem for RecordingIo {
    fn receive(&mut self, _: CycleTime, _: Mode, image: &mut Image) {
        for (s, data) in self.1.lock().unwrap().drain(..) {
            assert!(image.set_inputs(s, &data));
        }
    }

    fn send(&mut self, _: CycleTime, mode: Mode, image: &mut Image) {
        let per_submodule = (0..image.submodules().len())
            .map(|s| (image.outputs(s).to_vec(), image.status(s).output_iops))
            .collect();
        self.0.lock().unwrap().push((mode, per_submodule));
    }
}

struct Rig {
    engine: Engine<MemoryLink>,
    shared: Arc<Shared>,
    tables: Tables,
    sent: Arc<Mutex<Vec<Sent>>>,
    arriving: Arriving,
    k: u64,
}

impl Rig {
    fn new(late_policy: LatePolicy, start: Mode) -> Rig {
        let tables = Tables::from_config(&Config::demo()).expect("the demo layout");
        let shared = Arc::new(Shared::new(tables.submodules.len()));
        shared.target_mode.store(start.as_u32(), Ordering::Release);
        let sent = Arc::new(Mutex::new(Vec::new()));
        let arriving = Arriving::default();
        let (stats, _collector) = crate::stats::stats_channel();
        let settings = EngineSettings {
            cycle_ns: T,
            opdone_deadline_ns: DEADLINE,
            late_policy,
            output_timing: OutputTiming::Immediately,
            opdone_wait: OpdoneWait::Event,
            opdone_spin_ns: 0,
            generation: 1,
        };
        // What is not input data or output mirror is rewritten by every publication.
        let l = &tables.layout;
        let mut link = MemoryLink::default();
        link.scribble = vec![
            (l.input_size as usize, l.output_mirror_offset as usize),
            (tables.output_mirror_end(), l.input_payload_size as usize),
        ];
        let engine = Engine::new(
            settings,
            &tables,
            link,
            Box::new(RecordingIo(sent.clone(), arriving.clone())),
            shared.clone(),
            stats,
        );
        Rig {
            engine,
            shared,
            tables,
            sent,
            arriving,
            k: 0,
        }
    }

    /// Runs the next cycle at its planned start; returns the events it signalled.
    fn cycle(&mut self) -> Vec<usize> {
        self.k += 1;
        let t0 = self.k * T;
        let link = &mut self.engine.ports;
        link.now = link.now.max(t0);
        link.events.clear();
        self.engine.run_cycle(self.k, t0);
        self.engine.ports.events.clone()
    }

    /// Runs cycles until the engine is in `mode`.
    fn reach(&mut self, mode: Mode) {
        for _ in 0..3 {
            if self.engine.mode() == mode {
                return;
            }
            self.cycle();
        }
        assert_eq!(self.engine.mode(), mode);
    }

    fn join(&self, slot: u32, token: u64, synchronous: bool) {
        assert!(self.shared.command(Command::Join {
            slot,
            token,
            synchronous,
            newcycle: false,
        }));
    }

    /// Asks for `mode`, as `procimg mode` does.
    fn set_mode(&self, mode: Mode) {
        self.shared
            .target_mode
            .store(mode.as_u32(), Ordering::Release);
        assert!(self.shared.command(Command::SetMode(mode)));
    }

    fn claim(&self, s: usize, token: u64) {
        self.shared.claims[s].store(token, Ordering::Release);
    }

    fn echo(&self) -> usize {
        (0..self.tables.submodules.len())
            .find(|&s| {
                self.tables
                    .device_name(self.tables.submodules[s].device as usize)
                    == "echo"
                    && self.tables.submodules[s].output_length == 16
            })
            .expect("the demo's echo module")
    }

    /// An output sample of client (`slot`, `token`) writing `data` to submodule `s`.
    fn sample(
        &self,
        slot: u32,
        token: u64,
        cycle: u64,
        s: usize,
        data: &[u8],
    ) -> (OutputHeader, Vec<u8>) {
        let layout = &self.tables.layout;
        let mut payload = vec![0u8; layout.output_payload_size as usize];
        let e = self.tables.submodules[s];
        let at = e.output_offset as usize;
        payload[at..at + data.len()].copy_from_slice(data);
        let st = layout.client_status_offset as usize + 4 * s;
        payload[st..st + 4].copy_from_slice(&[
            IOXS_GOOD,
            0,
            CLIENT_WROTE_OUTPUTS | CLIENT_SET_OUTPUT_IOPS,
            0,
        ]);
        let header = OutputHeader {
            magic: IMAGE_MAGIC,
            layout_hash: self.tables.hash,
            cycle_number: cycle,
            client_token: token,
            client_slot: slot,
            flags: if cycle == 0 { 0 } else { OUTPUT_SYNCHRONOUS },
            sent_ns: 0,
        };
        (header, payload)
    }

    /// In OPERATE under `policy`: a synchronous client (`slot`, `token`) that owns the echo
    /// submodule, waited for from its first sample on (one still setting up is not late), and
    /// whose answer to a cycle's STARTOP (`answer` bytes) arrived while the engine waited.
    /// Returns the echo's index and that cycle's events.
    fn with_an_answering_client(
        policy: LatePolicy,
        slot: u32,
        token: u64,
        answer: u8,
    ) -> (Rig, usize, Vec<usize>) {
        let mut rig = Rig::new(policy, Mode::Operate);
        let echo = rig.echo();
        rig.join(slot, token, true);
        rig.claim(echo, token);
        rig.reach(Mode::Operate);
        let first = rig.sample(slot, token, rig.k, echo, &[0; 16]);
        rig.engine.ports.outputs.push_back(first);
        let k = rig.k + 1;
        let sample = rig.sample(slot, token, k, echo, &[answer; 16]);
        rig.engine.ports.answers.push_back(sample);
        let events = rig.cycle();
        let sent = (Mode::Operate, vec![answer; 16], IOXS_GOOD);
        assert_eq!(rig.last_sent(echo), sent);
        (rig, echo, events)
    }

    /// What the last send put out for submodule `s`.
    /// The first byte of a published `payload` that holds what its sample held when it was
    /// first loaned. The bytes around the outputs in an output frame do not count: the IO
    /// system writes them when it sends the frame (this test's sends nothing), and no client
    /// reads them.
    fn left_as_loaned(&self, payload: &[u8]) -> Option<usize> {
        let in_frame_gap = |at: usize| {
            let in_frame = self.tables.output_frames.iter().flatten();
            let mut in_frame = in_frame.map(|f| &f.range);
            in_frame.any(|r| r.contains(&at))
                && !self.tables.submodules.iter().any(|e| {
                    let start = e.output_mirror_offset as usize;
                    (start..start + e.output_length as usize).contains(&at)
                })
        };
        payload
            .iter()
            .enumerate()
            .position(|(at, &b)| b == crate::cycle::link::UNWRITTEN && !in_frame_gap(at))
    }

    fn last_sent(&self, s: usize) -> (Mode, Vec<u8>, u8) {
        let sent = self.sent.lock().unwrap();
        let (mode, subs) = sent.last().expect("something was sent");
        (*mode, subs[s].0.clone(), subs[s].1)
    }
}

#[test]
fn modes_step_through_clear_one_cycle_each_with_a_mode_event() {
    let mut rig = Rig::new(LatePolicy::HoldLastOutputs, Mode::Operate);
    let mut seen = Vec::new();
    for _ in 0..3 {
        let events = rig.cycle();
        seen.push((
            rig.engine.mode(),
            events.contains(&EVENT_MODE),
            events.contains(&EVENT_STARTOP),
        ));
    }
    assert_eq!(
        seen,
        [
            (Mode::Clear, true, true),
            (Mode::Operate, true, true),
            (Mode::Operate, false, true)
        ]
    );
    // Every step is numbered in the published image, for clients that miss a notification.
    let (header, _) = rig.engine.ports.published.last().unwrap();
    assert_eq!(header.mode_changes, 2);
    assert_eq!(header.mode, Mode::Operate.as_u32());
}

#[test]
fn only_the_owners_outputs_are_taken_and_unowned_ones_go_out_bad() {
    let mut rig = Rig::new(LatePolicy::HoldLastOutputs, Mode::Operate);
    let echo = rig.echo();
    rig.join(0, 11, false);
    rig.join(1, 22, false);
    rig.reach(Mode::Operate);
    rig.cycle();
    assert_eq!(
        rig.last_sent(echo).2,
        IOXS_BAD_BY_CONTROLLER,
        "nobody owns it yet"
    );

    rig.claim(echo, 11);
    let intruder = rig.sample(1, 22, 0, echo, &[0xbb; 16]);
    let owner = rig.sample(0, 11, 0, echo, &[0xaa; 16]);
    rig.engine.ports.outputs.extend([owner, intruder]);
    rig.cycle();
    assert_eq!(
        rig.last_sent(echo),
        (Mode::Operate, vec![0xaa; 16], IOXS_GOOD)
    );
    assert_eq!(
        rig.shared.counters.rejected_writes.load(Ordering::Relaxed),
        1
    );

    // In CLEAR the same outputs go out invalid.
    rig.set_mode(Mode::Clear);
    rig.cycle();
    assert_eq!(
        rig.last_sent(echo),
        (Mode::Clear, vec![0xaa; 16], IOXS_BAD_BY_CONTROLLER)
    );
}

#[test]
fn iceoryx2_gets_the_image_after_the_answers_only_when_every_client_reads_by_its_mark() {
    let (mut rig, echo, _) = Rig::with_an_answering_client(LatePolicy::IopsBad, 3, 33, 1);
    let named_at = |rig: &Rig| {
        let link = &rig.engine.ports;
        let (header, _) = link.published.last().expect("an image");
        (
            header.cycle.cycle_number,
            *link.sent_at.last().expect("an image"),
        )
    };
    assert_eq!(named_at(&rig), (rig.k, None), "sent before STARTOP");

    // Every client reads by its mark: the image is named, STARTOP given, the answer taken
    // and sent out, and only then does iceoryx2's send come.
    rig.engine.ports.all_read_by_mark = true;
    let k = rig.k + 1;
    let answer = rig.sample(3, 33, k, echo, &[2; 16]);
    rig.engine.ports.answers.push_back(answer);
    let events = rig.cycle();
    let startop = events.iter().position(|&e| e == EVENT_STARTOP);
    let (cycle, sent_at) = named_at(&rig);
    assert_eq!(cycle, k);
    assert!(
        sent_at.is_some_and(|at| startop.is_some_and(|s| at > s)),
        "sent at event {sent_at:?}, STARTOP at {startop:?}"
    );
    assert_eq!(rig.last_sent(echo), (Mode::Operate, vec![2; 16], IOXS_GOOD));
    assert_eq!(
        rig.shared
            .counters
            .unpublished_images
            .load(Ordering::Relaxed),
        0
    );
}

#[test]
fn a_late_synchronous_client_gets_one_opfault_and_is_not_waited_for_again() {
    // In time: its answer arrives while the engine waits.
    let (mut rig, echo, events) = Rig::with_an_answering_client(LatePolicy::IopsBad, 3, 33, 1);
    assert!(!events.contains(&opfault_event(3)));
    assert!(
        rig.engine.ports.now < rig.k * T + DEADLINE,
        "the engine did not wait for the deadline"
    );

    // Silent: one OPFAULT at the deadline, its submodule BAD (policy iops-bad) ...
    let events = rig.cycle();
    assert_eq!(events.iter().filter(|&&e| e == opfault_event(3)).count(), 1);
    assert_eq!(rig.engine.ports.now, rig.k * T + DEADLINE);
    assert_eq!(rig.last_sent(echo).2, IOXS_BAD_BY_CONTROLLER);
    assert_eq!(
        rig.shared.counters.client_last_opfault[3].load(Ordering::Relaxed),
        rig.k
    );
    // ... and then it is not waited for: no more OPFAULTs, no wait for the deadline.
    for _ in 0..5 {
        let events = rig.cycle();
        assert!(!events.contains(&opfault_event(3)));
        assert!(rig.engine.ports.now < rig.k * T + DEADLINE);
    }
    assert_eq!(rig.shared.counters.opfaults.load(Ordering::Relaxed), 1);

    // An answer to an old cycle re-arms it without being used; the next one in time counts.
    let stale = rig.sample(3, 33, rig.k, echo, &[9; 16]);
    rig.engine.ports.outputs.push_back(stale);
    let k = rig.k + 1;
    let answer = rig.sample(3, 33, k, echo, &[2; 16]);
    rig.engine.ports.answers.push_back(answer);
    rig.cycle();
    assert_eq!(rig.last_sent(echo), (Mode::Operate, vec![2; 16], IOXS_GOOD));
}

#[test]
fn a_late_answer_written_again_while_it_is_read_is_no_rejected_write() {
    let (mut rig, echo, _) = Rig::with_an_answering_client(LatePolicy::HoldLastOutputs, 2, 22, 7);
    let sent = rig.last_sent(echo);
    // The answer to the last cycle, read in this one while the client, which saw this
    // cycle's STARTOP, writes its next outputs into the same sample.
    rig.engine.ports.torn_slots.push(2);
    let late = rig.sample(2, 22, rig.k, echo, &[8; 16]);
    rig.engine.ports.outputs.push_back(late);
    let rejected = rig.shared.counters.rejected_writes.load(Ordering::Relaxed);
    rig.cycle();
    assert_eq!(
        rig.shared.counters.rejected_writes.load(Ordering::Relaxed),
        rejected,
        "a late answer is no write outside the window"
    );
    assert_eq!(rig.last_sent(echo), sent, "a late answer writes nothing");
}

#[test]
fn a_torn_opdone_sample_is_an_opfault_and_its_outputs_go_out_cleared_and_bad_until_written() {
    let (mut rig, echo, _) = Rig::with_an_answering_client(LatePolicy::HoldLastOutputs, 2, 22, 7);

    // Written again while it was read (a busy client writing outside its window).
    rig.engine.ports.torn_slots.push(2);
    let k = rig.k + 1;
    let torn = rig.sample(2, 22, k, echo, &[8; 16]);
    rig.engine.ports.answers.push_back(torn);
    let rejected = rig.shared.counters.rejected_writes.load(Ordering::Relaxed);
    let events = rig.cycle();
    assert_eq!(events.iter().filter(|&&e| e == opfault_event(2)).count(), 1);
    let cleared = (Mode::Operate, vec![0; 16], IOXS_BAD_BY_CONTROLLER);
    assert_eq!(rig.last_sent(echo), cleared);
    assert_eq!(
        rig.shared.counters.rejected_writes.load(Ordering::Relaxed),
        rejected + 1
    );
    // Not one torn byte goes out later either (hold-last-outputs keeps what was sent).
    rig.cycle();
    assert_eq!(rig.last_sent(echo), cleared);

    // Whole again: an answer re-arms it, the next one in time is used.
    rig.engine.ports.torn_slots.clear();
    let stale = rig.sample(2, 22, rig.k, echo, &[1; 16]);
    rig.engine.ports.outputs.push_back(stale);
    let k = rig.k + 1;
    let answer = rig.sample(2, 22, k, echo, &[9; 16]);
    rig.engine.ports.answers.push_back(answer);
    let events = rig.cycle();
    assert!(!events.contains(&opfault_event(2)));
    assert_eq!(rig.last_sent(echo), (Mode::Operate, vec![9; 16], IOXS_GOOD));
}

#[test]
fn forced_outputs_go_out_valid_over_the_owner_and_without_one() {
    let mut rig = Rig::new(LatePolicy::HoldLastOutputs, Mode::Operate);
    let echo = rig.echo();
    rig.join(0, 11, false);
    rig.reach(Mode::Operate);
    let mut plan = Box::new(crate::cycle::ForcePlan::empty(rig.tables.submodules.len()));
    plan.push(
        procimg_control::Space::Output,
        echo as u32,
        2,
        &[0x5a, 0x5b],
    );
    assert!(rig.shared.send_force_plan(plan).is_ok());
    rig.cycle();
    let mut want = vec![0; 16];
    want[2..4].copy_from_slice(&[0x5a, 0x5b]);
    assert_eq!(
        rig.last_sent(echo),
        (Mode::Operate, want.clone(), IOXS_GOOD)
    );

    rig.claim(echo, 11);
    let owner = rig.sample(0, 11, 0, echo, &[0xaa; 16]);
    rig.engine.ports.outputs.push_back(owner);
    rig.cycle();
    let mut want = vec![0xaa; 16];
    want[2..4].copy_from_slice(&[0x5a, 0x5b]);
    assert_eq!(rig.last_sent(echo), (Mode::Operate, want, IOXS_GOOD));
    // The replaced plan went back to be freed off the cycle.
    assert_eq!(rig.shared.spent_force_plans.len(), 1);
}

#[test]
fn a_late_client_under_hold_last_outputs_keeps_its_last_outputs_valid() {
    let (mut rig, echo, _) = Rig::with_an_answering_client(LatePolicy::HoldLastOutputs, 2, 22, 7);

    // Silent from here on: one OPFAULT, and the outputs it wrote last stay on the wire, valid.
    let mut opfaults = 0;
    for _ in 0..4 {
        let events = rig.cycle();
        opfaults += events.iter().filter(|&&e| e == opfault_event(2)).count();
        assert_eq!(rig.last_sent(echo), (Mode::Operate, vec![7; 16], IOXS_GOOD));
    }
    assert_eq!(opfaults, 1);
}

#[test]
fn going_offline_passes_through_clear_and_forgets_the_outputs() {
    let mut rig = Rig::new(LatePolicy::HoldLastOutputs, Mode::Operate);
    let echo = rig.echo();
    rig.join(0, 11, false);
    rig.claim(echo, 11);
    rig.reach(Mode::Operate);
    let owner = rig.sample(0, 11, 0, echo, &[0xaa; 16]);
    rig.engine.ports.outputs.push_back(owner);
    rig.cycle();
    assert_eq!(
        rig.last_sent(echo),
        (Mode::Operate, vec![0xaa; 16], IOXS_GOOD)
    );

    rig.set_mode(Mode::Offline);
    let mut steps = Vec::new();
    for _ in 0..3 {
        let events = rig.cycle();
        steps.push((rig.engine.mode(), events.contains(&EVENT_MODE)));
    }
    assert_eq!(
        steps,
        [
            (Mode::Clear, true),
            (Mode::Offline, true),
            (Mode::Offline, false)
        ]
    );
    // IO-Base: in OFFLINE the outputs written are lost; back in OPERATE nothing old goes out.
    rig.set_mode(Mode::Operate);
    rig.reach(Mode::Operate);
    rig.cycle();
    let (mode, outputs, _) = rig.last_sent(echo);
    assert_eq!((mode, outputs), (Mode::Operate, vec![0; 16]));
}

/// Inputs arrive straight in the sample being published; a device that sent nothing keeps
/// its last inputs in every image, also across a cycle that could not loan a sample, and
/// every byte of every image is written (none keeps what the loaned sample held).
#[test]
fn inputs_that_did_not_arrive_are_carried_into_every_image() {
    let mut rig = Rig::new(LatePolicy::HoldLastOutputs, Mode::Operate);
    rig.reach(Mode::Operate);
    let with_inputs: Vec<usize> = (0..rig.tables.submodules.len())
        .filter(|&s| rig.tables.submodules[s].input_length > 0)
        .collect();
    let (a, b) = (with_inputs[0], *with_inputs.last().unwrap());
    assert_ne!(a, b, "the demo has several submodules with inputs");
    let tables = rig.tables.clone();
    let data = |s: usize, v: u8| vec![v; tables.submodules[s].input_length as usize];
    let inputs = |rig: &Rig, s: usize| {
        let (_, payload) = rig.engine.ports.published.last().unwrap();
        let e = rig.tables.submodules[s];
        payload[e.input_offset as usize..][..e.input_length as usize].to_vec()
    };
    // (what arrives for a, for b, whether a sample can be loaned) per cycle
    let script: [(Option<u8>, Option<u8>, bool); 6] = [
        (Some(1), Some(2), true),
        (Some(3), None, true),
        (None, None, true),
        (None, Some(4), false),
        (None, None, true),
        (Some(5), None, true),
    ];
    let (mut last_a, mut last_b) = (0, 0);
    for (a_new, b_new, loans) in script {
        let published = rig.engine.ports.published.len();
        {
            let mut arriving = rig.arriving.lock().unwrap();
            arriving.extend(a_new.map(|v| (a, data(a, v))));
            arriving.extend(b_new.map(|v| (b, data(b, v))));
        }
        rig.engine.ports.refuse_loans = !loans;
        rig.cycle();
        last_a = a_new.unwrap_or(last_a);
        last_b = b_new.unwrap_or(last_b);
        if !loans {
            assert_eq!(rig.engine.ports.published.len(), published);
            continue;
        }
        assert_eq!(inputs(&rig, a), data(a, last_a));
        assert_eq!(inputs(&rig, b), data(b, last_b));
        let (_, payload) = rig.engine.ports.published.last().unwrap();
        assert_eq!(
            rig.left_as_loaned(payload),
            None,
            "a byte of the published image was left as the loan held it"
        );
    }
    assert_eq!(
        rig.shared
            .counters
            .unpublished_images
            .load(Ordering::Relaxed),
        1
    );
}

/// Each sample comes back holding the image it was published with, so a cycle carries over
/// only what changed since: nothing once nothing changes, and new inputs of one submodule
/// once into each of the other samples, the next time each is loaned.
#[test]
fn a_cycle_carries_over_only_what_changed_since_its_sample_held_the_image() {
    let mut rig = Rig::new(LatePolicy::HoldLastOutputs, Mode::Operate);
    rig.reach(Mode::Operate);
    // Every sample of the link's three has been published (and started as garbage).
    for _ in 0..4 {
        rig.cycle();
    }
    let carried = |rig: &Rig| rig.engine.st.image.carried_bytes();
    let quiet = carried(&rig);
    for _ in 0..6 {
        rig.cycle();
    }
    assert_eq!(
        carried(&rig),
        quiet,
        "nothing changed: nothing carried over"
    );

    let a = (0..rig.tables.submodules.len())
        .find(|&s| rig.tables.submodules[s].input_length > 0)
        .unwrap();
    let len = rig.tables.submodules[a].input_length as usize;
    rig.arriving.lock().unwrap().push((a, vec![0x5A; len]));
    rig.cycle();
    let arrived = carried(&rig);
    for _ in 0..6 {
        rig.cycle();
        let (_, payload) = rig.engine.ports.published.last().unwrap();
        let at = rig.tables.submodules[a].input_offset as usize;
        assert_eq!(payload[at..at + len], vec![0x5A; len][..]);
    }
    assert_eq!(
        carried(&rig) - arrived,
        2 * len as u64,
        "the new inputs went into the two other samples, once each"
    );
}

/// Outputs are merged straight into the next image: what a client wrote once goes out and
/// shows as last sent in every image after, while the client sends nothing, across a cycle
/// that could not loan a sample, with a force over part of it and after the force is gone;
/// another client's new outputs land beside it; no published byte is left as the loan held it.
#[test]
fn outputs_written_once_are_sent_and_shown_as_last_sent_in_every_image() {
    let mut rig = Rig::new(LatePolicy::HoldLastOutputs, Mode::Operate);
    let echo = rig.echo();
    let other = (0..rig.tables.submodules.len())
        .find(|&s| s != echo && rig.tables.submodules[s].output_length > 0)
        .expect("the demo has other outputs");
    let other_len = rig.tables.submodules[other].output_length as usize;
    rig.join(0, 11, false);
    rig.join(1, 22, false);
    rig.claim(echo, 11);
    rig.claim(other, 22);
    rig.reach(Mode::Operate);
    let mirror = |rig: &Rig, s: usize| {
        let (_, payload) = rig.engine.ports.published.last().unwrap();
        let e = rig.tables.submodules[s];
        payload[e.output_mirror_offset as usize..][..e.output_length as usize].to_vec()
    };
    let pattern: Vec<u8> = (1..=16).collect();
    let sample = rig.sample(0, 11, 0, echo, &pattern);
    rig.engine.ports.outputs.push_back(sample);
    rig.cycle();
    assert_eq!(
        rig.last_sent(echo).1,
        pattern,
        "sent in the cycle it was merged"
    );
    // (loans, force byte 2 of echo to 0x77, another client writes `other`)
    let script: [(bool, bool, Option<u8>); 6] = [
        (true, false, None),
        (false, false, Some(5)),
        (true, false, None),
        (true, true, None),
        (true, false, Some(6)),
        (true, false, None),
    ];
    let mut expected_echo = pattern.clone();
    let mut expected_other = vec![0u8; other_len];
    for (loans, forced, write_other) in script {
        let published = rig.engine.ports.published.len();
        let mut plan = ForcePlan::empty(rig.tables.submodules.len());
        if forced {
            plan.push(Space::Output, echo as u32, 2, &[0x77]);
        }
        assert!(rig.shared.send_force_plan(Box::new(plan)).is_ok());
        if let Some(v) = write_other {
            let sample = rig.sample(1, 22, 0, other, &vec![v; other_len]);
            rig.engine.ports.outputs.push_back(sample);
        }
        rig.engine.ports.refuse_loans = !loans;
        // The image of this cycle shows what went out in the last one.
        let shown = (expected_echo.clone(), expected_other.clone());
        rig.cycle();
        if forced {
            expected_echo[2] = 0x77;
        }
        if let Some(v) = write_other {
            expected_other = vec![v; other_len];
        }
        assert_eq!(rig.last_sent(echo).1, expected_echo);
        assert_eq!(rig.last_sent(other).1, expected_other);
        if !loans {
            assert_eq!(rig.engine.ports.published.len(), published);
            continue;
        }
        assert_eq!((mirror(&rig, echo), mirror(&rig, other)), shown);
        let (_, payload) = rig.engine.ports.published.last().unwrap();
        assert_eq!(
            rig.left_as_loaned(payload),
            None,
            "a byte of the published image was left as the loan held it"
        );
    }
}
