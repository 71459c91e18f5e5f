// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base compatible controller API (`pniousrx.h`, `pniobase.h`, `pnioerrx.h`).

pub(crate) mod services;
