// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base compatible controller API (`pniousrx.h`, `pniobase.h`, `pnioerrx.h`), and the
//! types of the device API (`pniousrd.h`).
//!
//! * [`types`] and [`errors`]: the C types and return codes, with the manual's names.
//! * [`device_types`]: the C types, callback types and function prototypes of the device
//!   API; `device_api` exports its management, configuration, AR and IO data functions,
//!   `device_alarm_api` its diagnosis and alarm functions, and `device` is the open device
//!   behind them.
//! * `api`: the exported `PNIO_*` functions; `controller`: an open controller, its mode
//!   and its threads; `data`: the IO data functions; `callbacks`: the callback table and
//!   the one place that calls the program back; `services`: records, alarms, device
//!   activation and diagnosis.
//! * `isochronous`: the STARTOP..OPDONE handshake and the registration rules both roles
//!   share; `cycle_thread`: the thread that calls the isochronous callbacks, for both;
//!   `io_failure`: the codes of a failed IO data access, for both; `handles`: the one
//!   handle counter of both; [`watchdog`]: the CP application watchdog of both.
//! * [`interface_api`] and [`interface_types`]: the controller's own interface (PN
//!   Driver's `PNIO_interface_*`), its events delivered by `interface_worker`.
//! * [`pn_driver`] and [`pn_driver_types`]: PN Driver's start-up (`servusrx.h`), a procimgd
//!   started as the program's stack; [`cp_services`]: the CP service functions of chapter 8
//!   that procimg has.

pub mod api;
pub(crate) mod callbacks;
mod controller;
pub mod cp_info;
pub mod cp_services;
mod cycle_thread;
mod data;
pub(crate) mod device;
pub mod device_alarm_api;
pub mod device_api;
pub mod device_types;
mod devices_up;
pub mod errors;
mod handles;
pub mod interface_api;
pub mod interface_types;
mod interface_worker;
mod io_failure;
mod isochronous;
pub mod pe_api;
pub mod pe_types;
pub mod pn_driver;
pub mod pn_driver_types;
pub(crate) mod rema;
pub(crate) mod services;
pub(crate) mod stopped;
pub(crate) mod sync;
pub mod types;
mod wake;
pub(crate) mod wake_ahead_env;
pub mod watchdog;
