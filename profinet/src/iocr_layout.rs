// SPDX-License-Identifier: MIT OR Apache-2.0
//! Where each submodule's IO data, IOPS and IOCS sit in the C_SDU of the two IO CRs.
//!
//! The IO controller chooses every offset and tells the device in the IOCRBlockReq. The
//! layout here is the one an S7-1500 chooses, verified against its connect to the p-net
//! sample device: submodules in ascending (API, slot, subslot) order, each taking in turn
//!
//! - in the **input CR** (device → controller): its input data and IOPS if it has inputs or
//!   no IO data at all (a data-less submodule is an input of length 0), then an IOCS if it
//!   has outputs;
//! - in the **output CR** (controller → device): an IOCS if it has inputs or no IO data, then
//!   its output data and IOPS if it has outputs;
//!
//! with the C_SDU padded to at least 40 bytes.

use crate::wire::connect::{ConnectRequest, ExpectedSubmoduleBlockReq};
use crate::wire::connect::{
    FRAME_SEND_OFFSET_BEST_EFFORT, IocrApi, IocrBlockReq, IocrEntry, LT_PROFINET,
    TAG_HEADER_PRIO_6, iocr_properties,
};
use crate::wire::rt::{MAX_DATA_LENGTH, MIN_DATA_LENGTH};
use crate::wire::{EmitError, MacAddress};

/// One submodule as the layout needs it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubmoduleIo {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// Input bytes.
    pub input_length: u16,
    /// Output bytes.
    pub output_length: u16,
}

impl SubmoduleIo {
    /// Whether the submodule counts as an input one (inputs, or no IO data at all).
    pub const fn is_input(&self) -> bool {
        self.input_length > 0 || self.output_length == 0
    }

    /// Whether it has outputs.
    pub const fn is_output(&self) -> bool {
        self.output_length > 0
    }
}

/// An IO data object in a C_SDU: the data of one submodule followed by its IOPS.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DataObject {
    /// Index of the submodule in the list given to [`IocrLayout::new`].
    pub submodule: usize,
    /// Offset of the data in the C_SDU.
    pub data_offset: u16,
    /// Data bytes.
    pub length: u16,
    /// Offset of the IOPS (right after the data).
    pub iops_offset: u16,
}

/// A consumer status in a C_SDU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Iocs {
    /// Index of the submodule in the list given to [`IocrLayout::new`].
    pub submodule: usize,
    /// Offset of the IOCS.
    pub offset: u16,
}

/// The layout of one IO CR's C_SDU.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct CrLayout {
    /// C_SDU bytes (at least 40).
    pub data_length: u16,
    /// Data objects, in frame order.
    pub objects: Vec<DataObject>,
    /// Consumer statuses, in frame order.
    pub iocs: Vec<Iocs>,
}

/// The layouts of an AR's input and output CR.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IocrLayout {
    /// Device → controller.
    pub input: CrLayout,
    /// Controller → device.
    pub output: CrLayout,
}

/// The IO data does not fit in one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TooLarge {
    /// Which CR: true for the input CR.
    pub input: bool,
    /// Bytes it would need.
    pub bytes: usize,
}

impl core::fmt::Display for TooLarge {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "the {} CR would need {} bytes of IO data and status, over the {MAX_DATA_LENGTH} \
             a frame carries; split the device's IO over fewer submodules or bytes",
            if self.input { "input" } else { "output" },
            self.bytes
        )
    }
}

impl core::error::Error for TooLarge {}

impl IocrLayout {
    /// Lays out the submodules of one device (in any order; the layout sorts them).
    pub fn new(submodules: &[SubmoduleIo]) -> Result<IocrLayout, TooLarge> {
        let mut order: Vec<usize> = (0..submodules.len()).collect();
        order.sort_by_key(|&i| (submodules[i].api, submodules[i].slot, submodules[i].subslot));
        let (mut input, mut output) = (CrLayout::default(), CrLayout::default());
        let (mut at_in, mut at_out) = (0usize, 0usize);
        for &i in &order {
            let s = &submodules[i];
            let (in_len, out_len) = (usize::from(s.input_length), usize::from(s.output_length));
            // Where this submodule's entries go: (data, IOCS) in the input CR and (IOCS,
            // data) in the output CR, placed only once both CRs are known to fit.
            let (mut in_data, mut out_iocs, mut in_iocs, mut out_data) = (None, None, None, None);
            if s.is_input() {
                in_data = Some(at_in);
                at_in += in_len + 1;
                out_iocs = Some(at_out);
                at_out += 1;
            }
            if s.is_output() {
                in_iocs = Some(at_in);
                at_in += 1;
                out_data = Some(at_out);
                at_out += out_len + 1;
            }
            for (input, bytes) in [(true, at_in), (false, at_out)] {
                if bytes > MAX_DATA_LENGTH {
                    return Err(TooLarge { input, bytes });
                }
            }
            // Every offset is below the checked end of its CR, so it fits the u16 fields.
            let in_cr = |at: usize| offset(at, true, at_in);
            let out_cr = |at: usize| offset(at, false, at_out);
            if let Some(at) = in_data {
                input.objects.push(DataObject {
                    submodule: i,
                    data_offset: in_cr(at)?,
                    length: s.input_length,
                    iops_offset: in_cr(at + in_len)?,
                });
            }
            if let Some(at) = out_iocs {
                output.iocs.push(Iocs {
                    submodule: i,
                    offset: out_cr(at)?,
                });
            }
            if let Some(at) = in_iocs {
                input.iocs.push(Iocs {
                    submodule: i,
                    offset: in_cr(at)?,
                });
            }
            if let Some(at) = out_data {
                output.objects.push(DataObject {
                    submodule: i,
                    data_offset: out_cr(at)?,
                    length: s.output_length,
                    iops_offset: out_cr(at + out_len)?,
                });
            }
        }
        input.data_length = offset(at_in.max(MIN_DATA_LENGTH), true, at_in)?;
        output.data_length = offset(at_out.max(MIN_DATA_LENGTH), false, at_out)?;
        Ok(IocrLayout { input, output })
    }
}

/// An offset or length in a CR of `bytes` bytes as its u16 wire field; [`TooLarge`] if it
/// does not fit (never after the [`MAX_DATA_LENGTH`] check).
fn offset(at: usize, input: bool, bytes: usize) -> Result<u16, TooLarge> {
    u16::try_from(at).map_err(|_| TooLarge { input, bytes })
}

/// The IOCRBlockReq of a CR layout.
impl IocrBlockReq {
    /// An IO CR carrying `layout` (one CR of an [`IocrLayout`]):
    /// DataLength from the layout, one IODataObject per data object (at its data offset) and
    /// one IOCS per consumer status, grouped by API in frame order. `submodules` is the list
    /// the layout was computed from (its indices are the layout's `submodule` fields); an index
    /// outside it gives [`EmitError::Inconsistent`]. It lives beside the layout it is built from, so that the codec does not
    /// depend on the layout.
    ///
    /// The other fields are what the S7-1515 sends: LT 0x8892, RT class 2, SendClockFactor 32,
    /// ReductionRatio 32 (32 ms), phase 1, sequence 0, best-effort FrameSendOffset,
    /// watchdog and data hold factor 3, tag header 0xC000, no multicast address. Change the
    /// public fields for other timing.
    pub fn from_layout(
        iocr_type: u16,
        iocr_reference: u16,
        frame_id: u16,
        layout: &CrLayout,
        submodules: &[SubmoduleIo],
    ) -> Result<IocrBlockReq, EmitError> {
        fn api_entry(apis: &mut Vec<IocrApi>, api: u32) -> &mut IocrApi {
            let i = match apis.iter().position(|a| a.api == api) {
                Some(i) => i,
                None => {
                    apis.push(IocrApi {
                        api,
                        ..IocrApi::default()
                    });
                    apis.len() - 1
                }
            };
            &mut apis[i]
        }
        const OUTSIDE: EmitError =
            EmitError::Inconsistent("the layout names a submodule outside the list");
        let mut apis = Vec::new();
        for o in &layout.objects {
            let s = submodules.get(o.submodule).ok_or(OUTSIDE)?;
            api_entry(&mut apis, s.api).data_objects.push(IocrEntry {
                slot: s.slot,
                subslot: s.subslot,
                frame_offset: o.data_offset,
            });
        }
        for c in &layout.iocs {
            let s = submodules.get(c.submodule).ok_or(OUTSIDE)?;
            api_entry(&mut apis, s.api).iocs.push(IocrEntry {
                slot: s.slot,
                subslot: s.subslot,
                frame_offset: c.offset,
            });
        }
        Ok(IocrBlockReq {
            iocr_type,
            iocr_reference,
            lt: LT_PROFINET,
            iocr_properties: iocr_properties::RT_CLASS_2,
            data_length: layout.data_length,
            frame_id,
            send_clock_factor: 32,
            reduction_ratio: 32,
            phase: 1,
            sequence: 0,
            frame_send_offset: FRAME_SEND_OFFSET_BEST_EFFORT,
            watchdog_factor: 3,
            data_hold_factor: 3,
            tag_header: TAG_HEADER_PRIO_6,
            multicast_mac: MacAddress::default(),
            apis,
        })
    }
}

/// What the layout needs of an ExpectedSubmoduleBlockReq.
impl ExpectedSubmoduleBlockReq {
    /// Every submodule as the IOCR layout needs it, in block order.
    pub fn submodules(&self) -> impl Iterator<Item = SubmoduleIo> + '_ {
        self.modules.iter().flat_map(|m| {
            m.submodules.iter().map(|s| SubmoduleIo {
                api: m.api,
                slot: m.slot,
                subslot: s.subslot,
                input_length: s.input_length(),
                output_length: s.output_length(),
            })
        })
    }
}

/// What the layout needs of a Connect request.
impl ConnectRequest {
    /// Every expected submodule, in block order: the input of [`IocrLayout::new`].
    pub fn submodules(&self) -> impl Iterator<Item = SubmoduleIo> + '_ {
        self.expected
            .iter()
            .flat_map(ExpectedSubmoduleBlockReq::submodules)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(slot: u16, subslot: u16, i: u16, o: u16) -> SubmoduleIo {
        SubmoduleIo {
            api: 0,
            slot,
            subslot,
            input_length: i,
            output_length: o,
        }
    }

    /// The layout the S7-1515 chose for the p-net sample device (DAP with interface and port,
    /// DI8, DO8, DIO8, 8-byte echo), as its connect request and cyclic frames show.
    #[test]
    fn matches_the_s7_layout_for_the_pnet_sample() {
        let subs = [
            sub(4, 1, 8, 8), // echo, listed out of order on purpose
            sub(0, 1, 0, 0), // DAP
            sub(0, 0x8000, 0, 0),
            sub(0, 0x8001, 0, 0),
            sub(1, 1, 1, 0), // DI8
            sub(2, 1, 0, 1), // DO8
            sub(3, 1, 1, 1), // DIO8
        ];
        let l = IocrLayout::new(&subs).unwrap();
        let obj = |cr: &CrLayout, s: usize| {
            let o = cr.objects.iter().find(|o| o.submodule == s).unwrap();
            (o.data_offset, o.iops_offset)
        };
        let iocs =
            |cr: &CrLayout, s: usize| cr.iocs.iter().find(|c| c.submodule == s).unwrap().offset;
        // Input CR 0x8000.
        assert_eq!(obj(&l.input, 1), (0, 0));
        assert_eq!(obj(&l.input, 2), (1, 1));
        assert_eq!(obj(&l.input, 3), (2, 2));
        assert_eq!(obj(&l.input, 4), (3, 4));
        assert_eq!(iocs(&l.input, 5), 5);
        assert_eq!(obj(&l.input, 6), (6, 7));
        assert_eq!(iocs(&l.input, 6), 8);
        assert_eq!(obj(&l.input, 0), (9, 17));
        assert_eq!(iocs(&l.input, 0), 18);
        assert_eq!(l.input.data_length, 40);
        // Output CR 0x8001.
        assert_eq!(iocs(&l.output, 1), 0);
        assert_eq!(iocs(&l.output, 2), 1);
        assert_eq!(iocs(&l.output, 3), 2);
        assert_eq!(iocs(&l.output, 4), 3);
        assert_eq!(obj(&l.output, 5), (4, 5));
        assert_eq!(iocs(&l.output, 6), 6);
        assert_eq!(obj(&l.output, 6), (7, 8));
        assert_eq!(iocs(&l.output, 0), 9);
        assert_eq!(obj(&l.output, 0), (10, 18));
        assert_eq!(l.output.data_length, 40);
    }

    #[test]
    fn io_beyond_one_frame_is_refused() {
        let subs: Vec<SubmoduleIo> = (1..=3).map(|s| sub(s, 1, 600, 0)).collect();
        assert_eq!(
            IocrLayout::new(&subs),
            Err(TooLarge {
                input: true,
                bytes: 1803
            })
        );
    }

    #[test]
    fn offsets_past_u16_are_refused_not_truncated() {
        // One submodule whose IOPS would sit beyond 65535: refused as a whole, no entry of it
        // with a wrapped offset.
        let subs = [sub(1, 1, 1000, 0), sub(2, 1, u16::MAX, u16::MAX)];
        assert_eq!(
            IocrLayout::new(&subs),
            Err(TooLarge {
                input: true,
                bytes: 1001 + 65536 + 1
            })
        );
    }

    proptest::proptest! {
        /// Objects and statuses never overlap and stay inside the C_SDU.
        #[test]
        fn no_overlaps(lens in proptest::collection::vec((0u16..64, 0u16..64), 0..20)) {
            let subs: Vec<SubmoduleIo> = lens.iter().enumerate().map(|(i, &(a, b))| sub(1 + i as u16, 1, a, b)).collect();
            let l = IocrLayout::new(&subs).unwrap();
            for cr in [&l.input, &l.output] {
                let mut used = vec![false; cr.data_length as usize];
                let mut mark = |from: u16, n: u16| {
                    for b in from..from + n {
                        proptest::prop_assert!(!used[b as usize], "byte {} used twice", b);
                        used[b as usize] = true;
                    }
                    Ok(())
                };
                for o in &cr.objects {
                    mark(o.data_offset, o.length)?;
                    mark(o.iops_offset, 1)?;
                }
                for c in &cr.iocs {
                    mark(c.offset, 1)?;
                }
            }
        }
    }
}
