// SPDX-License-Identifier: MIT OR Apache-2.0
//! Forced bytes, as the cycle thread applies them: a plan built off the real-time path (see
//! `server::force`) and handed over whole through [`Shared`](super::Shared), so that applying
//! it is a few copies and taking a new one is a pointer swap. The cycle thread never frees a
//! plan: the one it replaces goes back to the acyclic side, which drops it.

use crate::image::Image;
use procimg_control::Space;

/// Consecutive forced bytes inside one submodule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ForceRun {
    /// I (inputs as clients see them) or Q (outputs as they are sent).
    pub space: Space,
    /// Submodule table index.
    pub submodule: u32,
    /// First byte inside the submodule's data.
    pub offset: u32,
    /// Where the values start in `ForcePlan::values`.
    pub value_at: u32,
    /// Bytes.
    pub len: u32,
}

/// Everything forced, ready to apply.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ForcePlan {
    runs: Vec<ForceRun>,
    values: Vec<u8>,
    /// Per submodule: some of its outputs are forced (they go out GOOD in OPERATE).
    forced_outputs: Vec<bool>,
}

impl ForcePlan {
    /// A plan that forces nothing, for `submodules` submodules.
    pub fn empty(submodules: usize) -> ForcePlan {
        ForcePlan {
            runs: Vec::new(),
            values: Vec::new(),
            forced_outputs: vec![false; submodules],
        }
    }

    /// Adds a run of `values` at `offset` in submodule `submodule`.
    pub fn push(&mut self, space: Space, submodule: u32, offset: u32, values: &[u8]) {
        self.runs.push(ForceRun {
            space,
            submodule,
            offset,
            value_at: self.values.len() as u32,
            len: values.len() as u32,
        });
        self.values.extend_from_slice(values);
        if space == Space::Output
            && let Some(f) = self.forced_outputs.get_mut(submodule as usize)
        {
            *f = true;
        }
    }

    /// Whether nothing is forced.
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// The runs, in the order they were added.
    pub fn runs(&self) -> &[ForceRun] {
        &self.runs
    }

    /// Whether some outputs of submodule `s` are forced.
    pub fn forces_outputs_of(&self, s: usize) -> bool {
        self.forced_outputs.get(s).copied().unwrap_or(false)
    }

    /// Puts the forced values of `space` into the image. Runs that do not fit the image (a
    /// plan made for another layout) are skipped.
    pub fn apply(&self, space: Space, image: &mut Image) {
        for r in self.runs.iter().filter(|r| r.space == space) {
            let s = r.submodule as usize;
            if s >= image.submodules().len() {
                continue;
            }
            let data = match space {
                Space::Input => image.inputs_mut(s),
                Space::Output => image.outputs_mut(s),
            };
            let (from, at) = (r.value_at as usize, r.offset as usize);
            let len = r.len as usize;
            if let (Some(dst), Some(src)) = (
                data.get_mut(at..at + len),
                self.values.get(from..from + len),
            ) {
                dst.copy_from_slice(src);
            }
        }
    }
}
