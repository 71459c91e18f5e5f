// SPDX-License-Identifier: MIT OR Apache-2.0
//! The iceoryx2 configuration every procimg node uses.

use iceoryx2::config::Config;
use iceoryx2::prelude::{FileName, SemanticString};
use std::sync::OnceLock;

/// iceoryx2's configuration with procimg's file prefix; built once.
pub fn iox2_config() -> &'static Config {
    static CONFIG: OnceLock<Config> = OnceLock::new();
    CONFIG.get_or_init(|| {
        let mut c = Config::default();
        if let Ok(prefix) = FileName::new(procimg_shm_layout::share::IOX2_PREFIX.as_bytes()) {
            c.global.prefix = prefix;
        }
        if let Ok(path) =
            iceoryx2::prelude::Path::new(procimg_shm_layout::share::iceoryx2_directory().as_bytes())
        {
            c.global.set_root_path(&path);
        }
        c
    })
}
