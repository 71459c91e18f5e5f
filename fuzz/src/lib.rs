// SPDX-License-Identifier: MIT OR Apache-2.0
//! Helpers shared by the fuzz targets in `fuzz_targets/` and by the `seed_corpus` program:
//! the byte format of the targets that take a sequence of operations ([`ops`]), checks that
//! what our own code puts on the wire parses again ([`wire_check`]), the simulated network the
//! controller and device targets run on ([`world`]), and the captured frames the seeds are cut
//! from ([`captures`]).

pub mod captures;
pub mod ops;
pub mod wire_check;
pub mod world;
