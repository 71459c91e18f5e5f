// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller services behind the IO-Base API: record jobs, alarms, device activation and
//! diagnosis, delivered to the program's callbacks on a thread of their own.
