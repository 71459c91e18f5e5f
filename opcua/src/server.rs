// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server put together: the endpoint, its security policies, the PKI folder with the
//! certificate made at first start, the two node managers (the browsable tree and the PNIO
//! item names), and limits that let subscriptions sample at the image's pace.

use crate::auth::Sessions;
use crate::pnio_nodes::{PnioItems, PnioItemsBuilder};
use crate::records::Job;
use crate::snapshot::Snapshot;
use crate::tree::Tree;
use crate::users::Users;
use crate::writer::Write;
use opcua::crypto::SecurityPolicy;
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::{SimpleNodeManager, simple_node_manager};
use opcua::server::{ANONYMOUS_USER_TOKEN_ID, Server, ServerBuilder, ServerEndpoint, ServerHandle};
use opcua::types::MessageSecurityMode;
use std::path::PathBuf;
use std::sync::{Arc, mpsc};
use std::time::Duration;
use tokio::sync::watch;

/// Where and how the server listens.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Endpoint {
    /// The host clients reach it by (and it listens on).
    pub host: String,
    /// The TCP port.
    pub port: u16,
}

impl Endpoint {
    /// `opc.tcp://HOST:PORT` (a path after it is not served).
    pub fn parse(url: &str) -> Result<Endpoint, String> {
        let rest = url
            .strip_prefix("opc.tcp://")
            .ok_or_else(|| format!("{url:?} is no opc.tcp:// URL: give opc.tcp://HOST:PORT"))?;
        let rest = rest.trim_end_matches('/');
        let (host, port) = rest.rsplit_once(':').ok_or_else(|| {
            format!("{url:?} has no port: give opc.tcp://HOST:PORT, e.g. opc.tcp://0.0.0.0:4840")
        })?;
        let port = port
            .parse::<u16>()
            .map_err(|_| format!("{url:?}: the port {port:?} is not a number from 0 to 65535"))?;
        if host.is_empty() || host.contains('/') {
            return Err(format!("{url:?}: no host before the port"));
        }
        Ok(Endpoint {
            host: host
                .trim_start_matches('[')
                .trim_end_matches(']')
                .to_owned(),
            port,
        })
    }

    /// The URL clients use.
    pub fn url(&self) -> String {
        if self.host.contains(':') {
            format!("opc.tcp://[{}]:{}/", self.host, self.port)
        } else {
            format!("opc.tcp://{}:{}/", self.host, self.port)
        }
    }
}

/// What the server serves and how.
pub struct Options {
    /// The instance of procimgd.
    pub instance: String,
    /// Its CpIndex, the `n` of `PNIO:[CTRL<n>]`.
    pub controller: u8,
    /// Where it listens.
    pub endpoint: Endpoint,
    /// The PKI folder: `own/cert.der`, `private/private.pem`, `trusted/`, `rejected/`.
    pub pki: PathBuf,
    /// Offer the endpoint without security (policy None) as well.
    pub insecure: bool,
    /// The image's cycle time: the shortest sampling interval.
    pub cycle: Duration,
    /// The users (none: anonymous sessions only, which read).
    pub users: Arc<Users>,
    /// The image feed's pace, which the monitored items set.
    pub pace: Arc<crate::snapshot::Pace>,
    /// The GSDML files that type the submodules' data.
    pub catalog: Arc<crate::typed::Catalog>,
}

/// The server, its handle, and what publishes the image into it.
pub struct Assembled {
    /// Run it.
    pub server: Server,
    /// Stop it, reach its subscriptions.
    pub handle: ServerHandle,
    /// The browsable tree's node manager.
    pub tree_nodes: Arc<SimpleNodeManager>,
    /// The browsable tree.
    pub tree: Tree,
    /// The PNIO item names.
    pub items: Arc<PnioItems>,
    /// The tree's namespace index.
    pub tree_namespace: u16,
    /// The event types' namespace index.
    pub types_namespace: u16,
}

/// The server's private key, made at first start, readable by its owner only.
fn keep_key_private(pki: &std::path::Path) {
    use std::os::unix::fs::PermissionsExt;
    let key = pki.join("private/private.pem");
    if key.exists()
        && let Err(e) = std::fs::set_permissions(&key, std::fs::Permissions::from_mode(0o600))
    {
        tracing::warn!(
            "cannot make {} readable by its owner only: {e}",
            key.display()
        );
    }
}

/// The shortest publishing interval, in ms, and the subscriptions' tick: a cycle, at least
/// 10 ms (a client that wants each image sets a queue, not a faster publication).
fn publishing_tick_ms(cycle: Duration) -> u64 {
    (cycle.as_millis() as u64).clamp(10, 100)
}

/// The browsable tree's namespace URI for `instance`.
pub fn tree_namespace(instance: &str) -> String {
    format!("urn:procimg:{instance}")
}

/// Builds the server, fed by `snapshots` (its tree made for the layout of the one there).
pub fn assemble(
    o: &Options,
    snapshots: watch::Receiver<Arc<Snapshot>>,
    writer: mpsc::Sender<Write>,
    records: mpsc::Sender<Job>,
) -> Result<Assembled, String> {
    let users = [ANONYMOUS_USER_TOKEN_ID.to_owned()];
    let mut builder = ServerBuilder::new()
        .application_name(format!("procimg-opcua {}", o.instance))
        .application_uri(format!("urn:procimg:opcua:{}", o.instance))
        .product_uri("urn:procimg")
        .host(o.endpoint.host.clone())
        .port(o.endpoint.port)
        .discovery_urls(vec![o.endpoint.url()])
        .pki_dir(o.pki.clone())
        .create_sample_keypair(true)
        .with_authenticator(Arc::new(Sessions::new(o.users.clone())))
        .add_endpoint(
            "basic256sha256-sign",
            ServerEndpoint::new(
                "/",
                SecurityPolicy::Basic256Sha256,
                MessageSecurityMode::Sign,
                &users,
            ),
        )
        .add_endpoint(
            "basic256sha256-sign-encrypt",
            ServerEndpoint::new(
                "/",
                SecurityPolicy::Basic256Sha256,
                MessageSecurityMode::SignAndEncrypt,
                &users,
            ),
        )
        .add_endpoint(
            "aes128-sign-encrypt",
            ServerEndpoint::new(
                "/",
                SecurityPolicy::Aes128Sha256RsaOaep,
                MessageSecurityMode::SignAndEncrypt,
                &users,
            ),
        )
        .add_endpoint(
            "aes256-sign-encrypt",
            ServerEndpoint::new(
                "/",
                SecurityPolicy::Aes256Sha256RsaPss,
                MessageSecurityMode::SignAndEncrypt,
                &users,
            ),
        )
        // The subscriptions' tick is the shortest publishing interval: samples down to the
        // cycle reach the subscriptions as the images come (the items' node manager pushes
        // them); a tick of each cycle would wake the server 1000 times a second for nothing.
        .subscription_poll_interval_ms(publishing_tick_ms(o.cycle))
        .with_node_manager(simple_node_manager(
            NamespaceMetadata {
                namespace_uri: tree_namespace(&o.instance),
                ..Default::default()
            },
            "procimg-tree",
        ))
        .with_node_manager(simple_node_manager(
            NamespaceMetadata {
                namespace_uri: crate::event_types::TYPES_NAMESPACE.to_owned(),
                ..Default::default()
            },
            "procimg-types",
        ))
        .with_node_manager(PnioItemsBuilder {
            controller: o.controller,
            snapshots: snapshots.clone(),
            users: o.users.clone(),
            writer,
            records: records.clone(),
            pace: o.pace.clone(),
        });
    if o.insecure {
        builder = builder.add_endpoint("none", ServerEndpoint::new_none("/", &users));
    }
    let cycle_ms = (o.cycle.as_secs_f64() * 1e3).max(1.0);
    let limits = builder.limits_mut();
    limits.subscriptions.min_sampling_interval_ms = cycle_ms;
    limits.subscriptions.min_publishing_interval_ms = publishing_tick_ms(o.cycle) as f64;
    // Plants monitor thousands of items: no cap per subscription, a generous one per call.
    limits.subscriptions.max_monitored_items_per_sub = 0;
    limits.subscriptions.max_monitored_item_queue_size = 100;
    limits.operational.max_monitored_items_per_call = 10_000;
    let (server, handle) = builder.build()?;
    keep_key_private(&o.pki);
    let tree_nodes = handle
        .node_managers()
        .get_by_name::<SimpleNodeManager>("procimg-tree")
        .ok_or("the tree's node manager is missing")?;
    let types = handle
        .get_namespace_index(crate::event_types::TYPES_NAMESPACE)
        .ok_or("the event types' namespace is missing")?;
    {
        let type_nodes = handle
            .node_managers()
            .get_by_name::<SimpleNodeManager>("procimg-types")
            .ok_or("the event types' node manager is missing")?;
        let mut space = type_nodes.address_space().write();
        crate::event_types::add(&mut space, &mut handle.type_tree().write(), types);
    }
    let items = handle
        .node_managers()
        .get_of_type::<PnioItems>()
        .ok_or("the PNIO items' node manager is missing")?;
    let ns = handle
        .get_namespace_index(&tree_namespace(&o.instance))
        .ok_or("the tree's namespace is missing")?;
    let layout = snapshots.borrow().layout.clone();
    let tree = Tree::build(
        &tree_nodes,
        ns,
        (&o.instance, o.controller),
        o.catalog.clone(),
        &layout,
    );
    crate::methods::add(&tree_nodes, ns, &o.instance, snapshots, records);
    Ok(Assembled {
        server,
        handle,
        tree_nodes,
        tree,
        items,
        tree_namespace: ns,
        types_namespace: types,
    })
}

#[cfg(test)]
mod tests {
    use super::Endpoint;

    #[test]
    fn endpoints_read_as_opc_tcp_urls() {
        let e = Endpoint::parse("opc.tcp://0.0.0.0:4840").unwrap();
        assert_eq!((e.host.as_str(), e.port), ("0.0.0.0", 4840));
        assert_eq!(e.url(), "opc.tcp://0.0.0.0:4840/");
        let v6 = Endpoint::parse("opc.tcp://[::1]:4841/").unwrap();
        assert_eq!(
            (v6.host.as_str(), v6.url()),
            ("::1", "opc.tcp://[::1]:4841/".to_owned())
        );
        for bad in [
            "http://x:1",
            "opc.tcp://x",
            "opc.tcp://x:70000",
            "opc.tcp://:4840",
        ] {
            assert!(Endpoint::parse(bad).is_err(), "{bad}");
        }
    }
}
