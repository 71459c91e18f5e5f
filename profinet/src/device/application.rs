// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's application, as the protocol engine sees it: what goes into its inputs.

/// What a device's program does with its IO data. The engine calls it once per submodule for
/// every input frame it produces; what the program does with the outputs it received is up to
/// it (they are handed over here as well). procimgd's demo behaviours (echo, counter, digital
/// IO) are one implementation.
pub trait Application {
    /// Fills one submodule's `inputs` for the `k`-th produced frame.
    ///
    /// `own_outputs` are the outputs this submodule last received (empty if it has none, zeros
    /// where they were invalid), `device_outputs` those of the whole device concatenated in
    /// submodule order, and `last` says whether this is the device's last submodule with
    /// inputs. Called on the device's cyclic path: it should not allocate.
    fn fill_inputs(
        &mut self,
        k: u64,
        inputs: &mut [u8],
        own_outputs: &[u8],
        device_outputs: &[u8],
        last: bool,
    );
}
