// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base compatible controller API (`pniousrx.h`, `pniobase.h`, `pnioerrx.h`).
//!
//! * [`types`] and [`errors`]: the C types and return codes, with the manual's names.
//! * `api`: the exported `PNIO_*` functions; `controller`: an open controller, its mode
//!   and its threads; `data`: the IO data functions; `callbacks`: the callback table and
//!   the one place that calls the program back; `services`: records, alarms, device
//!   activation and diagnosis.

pub mod api;
pub(crate) mod callbacks;
mod controller;
mod data;
pub mod errors;
pub(crate) mod services;
pub mod types;
