// SPDX-License-Identifier: MIT OR Apache-2.0
//! IO-Base style access by logical address, unbuffered and buffered.

use crate::access::{Space, resolve_read, resolve_write};
use crate::cache::ReadCache;
use crate::client::Client;
use crate::error::IoError;
use crate::status::{Ioxs, SubmoduleIoxs, read_status};
use procimg_shm_layout::{
    CLIENT_SET_INPUT_IOCS, CLIENT_SET_OUTPUT_IOPS, CLIENT_WROTE_OUTPUTS, SubmoduleEntry,
};

/// The result of a read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadResult {
    /// IO-Base's `*pDataLen`: the bytes from the address to the end of the submodule (the
    /// buffer length needed to read them all); `min(len, buffer)` bytes were copied.
    pub len: usize,
    /// The remote status (the device's IOPS) of the data read.
    pub remote: Ioxs,
}

/// The result of reading outputs back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputReadResult {
    /// As [`ReadResult::len`].
    pub len: usize,
    /// The local status (IOPS) the outputs were sent with.
    pub local: Ioxs,
    /// The remote status (the device's IOCS).
    pub remote: Ioxs,
}

/// Marks submodule `e` in an output-sample payload: its data (whole) and statuses.
pub(crate) fn stamp(
    payload: &mut [u8],
    e: &SubmoduleEntry,
    data: Option<&[u8]>,
    output_iops: Option<Ioxs>,
    input_iocs: Option<Ioxs>,
) {
    let cs = e.client_status_offset as usize;
    let mut flags = payload.get(cs + 2).copied().unwrap_or(0);
    if let Some(d) = data {
        let at = e.output_offset as usize;
        if let Some(dst) = payload.get_mut(at..at + d.len()) {
            dst.copy_from_slice(d);
            flags |= CLIENT_WROTE_OUTPUTS;
        }
    }
    if let Some(st) = payload.get_mut(cs..cs + 4) {
        if let Some(iops) = output_iops {
            st[0] = iops.byte();
            flags |= CLIENT_SET_OUTPUT_IOPS;
        }
        if let Some(iocs) = input_iocs {
            st[1] = iocs.byte();
            flags |= CLIENT_SET_INPUT_IOCS;
        }
        st[2] = flags;
    }
}

/// Copies a read of `buf.len()` bytes at `address` from an input-image payload.
pub(crate) fn read_inputs(
    client: &Client,
    payload: &[u8],
    address: u32,
    buf: &mut [u8],
) -> Result<(ReadResult, usize), IoError> {
    let r = resolve_read(
        &client.layout.submodules,
        Space::Input,
        address,
        buf.len(),
        client.opts.slice_access,
    )?;
    let e = &client.layout.submodules[r.submodule];
    let at = e.input_offset as usize + r.offset;
    if let Some(src) = payload.get(at..at + r.len) {
        buf[..r.len].copy_from_slice(src);
    }
    Ok((
        ReadResult {
            len: r.data_len,
            remote: read_status(payload, e).input_remote,
        },
        r.submodule,
    ))
}

impl Client {
    fn no_image(&self) -> IoError {
        IoError::NoImage {
            instance: self.instance().to_string(),
        }
    }

    /// The newest input-image payload, refreshed.
    pub(crate) fn newest_payload(&mut self) -> Result<&[u8], IoError> {
        self.ensure_fresh()?;
        match &self.latest {
            Some(s) => Ok(s.payload()),
            None => Err(self.no_image()),
        }
    }

    /// All input data of the newest image (the I area), in place in shared memory, taking a
    /// newer image first; for asynchronous access without copying (the C header's
    /// `procimg_inputs`). Valid until the next call that takes a newer image.
    pub fn newest_inputs(&mut self) -> Result<&[u8], IoError> {
        let n = self.layout.header.input_size as usize;
        Ok(self.newest_payload()?.get(..n).unwrap_or(&[]))
    }

    /// The newest image as one: its inputs, the outputs as sent and the status bytes of every
    /// submodule from the same cycle, taking a newer image first. For a reader that publishes
    /// the whole image (an OPC UA server): calls of [`Client::newest_input`] and the like may
    /// each take a newer image.
    pub fn newest_image(&mut self) -> Result<ImageView<'_>, IoError> {
        self.ensure_fresh()?;
        let Some(sample) = &self.latest else {
            return Err(self.no_image());
        };
        Ok(ImageView {
            layout: &self.layout,
            payload: sample.payload(),
            cycle: sample.user_header().cycle,
        })
    }

    /// The inputs of submodule `s` in the newest image, in place, taking a newer image first;
    /// `None` when `s` is not in the layout.
    pub fn newest_input(&mut self, s: usize) -> Result<Option<&[u8]>, IoError> {
        let Some(e) = self.layout.submodules.get(s).copied() else {
            return Ok(None);
        };
        let at = e.input_offset as usize;
        Ok(self.newest_payload()?.get(at..at + e.input_length as usize))
    }

    /// The status bytes of submodule `s` in the newest image, taking a newer image first;
    /// `None` when `s` is not in the layout.
    pub fn newest_status(&mut self, s: usize) -> Result<Option<SubmoduleIoxs>, IoError> {
        let Some(e) = self.layout.submodules.get(s).copied() else {
            return Ok(None);
        };
        Ok(Some(read_status(self.newest_payload()?, &e)))
    }

    /// Reads inputs at a logical address (IO-Base `PNIO_data_read`), from the newest image.
    /// `local` is the local status (IOCS) to send for these inputs.
    pub fn data_read(
        &mut self,
        address: u32,
        buf: &mut [u8],
        local: Ioxs,
    ) -> Result<ReadResult, IoError> {
        self.ensure_fresh()?;
        let payload = match &self.latest {
            Some(s) => s.payload(),
            None => return Err(self.no_image()),
        };
        let (res, s) = read_inputs(self, payload, address, buf)?;
        if self.local_input_iocs[s] != local {
            // Rare: this client changes the local status it asks for. Send it on its own so it
            // reaches the device in the next cycle, as IO-Base specifies; only on a change, so
            // reading never turns into a stream of samples.
            self.local_input_iocs[s] = local;
            self.write_cache.input_iocs[s] = Some(local);
            self.flush_submodules(&[])?;
        }
        Ok(res)
    }

    /// Reads back outputs at a logical address (IO-Base `PNIO_output_data_read`): the
    /// outputs as last sent, with their local and remote status.
    pub fn output_data_read(
        &mut self,
        address: u32,
        buf: &mut [u8],
    ) -> Result<OutputReadResult, IoError> {
        let slice = self.opts.slice_access;
        let r = resolve_read(
            &self.layout.submodules,
            Space::Output,
            address,
            buf.len(),
            slice,
        )?;
        let e = self.layout.submodules[r.submodule];
        let payload = self.newest_payload()?;
        let at = e.output_mirror_offset as usize + r.offset;
        if let Some(src) = payload.get(at..at + r.len) {
            buf[..r.len].copy_from_slice(src);
        }
        let st = read_status(payload, &e);
        Ok(OutputReadResult {
            len: r.data_len,
            local: st.output_local,
            remote: st.output_remote,
        })
    }

    /// Writes outputs at a logical address (IO-Base `PNIO_data_write`). The write is applied
    /// whole in one cycle. Returns the remote status (the device's IOCS), which refers to the
    /// outputs of the previous cycle.
    pub fn data_write(&mut self, address: u32, data: &[u8], local: Ioxs) -> Result<Ioxs, IoError> {
        let s = self.write_to_cache(address, data, local)?;
        self.flush_submodules(&[s])?;
        self.ensure_fresh()?;
        Ok(self.output_remote(s))
    }

    /// Copies the whole input image into the read cache (IO-Base
    /// `PNIO_data_read_cache_refresh`).
    pub fn data_read_cache_refresh(&mut self) -> Result<(), IoError> {
        let payload = self.newest_payload()?.to_vec();
        self.read_cache = Some(ReadCache { payload });
        Ok(())
    }

    /// Reads inputs from the read cache (IO-Base `PNIO_data_read_cache`); `local` goes into
    /// the write cache and is sent by the next flush.
    pub fn data_read_cache(
        &mut self,
        address: u32,
        buf: &mut [u8],
        local: Ioxs,
    ) -> Result<ReadResult, IoError> {
        let cache = self.read_cache.take().ok_or_else(|| self.no_image())?;
        let result = read_inputs(self, &cache.payload, address, buf);
        self.read_cache = Some(cache);
        let (res, s) = result?;
        if self.local_input_iocs[s] != local {
            self.local_input_iocs[s] = local;
            self.write_cache.input_iocs[s] = Some(local);
        }
        Ok(res)
    }

    /// Writes outputs into the write cache (IO-Base `PNIO_data_write_cache`); they go out
    /// with the next flush. Returns the remote status from the read cache.
    pub fn data_write_cache(
        &mut self,
        address: u32,
        data: &[u8],
        local: Ioxs,
    ) -> Result<Ioxs, IoError> {
        let s = self.write_to_cache(address, data, local)?;
        let e = self.layout.submodules[s];
        Ok(self
            .read_cache
            .as_ref()
            .map_or(Ioxs::Bad, |c| read_status(&c.payload, &e).output_remote))
    }

    /// Whether the newest image holds what this client last sent of each submodule it wrote
    /// since it attached: the same bytes and IOPS. Then the server has applied the writes,
    /// and its frames carry them: a device program that wrote the I data the PLC is to get
    /// with the ApplicationReady asks this before it lets the ApplicationReady go (IO-Base's
    /// order: `PNIO_initiate_data_write`, then `PNIO_set_appl_state_ready`). Written into
    /// the cache and not flushed counts as not applied.
    pub fn outputs_applied(&mut self) -> Result<bool, IoError> {
        self.ensure_fresh()?;
        let Some(latest) = &self.latest else {
            return Ok(false);
        };
        let payload = latest.payload();
        let cache = &self.write_cache;
        Ok(self
            .layout
            .submodules
            .iter()
            .enumerate()
            .filter(|&(s, _)| cache.valid[s])
            .all(|(s, e)| {
                let (at, len) = (e.output_offset as usize, e.output_length as usize);
                let mirror = e.output_mirror_offset as usize;
                !cache.dirty[s]
                    && payload.get(mirror..mirror + len) == cache.data.get(at..at + len)
                    && read_status(payload, e).output_local == cache.output_iops[s]
            }))
    }

    /// Waits until [`outputs_applied`](Self::outputs_applied) says yes, at most `timeout`
    /// (a few cycles are plenty); whether it did.
    pub fn wait_outputs_applied(&mut self, timeout: std::time::Duration) -> Result<bool, IoError> {
        let until = std::time::Instant::now() + timeout;
        loop {
            if self.outputs_applied()? {
                return Ok(true);
            }
            if std::time::Instant::now() >= until {
                return Ok(false);
            }
            // A fraction of the shortest cycle procimgd runs: the answer comes with the
            // next image.
            std::thread::sleep(std::time::Duration::from_micros(250));
        }
    }

    /// Sends everything in the write cache in one sample, applied in one cycle (IO-Base
    /// `PNIO_data_write_cache_flush`).
    pub fn data_write_cache_flush(&mut self) -> Result<(), IoError> {
        let dirty: Vec<usize> = (0..self.write_cache.dirty.len())
            .filter(|&s| self.write_cache.dirty[s])
            .collect();
        if dirty.is_empty() && !self.write_cache.pending() {
            return Ok(());
        }
        self.flush_submodules(&dirty)
    }

    fn output_remote(&self, s: usize) -> Ioxs {
        let e = &self.layout.submodules[s];
        self.latest
            .as_ref()
            .map_or(Ioxs::Bad, |l| read_status(l.payload(), e).output_remote)
    }

    /// Applies a write to the cache (checking address, length and claim); returns the
    /// submodule.
    fn write_to_cache(&mut self, address: u32, data: &[u8], local: Ioxs) -> Result<usize, IoError> {
        let r = resolve_write(
            &self.layout.submodules,
            address,
            data.len(),
            self.opts.slice_access,
        )?;
        if !self.holds(r.submodule) {
            return Err(IoError::NotClaimed {
                submodule: r.submodule,
                address,
            });
        }
        let e = self.layout.submodules[r.submodule];
        let at = e.output_offset as usize;
        let len = e.output_length as usize;
        if !self.write_cache.valid[r.submodule] {
            // Start from the outputs as last sent, so a partial write keeps the other bytes.
            self.ensure_fresh()?;
            let mirror_at = e.output_mirror_offset as usize;
            let mirror = self.latest.as_ref().and_then(|l| {
                l.payload()
                    .get(mirror_at..mirror_at + len)
                    .map(<[u8]>::to_vec)
            });
            if let Some(m) = mirror {
                self.write_cache.data[at..at + len].copy_from_slice(&m);
            }
            self.write_cache.valid[r.submodule] = true;
        }
        self.write_cache.data[at + r.offset..at + r.offset + r.len].copy_from_slice(data);
        self.write_cache.dirty[r.submodule] = true;
        self.write_cache.output_iops[r.submodule] = local;
        Ok(r.submodule)
    }

    /// Sends the given submodules from the write cache, with every pending local input
    /// status, in one sample.
    fn flush_submodules(&mut self, submodules: &[usize]) -> Result<(), IoError> {
        let mut sample = self.loan_output()?;
        let payload = sample.payload_mut();
        for &s in submodules {
            let e = self.layout.submodules[s];
            let at = e.output_offset as usize;
            let data = &self.write_cache.data[at..at + e.output_length as usize];
            stamp(
                payload,
                &e,
                Some(data),
                Some(self.write_cache.output_iops[s]),
                None,
            );
        }
        for (s, iocs) in self.write_cache.input_iocs.iter().enumerate() {
            if iocs.is_some() {
                stamp(payload, &self.layout.submodules[s], None, None, *iocs);
            }
        }
        self.send_output(sample, None)?;
        for &s in submodules {
            self.write_cache.dirty[s] = false;
        }
        self.write_cache
            .input_iocs
            .iter_mut()
            .for_each(|v| *v = None);
        Ok(())
    }
}

/// One image of the server, whole: see [`Client::newest_image`].
pub struct ImageView<'a> {
    layout: &'a crate::Layout,
    payload: &'a [u8],
    cycle: procimg_shm_layout::CycleInfo,
}

impl ImageView<'_> {
    /// The layout the image is laid out by: the client's, which changes when the client
    /// attaches again to a procimgd with another layout.
    pub fn layout(&self) -> &crate::Layout {
        self.layout
    }

    /// The cycle the image is of.
    pub fn cycle(&self) -> procimg_shm_layout::CycleInfo {
        self.cycle
    }

    /// The inputs of submodule `s`; `None` when `s` is not in the layout.
    pub fn input(&self, s: usize) -> Option<&[u8]> {
        let e = self.layout.submodules.get(s)?;
        let at = e.input_offset as usize;
        self.payload.get(at..at + e.input_length as usize)
    }

    /// The outputs of submodule `s` as they went out.
    pub fn outputs_sent(&self, s: usize) -> Option<&[u8]> {
        let e = self.layout.submodules.get(s)?;
        let at = e.output_mirror_offset as usize;
        self.payload.get(at..at + e.output_length as usize)
    }

    /// The status bytes of submodule `s`.
    pub fn status(&self, s: usize) -> Option<SubmoduleIoxs> {
        let e = self.layout.submodules.get(s)?;
        Some(read_status(self.payload, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_shm_layout::{IOXS_BAD_BY_CONTROLLER, IOXS_GOOD};

    fn entry() -> SubmoduleEntry {
        SubmoduleEntry {
            output_offset: 2,
            output_length: 3,
            client_status_offset: 8,
            ..SubmoduleEntry::EMPTY
        }
    }

    #[test]
    fn a_stamp_writes_what_it_is_given_and_says_so_in_the_flags() {
        let e = entry();
        let mut p = [0u8; 12];
        stamp(&mut p, &e, Some(&[1, 2, 3]), None, None);
        assert_eq!(&p[2..5], &[1, 2, 3]);
        assert_eq!(p[8 + 2], CLIENT_WROTE_OUTPUTS);
        // Statuses later: the data flag stays, the statuses' bytes and flags are added.
        stamp(&mut p, &e, None, Some(Ioxs::Bad), Some(Ioxs::Good));
        assert_eq!(&p[8..10], &[IOXS_BAD_BY_CONTROLLER, IOXS_GOOD]);
        assert_eq!(
            p[8 + 2],
            CLIENT_WROTE_OUTPUTS | CLIENT_SET_OUTPUT_IOPS | CLIENT_SET_INPUT_IOCS
        );
    }

    #[test]
    fn a_stamp_outside_the_payload_writes_nothing() {
        let e = entry();
        let mut p = [0u8; 4];
        stamp(&mut p, &e, Some(&[1, 2, 3]), Some(Ioxs::Good), None);
        assert_eq!(p, [0; 4]);
    }
}
