// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd's configuration on this machine: the `network` interface is checked against the
//! interfaces the machine has (the check `procimg-nic` gives `procimg_config::load`), and the
//! message names the file, line and key, and the interfaces there are. The configuration's
//! own tests are the configuration crate's (`config/tests/`).

use procimg_nic::interfaces;
use procimg_runtime::config::{self, Network};

#[test]
fn load_checks_the_network_interface_on_this_machine() {
    let dir = std::env::temp_dir().join(format!("procimg-config-net-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("plant.toml");
    let text = "cycle_time = \"1ms\"\nnetwork = \"nosuchif0\"\n";
    std::fs::write(&path, text).unwrap();
    let e = config::load(&path, &interfaces::check).unwrap_err();
    let shown = e.to_string();
    assert_eq!((e.line(), e.key()), (Some(2), Some("network")), "{shown}");
    assert!(
        shown.starts_with(&format!("{}:2: network: ", path.display())),
        "{shown}"
    );
    assert!(shown.contains("\"nosuchif0\" does not exist"), "{shown}");
    // Every network namespace has its loopback interface: the list names it.
    assert!(shown.contains("lo"), "{shown}");
    assert!(shown.contains("\"sim\""), "{shown}");
    // An interface that exists passes; parsing text alone does not look at the machine.
    std::fs::write(&path, "network = \"lo\"\n").unwrap();
    assert_eq!(
        config::load(&path, &interfaces::check).unwrap().network,
        Network::Interface("lo".into())
    );
    assert_eq!(
        config::parse("network = \"nosuchif0\"", "plant.toml")
            .unwrap()
            .network,
        Network::Interface("nosuchif0".into())
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
