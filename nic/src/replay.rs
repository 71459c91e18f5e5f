// SPDX-License-Identifier: MIT OR Apache-2.0
//! Capture replay: a [`Nic`] that plays the frames of a pcap or pcapng file as received
//! frames, so that the cycle thread's PROFINET IO can be driven from a recording (offline
//! analysis, tests without hardware).
//!
//! **What it returns** is what the AF_PACKET backend would have returned on the interface that
//! made the capture: PROFINET frames only (EtherType 0x8892, directly or behind one 802.1Q
//! tag, the same test as the kernel filter of the packet socket), and none sent from the
//! interface's own MAC address. A capture holds both directions; the frames of the own MAC
//! are what "we" sent and are skipped, as `PACKET_IGNORE_OUTGOING` skips them live.
//!
//! **The own MAC is given by the caller** ([`ReplayOptions::mac`]). A pcap file does not
//! record it, and guessing it from the traffic (say, the source of the first output frame)
//! fails for controllers with more than one address: the S7-1500 sends its alarm frames from
//! its interface MAC and everything else from its port's. Only frames from exactly the given
//! address are skipped.
//!
//! **Pacing.** A frame is due at its capture time relative to the first record of the file,
//! counted from the first [`receive`](Nic::receive) call, on `CLOCK_MONOTONIC`
//! ([`Pacing::Realtime`]) or on a clock the caller supplies ([`Pacing::Clock`], for
//! deterministic tests); `receive` hands it over at the first call at or after that time, so the
//! cycle sees a frame in the first cycle after it is due. [`Pacing::AsFastAsPolled`] ignores
//! the timestamps. With [`ReplayOptions::repeat`], the replay starts over after the last
//! record (the devices' CycleCounters start over too, so a consumer's staleness check may
//! drop frames for a while after the seam).
//!
//! **The file is read whole when the replay is opened**, parsed and filtered there: `receive`
//! only hands over a slice of one buffer and never reads the file or allocates, as the trait
//! requires. Frames longer than [`MAX_FRAME`] are skipped there, as the AF_PACKET backend
//! drops them ([`ReplayStats::too_long`]). Memory is about the size of the PROFINET frames in
//! the file.
//!
//! **Frames sent** are copied into a buffer allocated at construction (bounded by
//! [`ReplayOptions::sent_buffer`]; a frame that does not fit is dropped and counted) and can
//! be looked at with [`Replay::sent`]. With [`ReplayOptions::output`] they are written to a
//! pcap file (nanosecond timestamps, on the capture's time line so that Wireshark can merge
//! it with the input) by [`Replay::flush`] and when the replay is dropped, never by
//! [`send`](Nic::send): file I/O does not belong on the real-time path. Since the cycle
//! thread owns its interface and never flushes it, a replay inside procimgd writes its
//! output when the IO system is dropped, and the buffer bounds how much is written.

use crate::capture::CaptureError;
use crate::{MAX_FRAME, Nic, RecvError, SendError, check_frame_len};
use pcap_file::pcap::{PcapHeader, PcapPacket, PcapParser, PcapWriter};
use pcap_file::pcapng::PcapNgParser;
use pcap_file::pcapng::blocks::interface_description::{
    InterfaceDescriptionBlock, InterfaceDescriptionOption,
};
use pcap_file::pcapng::blocks::{ENHANCED_PACKET_BLOCK, PACKET_BLOCK, SIMPLE_PACKET_BLOCK};
use pcap_file::{DataLink, Endianness, PcapError, TsResolution};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::ethernet::{ETHERTYPE_PROFINET, TPID_VLAN};
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Default size of the buffer of sent frames: 1 MiB, about 10 000 typical RT frames.
pub const DEFAULT_SENT_BUFFER: usize = 1 << 20;

/// The sent-frame buffer holds at most one frame per this many bytes of its size, so its
/// index is allocated once too (60 bytes: the shortest Ethernet frame without FCS).
const SENT_BYTES_PER_FRAME: usize = 60;

/// Length of a pcap file header.
const PCAP_HEADER_LEN: usize = 24;

/// LINKTYPE_ETHERNET.
const LINKTYPE_ETHERNET: u32 = 1;

const NS_PER_SEC: u64 = 1_000_000_000;

/// Why a capture could not be opened for replay.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// The file does not exist.
    #[error("capture file {path} does not exist; check the path")]
    NotFound {
        /// The file.
        path: PathBuf,
    },
    /// The file could not be read.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error("cannot read the capture file {path}: {error}; check that it is readable")]
    Read {
        /// The file.
        path: PathBuf,
        /// The error.
        error: std::io::Error,
    },
    /// The file is neither pcap nor pcapng.
    #[error(
        "{path} is not a pcap or pcapng capture (it starts with {start}); record one with \
         `procimg capture`, or save it from Wireshark as pcap or pcapng"
    )]
    NotPcap {
        /// The file.
        path: PathBuf,
        /// Its first bytes, in hex.
        start: String,
    },
    /// The frames are not Ethernet frames.
    #[error(
        "{path} holds frames of link type {link_type}, not Ethernet: capture on the Ethernet \
         interface itself (not \"any\"), e.g. with `procimg capture --iface IF -o FILE`"
    )]
    LinkType {
        /// The file.
        path: PathBuf,
        /// The link type, by name where known.
        link_type: String,
    },
    /// The file ends inside a record.
    #[error(
        "{path} ends inside a record at byte {offset} (after {records} complete records): the \
         capture was cut off; stop captures with Ctrl-C so they finish the file, or re-save \
         the readable part with Wireshark"
    )]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Where the incomplete record starts.
        offset: usize,
        /// Complete records before it.
        records: u64,
    },
    /// A record is malformed.
    #[error(
        "{path} is damaged at byte {offset}: {detail}; re-save it with Wireshark or capture \
         again"
    )]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// Where the malformed record starts.
        offset: usize,
        /// What is wrong.
        detail: String,
    },
    /// The output file could not be created.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error(
        "cannot create the output capture file {path}: {error}; check the directory exists \
         and is writable"
    )]
    Output {
        /// The file.
        path: PathBuf,
        /// The error.
        error: std::io::Error,
    },
}

/// When a replayed frame is returned.
pub enum Pacing {
    /// At its capture time relative to the first `receive` call, on `CLOCK_MONOTONIC`.
    Realtime,
    /// Like [`Realtime`](Pacing::Realtime), on a caller's clock in nanoseconds (tests,
    /// simulated time). It must not allocate: `receive` and `send` call it.
    Clock(Box<dyn FnMut() -> u64 + Send>),
    /// As soon as asked: every `receive` hands over the next frame.
    AsFastAsPolled,
}

impl core::fmt::Debug for Pacing {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Pacing::Realtime => "Realtime",
            Pacing::Clock(_) => "Clock(..)",
            Pacing::AsFastAsPolled => "AsFastAsPolled",
        })
    }
}

/// How a capture is replayed.
#[derive(Debug)]
pub struct ReplayOptions {
    /// The replaying interface's own MAC address: frames from it are what it sent and are
    /// not returned (see the module documentation).
    pub mac: MacAddress,
    /// When frames are returned (default [`Pacing::Realtime`]).
    pub pacing: Pacing,
    /// Start over this long after the last record's time (default: play once).
    pub repeat: Option<Duration>,
    /// Bytes of sent frames kept (default [`DEFAULT_SENT_BUFFER`]), allocated once.
    pub sent_buffer: usize,
    /// A pcap file the sent frames are written to (default none).
    pub output: Option<PathBuf>,
}

impl ReplayOptions {
    /// Defaults, with `mac` as the own address.
    pub fn new(mac: MacAddress) -> ReplayOptions {
        ReplayOptions {
            mac,
            pacing: Pacing::Realtime,
            repeat: None,
            sent_buffer: DEFAULT_SENT_BUFFER,
            output: None,
        }
    }
}

/// What was in the file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReplayStats {
    /// Packet records.
    pub records: u64,
    /// PROFINET frames that will be returned.
    pub profinet: u64,
    /// PROFINET frames from the own MAC, skipped.
    pub own: u64,
    /// Frames of other protocols, skipped.
    pub other: u64,
    /// PROFINET frames captured incompletely (snap length), skipped: a live interface never
    /// delivers part of a frame.
    pub cut: u64,
    /// PROFINET frames longer than [`MAX_FRAME`], skipped: the AF_PACKET backend drops them
    /// too (and reports them).
    pub too_long: u64,
}

/// A frame to return: where it is in the data, when it is due.
#[derive(Clone, Copy, Debug)]
struct Frame {
    /// Nanoseconds after the file's first record.
    due_ns: u64,
    start: usize,
    len: usize,
}

/// A frame sent.
#[derive(Clone, Copy, Debug)]
struct Sent {
    /// Capture time (ns since the Unix epoch).
    at_ns: u64,
    start: usize,
    len: usize,
}

/// The frames sent, in buffers allocated once.
struct SentBuffer {
    bytes: Vec<u8>,
    frames: Vec<Sent>,
    byte_limit: usize,
    frame_limit: usize,
    dropped: u64,
}

impl SentBuffer {
    fn new(byte_limit: usize) -> SentBuffer {
        let frame_limit = byte_limit.div_ceil(SENT_BYTES_PER_FRAME);
        SentBuffer {
            bytes: Vec::with_capacity(byte_limit),
            frames: Vec::with_capacity(frame_limit),
            byte_limit,
            frame_limit,
            dropped: 0,
        }
    }

    fn push(&mut self, at_ns: u64, frame: &[u8]) {
        let start = self.bytes.len();
        // Both checks keep the pushes within the capacity reserved at construction.
        if self.frames.len() >= self.frame_limit || frame.len() > self.byte_limit - start {
            self.dropped += 1;
            return;
        }
        self.bytes.extend_from_slice(frame);
        self.frames.push(Sent {
            at_ns,
            start,
            len: frame.len(),
        });
    }

    fn clear(&mut self) {
        self.bytes.clear();
        self.frames.clear();
    }
}

struct Output {
    path: PathBuf,
    file: File,
}

/// A capture replayed as a network interface.
pub struct Replay {
    origin: PathBuf,
    /// `origin`, for the errors of `send`, which then allocate nothing.
    name: Arc<str>,
    mac: MacAddress,
    pacing: Pacing,
    /// The frames to return, back to back.
    data: Vec<u8>,
    frames: Vec<Frame>,
    /// Capture time of the file's first record (ns since the Unix epoch).
    first_ns: u64,
    /// Time from one pass's start to the next, when repeating.
    period_ns: Option<u64>,
    stats: ReplayStats,
    /// Next frame to return, and how many passes are complete.
    next: usize,
    pass: u64,
    /// The time base of [`Pacing::Realtime`] (`Instant` is `CLOCK_MONOTONIC` on Linux).
    opened: Instant,
    /// The clock at the first `receive`.
    start_ns: Option<u64>,
    /// Replay time of the last frame returned (the clock of [`Pacing::AsFastAsPolled`]).
    position_ns: u64,
    sent: SentBuffer,
    output: Option<Output>,
}

impl Replay {
    /// Opens the pcap or pcapng file at `path`.
    pub fn open(path: &Path, options: ReplayOptions) -> Result<Replay, ReplayError> {
        let bytes = std::fs::read(path).map_err(|error| {
            if error.kind() == std::io::ErrorKind::NotFound {
                ReplayError::NotFound {
                    path: path.to_path_buf(),
                }
            } else {
                ReplayError::Read {
                    path: path.to_path_buf(),
                    error,
                }
            }
        })?;
        Replay::from_bytes(path, &bytes, options)
    }

    /// Replays the capture `bytes`; `origin` names it in messages.
    pub fn from_bytes(
        origin: &Path,
        bytes: &[u8],
        options: ReplayOptions,
    ) -> Result<Replay, ReplayError> {
        let loaded = load(origin, bytes, options.mac)?;
        let output = match options.output {
            Some(path) => Some(create_output(path)?),
            None => None,
        };
        let span = loaded.last_ns.saturating_sub(loaded.first_ns);
        Ok(Replay {
            origin: origin.to_path_buf(),
            name: origin.display().to_string().into(),
            mac: options.mac,
            pacing: options.pacing,
            data: loaded.data,
            frames: loaded.frames,
            first_ns: loaded.first_ns,
            period_ns: options
                .repeat
                .map(|gap| span.saturating_add(duration_ns(gap))),
            stats: loaded.stats,
            next: 0,
            pass: 0,
            opened: Instant::now(),
            start_ns: None,
            position_ns: 0,
            sent: SentBuffer::new(options.sent_buffer),
            output,
        })
    }

    /// The file replayed.
    pub fn origin(&self) -> &Path {
        &self.origin
    }

    /// What the file held.
    pub fn stats(&self) -> ReplayStats {
        self.stats
    }

    /// Every frame has been returned and the replay does not repeat.
    pub fn is_finished(&self) -> bool {
        self.period_ns.is_none() && self.next >= self.frames.len()
    }

    /// The frames sent since the last [`flush`](Self::flush), with their time on the
    /// capture's time line (since the Unix epoch).
    pub fn sent(&self) -> impl Iterator<Item = (Duration, &[u8])> + '_ {
        self.sent.frames.iter().map(|s| {
            (
                Duration::from_nanos(s.at_ns),
                self.sent.bytes.get(s.start..s.start + s.len).unwrap_or(&[]),
            )
        })
    }

    /// Sent frames dropped because the buffer was full.
    pub fn sent_dropped(&self) -> u64 {
        self.sent.dropped
    }

    /// Writes the frames sent so far to the output file, if there is one, and empties the
    /// buffer. Not for the real-time path: it writes to the file.
    pub fn flush(&mut self) -> Result<(), CaptureError> {
        if let Some(out) = &mut self.output
            && !self.sent.frames.is_empty()
        {
            let err = |detail: String| CaptureError::Write {
                path: out.path.clone(),
                detail,
            };
            // pcap-file 2 writes the file header with every writer and cannot flush through
            // it: the records go through a writer on a buffer, and the file gets what follows
            // the header (which was written once, when the file was created).
            let mut w = PcapWriter::with_header(Vec::new(), output_header())
                .map_err(|e| err(e.to_string()))?;
            for s in &self.sent.frames {
                let data = self.sent.bytes.get(s.start..s.start + s.len).unwrap_or(&[]);
                let packet =
                    PcapPacket::new(Duration::from_nanos(s.at_ns), data.len() as u32, data);
                w.write_packet(&packet).map_err(|e| err(e.to_string()))?;
            }
            let records = w.into_writer();
            out.file
                .write_all(records.get(PCAP_HEADER_LEN..).unwrap_or(&[]))
                .and_then(|()| out.file.flush())
                .map_err(|e| err(e.to_string()))?;
        }
        self.sent.clear();
        Ok(())
    }

    /// The pacing clock, or `None` without one.
    fn clock(&mut self) -> Option<u64> {
        match &mut self.pacing {
            Pacing::Realtime => Some(duration_ns(self.opened.elapsed())),
            Pacing::Clock(f) => Some(f()),
            Pacing::AsFastAsPolled => None,
        }
    }

    /// Time since the replay started (the first `receive`), on the replay's clock.
    fn elapsed(&mut self) -> u64 {
        match (self.clock(), self.start_ns) {
            (Some(now), Some(start)) => now.saturating_sub(start),
            (Some(_), None) => 0,
            (None, _) => self.position_ns,
        }
    }
}

impl Nic for Replay {
    fn mac(&self) -> MacAddress {
        self.mac
    }

    fn send(&mut self, frame: &[u8]) -> Result<(), SendError> {
        check_frame_len(&self.name, frame)?;
        let at = self.first_ns.saturating_add(self.elapsed());
        self.sent.push(at, frame);
        Ok(())
    }

    fn receive(&mut self, f: &mut dyn FnMut(&[u8])) -> Result<bool, RecvError> {
        let now = self.clock();
        let start = *self.start_ns.get_or_insert(now.unwrap_or(0));
        if self.next >= self.frames.len() {
            match self.period_ns {
                Some(_) if !self.frames.is_empty() => {
                    self.next = 0;
                    self.pass += 1;
                }
                _ => return Ok(false),
            }
        }
        let Some(&frame) = self.frames.get(self.next) else {
            return Ok(false);
        };
        let due = self
            .pass
            .saturating_mul(self.period_ns.unwrap_or(0))
            .saturating_add(frame.due_ns);
        if let Some(now) = now
            && now.saturating_sub(start) < due
        {
            return Ok(false);
        }
        let bytes = self
            .data
            .get(frame.start..frame.start + frame.len)
            .unwrap_or(&[]);
        self.next += 1;
        self.position_ns = due;
        f(bytes);
        Ok(true)
    }
}

impl Drop for Replay {
    fn drop(&mut self) {
        if let Err(e) = self.flush() {
            tracing::warn!("{e}");
        }
    }
}

/// EtherType 0x8892, directly or behind one 802.1Q tag: the test of the AF_PACKET backend's
/// kernel filter (`packet_socket.rs`), which also drops frames too short to hold the type.
pub fn is_profinet(frame: &[u8]) -> bool {
    let be16 = |at: usize| {
        frame
            .get(at..at + 2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
    };
    match be16(12) {
        Some(ETHERTYPE_PROFINET) => true,
        Some(TPID_VLAN) => be16(16) == Some(ETHERTYPE_PROFINET),
        _ => false,
    }
}

fn duration_ns(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

fn output_header() -> PcapHeader {
    PcapHeader {
        ts_resolution: TsResolution::NanoSecond,
        endianness: Endianness::native(),
        ..PcapHeader::default()
    }
}

fn create_output(path: PathBuf) -> Result<Output, ReplayError> {
    let file = File::create(&path).map_err(|error| ReplayError::Output {
        path: path.clone(),
        error,
    })?;
    let file = PcapWriter::with_header(file, output_header())
        .map_err(|e| ReplayError::Output {
            path: path.clone(),
            error: match e {
                PcapError::IoError(io) => io,
                other => std::io::Error::other(other.to_string()),
            },
        })?
        .into_writer();
    Ok(Output { path, file })
}

/// The file, parsed and filtered.
struct Loaded {
    data: Vec<u8>,
    frames: Vec<Frame>,
    first_ns: u64,
    last_ns: u64,
    stats: ReplayStats,
}

/// Takes the records of a file in order and keeps the ones to return.
struct Collector {
    mac: MacAddress,
    loaded: Loaded,
    seen_first: bool,
}

impl Collector {
    fn record(&mut self, ts_ns: u64, frame: &[u8], orig_len: u32) {
        let l = &mut self.loaded;
        l.stats.records += 1;
        if !self.seen_first {
            self.seen_first = true;
            l.first_ns = ts_ns;
        }
        l.last_ns = l.last_ns.max(ts_ns);
        if !is_profinet(frame) {
            l.stats.other += 1;
        } else if frame.get(6..12) == Some(&self.mac.0[..]) {
            l.stats.own += 1;
        } else if (frame.len() as u64) < u64::from(orig_len) {
            l.stats.cut += 1;
        } else if frame.len() > MAX_FRAME {
            l.stats.too_long += 1;
        } else {
            l.stats.profinet += 1;
            // Out-of-order timestamps (merged captures) make a frame due at once.
            l.frames.push(Frame {
                due_ns: ts_ns.saturating_sub(l.first_ns),
                start: l.data.len(),
                len: frame.len(),
            });
            l.data.extend_from_slice(frame);
        }
    }
}

const PCAP_MAGICS: [[u8; 4]; 4] = [
    [0xa1, 0xb2, 0xc3, 0xd4],
    [0xd4, 0xc3, 0xb2, 0xa1],
    [0xa1, 0xb2, 0x3c, 0x4d],
    [0x4d, 0x3c, 0xb2, 0xa1],
];
const PCAPNG_MAGIC: [u8; 4] = [0x0a, 0x0d, 0x0d, 0x0a];

fn load(origin: &Path, bytes: &[u8], mac: MacAddress) -> Result<Loaded, ReplayError> {
    let mut c = Collector {
        mac,
        loaded: Loaded {
            data: Vec::new(),
            frames: Vec::new(),
            first_ns: 0,
            last_ns: 0,
            stats: ReplayStats::default(),
        },
        seen_first: false,
    };
    let magic: Option<[u8; 4]> = bytes.get(..4).and_then(|m| m.try_into().ok());
    match magic {
        Some(m) if PCAP_MAGICS.contains(&m) => load_pcap(origin, bytes, &mut c)?,
        Some(PCAPNG_MAGIC) => load_pcapng(origin, bytes, &mut c)?,
        _ => {
            let start = if bytes.is_empty() {
                "nothing: the file is empty".to_string()
            } else {
                bytes
                    .iter()
                    .take(4)
                    .map(|b| format!("{b:02x}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            return Err(ReplayError::NotPcap {
                path: origin.to_path_buf(),
                start,
            });
        }
    }
    Ok(c.loaded)
}

/// The error for a record at `rest` (the unparsed tail of `bytes`) that pcap-file refused.
fn record_error(
    origin: &Path,
    bytes: &[u8],
    rest: &[u8],
    records: u64,
    e: PcapError,
) -> ReplayError {
    let offset = bytes.len() - rest.len();
    match e {
        PcapError::IncompleteBuffer => ReplayError::Truncated {
            path: origin.to_path_buf(),
            offset,
            records,
        },
        other => ReplayError::Corrupt {
            path: origin.to_path_buf(),
            offset,
            detail: other.to_string(),
        },
    }
}

fn link_name(link: DataLink) -> String {
    format!("{link:?} ({})", u32::from(link))
}

fn load_pcap(origin: &Path, bytes: &[u8], c: &mut Collector) -> Result<(), ReplayError> {
    let (mut rest, parser) =
        PcapParser::new(bytes).map_err(|e| record_error(origin, bytes, bytes, 0, e))?;
    let header = parser.header();
    if u32::from(header.datalink) != LINKTYPE_ETHERNET {
        return Err(ReplayError::LinkType {
            path: origin.to_path_buf(),
            link_type: link_name(header.datalink),
        });
    }
    let (frac_limit, ns_per_frac) = match header.ts_resolution {
        TsResolution::MicroSecond => (1_000_000, 1_000),
        TsResolution::NanoSecond => (1_000_000_000, 1),
    };
    while !rest.is_empty() {
        let records = c.loaded.stats.records;
        // Raw records: the checked ones of pcap-file reject records of snap-length-limited
        // captures (original length over the snap length), which are valid.
        let (rem, p) = parser
            .next_raw_packet(rest)
            .map_err(|e| record_error(origin, bytes, rest, records, e))?;
        if p.ts_frac >= frac_limit {
            return Err(ReplayError::Corrupt {
                path: origin.to_path_buf(),
                offset: bytes.len() - rest.len(),
                detail: format!("the timestamp's fraction {} is out of range", p.ts_frac),
            });
        }
        // At most (2^32 - 1) · 10^9 + 10^9: fits in u64.
        let ts = u64::from(p.ts_sec) * NS_PER_SEC + u64::from(p.ts_frac) * ns_per_frac;
        c.record(ts, &p.data, p.orig_len);
        rest = rem;
    }
    Ok(())
}

/// Reads a u16/u32 at `at` of a pcapng block body in the section's byte order.
fn read_u32(body: &[u8], at: usize, order: Endianness) -> Option<u32> {
    let b: [u8; 4] = body.get(at..at.checked_add(4)?)?.try_into().ok()?;
    Some(match order {
        Endianness::Big => u32::from_be_bytes(b),
        Endianness::Little => u32::from_le_bytes(b),
    })
}

fn read_u16(body: &[u8], at: usize, order: Endianness) -> Option<u16> {
    let b: [u8; 2] = body.get(at..at.checked_add(2)?)?.try_into().ok()?;
    Some(match order {
        Endianness::Big => u16::from_be_bytes(b),
        Endianness::Little => u16::from_le_bytes(b),
    })
}

/// A packet of a pcapng block: interface, raw timestamp (none in a simple packet block),
/// data, original length.
struct NgPacket<'a> {
    interface: u32,
    timestamp: Option<u64>,
    data: &'a [u8],
    orig_len: u32,
}

/// Parses an enhanced, obsolete or simple packet block body; `None` if it is too short for
/// what it declares. pcap-file 2 is not used for these: it ignores the interface's timestamp
/// resolution, reads the obsolete block's timestamp as one 64-bit number, and keeps a simple
/// block's padding as data.
fn ng_packet(
    kind: u32,
    body: &[u8],
    order: Endianness,
    snaplen_0: Option<u32>,
) -> Option<NgPacket<'_>> {
    let u32_at = |at| read_u32(body, at, order);
    if kind == SIMPLE_PACKET_BLOCK {
        let orig_len = u32_at(0)?;
        // The captured length is the original one, limited by the snap length of
        // interface 0 (0: none); the rest is padding.
        let captured = match snaplen_0 {
            Some(s) if s > 0 => orig_len.min(s),
            _ => orig_len,
        } as usize;
        let data = body.get(4..)?.get(..captured)?;
        return Some(NgPacket {
            interface: 0,
            timestamp: None,
            data,
            orig_len,
        });
    }
    let interface = match kind {
        ENHANCED_PACKET_BLOCK => u32_at(0)?,
        PACKET_BLOCK => u32::from(read_u16(body, 0, order)?),
        _ => return None,
    };
    let timestamp = (u64::from(u32_at(4)?) << 32) | u64::from(u32_at(8)?);
    let captured = u32_at(12)? as usize;
    let orig_len = u32_at(16)?;
    let data = body.get(20..)?.get(..captured)?;
    Some(NgPacket {
        interface,
        timestamp: Some(timestamp),
        data,
        orig_len,
    })
}

/// Converts a pcapng timestamp in units of `if_tsresol` (bit 7 clear: 10^-n s, set: 2^-n s;
/// default 10^-6) to ns, saturating.
pub(crate) fn ng_timestamp_ns(raw: u64, tsresol: u8) -> u64 {
    let n = u32::from(tsresol & 0x7f);
    let ns: u128 = if tsresol & 0x80 != 0 {
        (u128::from(raw) * u128::from(NS_PER_SEC)) >> n
    } else if n <= 9 {
        u128::from(raw) * 10u128.pow(9 - n)
    } else {
        // 10^(n-9) overflows u128 from n = 48 on; the result is 0 long before.
        10u128.checked_pow(n - 9).map_or(0, |d| u128::from(raw) / d)
    };
    u64::try_from(ns).unwrap_or(u64::MAX)
}

/// The timestamp resolution and offset (seconds) of an interface.
fn ng_time_base(iface: &InterfaceDescriptionBlock<'_>) -> (u8, u64) {
    let mut tsresol = 6;
    let mut offset_s = 0;
    for o in &iface.options {
        match o {
            InterfaceDescriptionOption::IfTsResol(r) => tsresol = *r,
            InterfaceDescriptionOption::IfTsOffset(s) => offset_s = *s,
            _ => {}
        }
    }
    (tsresol, offset_s)
}

fn load_pcapng(origin: &Path, bytes: &[u8], c: &mut Collector) -> Result<(), ReplayError> {
    let (mut rest, mut parser) =
        PcapNgParser::new(bytes).map_err(|e| record_error(origin, bytes, bytes, 0, e))?;
    // A simple packet block has no timestamp: it gets the one before it.
    let mut last_ts = 0u64;
    while !rest.is_empty() {
        let records = c.loaded.stats.records;
        let offset = bytes.len() - rest.len();
        // Raw blocks: pcap-file checks the framing and parses section and interface blocks;
        // other blocks it would parse whole can panic on malformed input (name resolution
        // records), and only packets matter here.
        let (rem, raw) = parser
            .next_raw_block(rest)
            .map_err(|e| record_error(origin, bytes, rest, records, e))?;
        rest = rem;
        if !matches!(
            raw.type_,
            ENHANCED_PACKET_BLOCK | PACKET_BLOCK | SIMPLE_PACKET_BLOCK
        ) {
            continue;
        }
        let corrupt = |detail: String| ReplayError::Corrupt {
            path: origin.to_path_buf(),
            offset,
            detail,
        };
        let order = parser.section().endianness;
        let snaplen_0 = parser.interfaces().first().map(|i| i.snaplen);
        let Some(p) = ng_packet(raw.type_, &raw.body, order, snaplen_0) else {
            return Err(corrupt(
                "a packet block is shorter than the packet it declares".into(),
            ));
        };
        let Some(iface) = parser.interfaces().get(p.interface as usize) else {
            return Err(corrupt(format!(
                "a packet of interface {}, which no interface block describes",
                p.interface
            )));
        };
        if u32::from(iface.linktype) != LINKTYPE_ETHERNET {
            return Err(ReplayError::LinkType {
                path: origin.to_path_buf(),
                link_type: link_name(iface.linktype),
            });
        }
        if let Some(raw_ts) = p.timestamp {
            let (tsresol, offset_s) = ng_time_base(iface);
            last_ts = ng_timestamp_ns(raw_ts, tsresol)
                .saturating_add(offset_s.saturating_mul(NS_PER_SEC));
        }
        c.record(last_ts, p.data, p.orig_len);
    }
    Ok(())
}

#[cfg(test)]
#[path = "replay_tests.rs"]
mod tests;
