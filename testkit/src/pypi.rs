// SPDX-License-Identifier: MIT OR Apache-2.0
//! The independent peers that come from PyPI (profinet-py, asyncua), each in a virtual
//! environment of its own that CI makes.

use std::path::PathBuf;

/// The Python interpreter of the virtual environment holding `package` (`name==version`):
/// the one environment variable `env` names, by default `target/<venv>/bin/python`, which CI
/// makes with `python3 -m venv target/<venv> && target/<venv>/bin/pip install <package>`.
/// Panics, saying how to make it, when there is none.
pub fn venv_python(env: &str, venv: &str, package: &str) -> PathBuf {
    let python = std::env::var_os(env).map_or_else(
        || crate::workspace_dir().join(format!("target/{venv}/bin/python")),
        PathBuf::from,
    );
    assert!(
        python.exists(),
        "no {package} interpreter at {}: python3 -m venv target/{venv} && \
         target/{venv}/bin/pip install {package} (or set {env})",
        python.display()
    );
    python
}
