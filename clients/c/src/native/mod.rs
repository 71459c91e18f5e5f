// SPDX-License-Identifier: MIT OR Apache-2.0
//! The native C API (`include/procimg.h`).
